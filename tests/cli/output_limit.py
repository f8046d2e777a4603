"""A run whose output cannot be written (a full disk, here a file-size limit: RLIMIT_FSIZE with
SIGXFSZ ignored, so that a write past it fails with EFBIG as a full disk's fails with ENOSPC)
stops with a clear error and leaves no partial file behind: exit code 1, the message names the
file, no `.tmp` remains, and summary.json says `failed` with that message (session 71: it said
`running`, and the partial `.vtu.tmp` stayed, holding the space the next write needed).
The limit is above summary.json's size and below the first .vtu's, so the run stops at its
first ParaView file.
Usage: output_limit.py SIGNORINI DECK WORKDIR"""
import json
import os
import resource
import shutil
import signal
import subprocess
import sys

signorini, deck, work = sys.argv[1:4]
shutil.rmtree(work, ignore_errors=True)
LIMIT = 20000  # bytes: friction_block's summary.json is about 2 kB at the start, each .vtu 39 kB


def limited():
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (LIMIT, LIMIT))


p = subprocess.run([signorini, "run", deck, "-q", "-o", work], preexec_fn=limited, restore_signals=False,
                   capture_output=True, text=True, timeout=300)
print(p.stderr)
assert p.returncode == 1, "exit code %d, not 1" % p.returncode
assert "increment_00_0000.vtu.tmp' failed (disk full?)" in p.stderr, "no message naming the file"
left = [f for f in os.listdir(work) if f.endswith(".tmp")]
assert not left, "partial files left: %s" % left
with open(os.path.join(work, "summary.json")) as f:
    summary = json.load(f)
assert summary["status"] == "failed", "summary.json's status: %s" % summary["status"]
assert "increment_00_0000.vtu" in (summary["failure"] or ""), "summary.json's failure: %s" % summary["failure"]
print("output_limit: exit code 1, the file named, no .tmp left, summary.json failed")
