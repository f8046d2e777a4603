"""A run on N MPI ranks stopped by SIGTERM (issue 15): every rank stops at the same check, none
waits forever in a collective, summary.json says `interrupted`, and the last increment that
results.pvd lists has all its ParaView pieces on disk.
The thick cylinder with J2 plasticity is run with increments 20 times smaller (about 200), on
N ranks with MUMPS. Once summary.json lists three increments, the signal goes to the last rank
alone (mpirun would pass a signal it gets to every rank, but each rank notices it at its own
point): unless the ranks agree on it, that rank stops alone, mpirun ends the job, and rank 0,
which writes summary.json, never says `interrupted`.
Usage: interrupt_ranks.py SIGNORINI EXAMPLE_DECK RANKS WORKDIR"""
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time

from mpi_case import launcher, read_deck, write_deck

signorini, deck, ranks, work = sys.argv[1:5]
ranks = int(ranks)
os.makedirs(work, exist_ok=True)
text = read_deck(deck)
text = text.replace("increments: {initial: 0.0556, max: 0.0556}", "increments: {initial: 0.00278, max: 0.00278}")
assert "0.00278" in text, "the deck's increments line changed: update this test"
text += "\nsolver: {linear: mumps}\n"
copy = write_deck(work, text)
out = os.path.join(work, "out")
shutil.rmtree(out, ignore_errors=True)

mpirun, env = launcher()
p = subprocess.Popen([mpirun, "-np", str(ranks), signorini, "run", copy, "-q", "-o", out], env=env,
                     stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
summary = os.path.join(out, "summary.json")
start = time.time()
increments = 0
while time.time() - start < 120 and p.poll() is None:
    time.sleep(0.2)
    try:
        with open(summary) as f:
            increments = len(json.load(f)["increments"])
    except (OSError, ValueError, KeyError):
        continue
    if increments >= 3:
        break
assert p.poll() is None, "the run ended before it could be interrupted:\n" + p.communicate()[0][-3000:]
assert increments >= 3, "no 3 increments in 120 s"

def rank_of(pid):
    try:
        with open("/proc/%d/environ" % pid, "rb") as f:
            for item in f.read().split(b"\0"):
                if item.startswith(b"OMPI_COMM_WORLD_RANK="):
                    return int(item.split(b"=")[1])
    except OSError:
        pass
    return None


children = subprocess.run(["pgrep", "-P", str(p.pid)], capture_output=True, text=True).stdout.split()
last_rank = [int(c) for c in children if rank_of(int(c)) == ranks - 1]
assert len(last_rank) == 1, "rank %d not found among mpirun's children %s" % (ranks - 1, children)
os.kill(last_rank[0], signal.SIGTERM)
try:
    log, _ = p.communicate(timeout=60)
except subprocess.TimeoutExpired:
    for child in children:  # the ranks too: mpirun's SIGKILL would leave them running
        try:
            os.kill(int(child), signal.SIGKILL)
        except OSError:
            pass
    p.kill()
    sys.exit("the ranks did not stop within 60 s of SIGTERM (a rank waiting in a collective?)\n" +
             p.communicate()[0][-3000:])
with open(summary) as f:
    s = json.load(f)
assert s["status"] == "interrupted", (s["status"], log[-3000:])
assert s["mpi_ranks"] == ranks, s["mpi_ranks"]
with open(os.path.join(out, "results.pvd")) as f:
    listed = re.findall(r'file="([^"]+)"', f.read())
last = listed[-1]
assert last.endswith(".pvtu"), last
with open(os.path.join(out, last)) as f:
    pieces = re.findall(r'<Piece Source="([^"]+)"', f.read())
assert len(pieces) == ranks, pieces
for piece in pieces:
    assert os.path.getsize(os.path.join(out, piece)) > 0, piece
print("rank %d stopped by SIGTERM after %d increments on %d ranks (exit code %d): summary.json says interrupted, "
      "%d increments kept, the last (%s) with its %d pieces" % (ranks - 1, increments, ranks, p.returncode, len(s["increments"]),
                                                              last, len(pieces)))
