"""Runs a shipped example with a PETSc linear solver on 1 and on N MPI ranks and checks that
the two runs agree (issue 15): both complete, summary.json says how many ranks solved, and
every reference check of the deck gives the same computed value to `tolerance` (relative).
Usage: compare_ranks.py SIGNORINI EXAMPLE_DECK LINEAR RANKS TOLERANCE WORKDIR"""
import json
import os
import shutil
import subprocess
import sys

signorini, deck, linear, ranks, tolerance, work = sys.argv[1:7]
ranks, tolerance = int(ranks), float(tolerance)
os.makedirs(work, exist_ok=True)
with open(deck) as f:
    text = f.read()
# The mesh path relative to the deck's folder, a solver section of our own.
folder = os.path.dirname(os.path.abspath(deck))
text = text.replace("file: ", "file: " + folder + "/", 1)
text = "\n".join(line for line in text.splitlines() if not line.startswith("solver:"))
text += "\nsolver: {linear: {type: %s, rtol: 1e-10}}\n" % linear
copy = os.path.join(work, "deck.yaml")
with open(copy, "w") as f:
    f.write(text)

mpirun = shutil.which("mpirun")
if mpirun is None:
    sys.exit("mpirun not found (apt install openmpi-bin)")
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")


def run(n):
    out = os.path.join(work, "np%d" % n)
    cmd = [signorini, "run", copy, "-q", "-o", out]
    if n > 1:
        cmd = [mpirun, "-np", str(n)] + cmd
    p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
    if p.returncode != 0:
        sys.exit("np %d: exit code %d\n%s\n%s" % (n, p.returncode, p.stdout[-3000:], p.stderr[-3000:]))
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f), p.stdout


one, _ = run(1)
many, log = run(ranks)
assert one["status"] == "completed" and many["status"] == "completed", (one["status"], many["status"])
assert one["mpi_ranks"] == 1 and many["mpi_ranks"] == ranks, (one["mpi_ranks"], many["mpi_ranks"])
assert log.count("Solved") == 1, "rank 0 alone should print the summary:\n" + log
worst = 0.0
for a, b in zip(one["checks"], many["checks"]):
    assert a["name"] == b["name"]
    err = abs(a["computed"] - b["computed"]) / max(abs(a["computed"]), 1e-300)
    worst = max(worst, err)
    assert err <= tolerance, "%s: %r on 1 rank, %r on %d" % (a["name"], a["computed"], b["computed"], ranks)
    assert b["pass"], b["name"]
krylov = [k for inc in many["increments"] for k in inc.get("krylov_iterations", [])]
print("%s with %s: 1 and %d ranks agree to %.1e (%d Newton iterations on 1 rank, %d on %d; Krylov per Newton "
      "iteration on %d ranks: %s)" % (os.path.basename(deck), linear, ranks, worst, one["total_iterations"],
                                       many["total_iterations"], ranks, ranks, krylov[:8]))
