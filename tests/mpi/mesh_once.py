"""Under mpirun rank 0 alone reads the mesh (GmshOptions::ranks): a .geo meshed once, a .msh
checked once, and the mesh sent to the other ranks; a failed meshing reported (rank 0's message) by
every rank alike, without a hang. A `gmsh` first on PATH logs each call and runs the real one.

Usage: mesh_once.py SIGNORINI EXAMPLE_DECK RANKS WORK
The example's mesh must be `mesh: {file: NAME.geo}` (no parameters), meshed in under 5 s (no size
estimate: one gmsh call)."""
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mpi_case import launcher, read_deck, run_signorini, write_deck  # noqa: E402

signorini, example, ranks, work = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
real = shutil.which("gmsh")
if real is None:
    sys.exit("gmsh not found (apt install gmsh)")
calls = os.path.join(work, "gmsh_calls")
bindir = os.path.join(work, "bin")
os.makedirs(bindir)
with open(os.path.join(bindir, "gmsh"), "w") as f:
    f.write('#!/bin/sh\necho "$@" >> "%s"\nexec "%s" "$@"\n' % (calls, real))
os.chmod(os.path.join(bindir, "gmsh"), 0o755)
mpirun, env = launcher(PATH=bindir + os.pathsep + os.environ.get("PATH", ""))
# By its name, not its path: OpenMPI's mpirun called by an absolute path puts its own folder
# (/usr/bin, the real gmsh's) first on the ranks' PATH.
mpirun = os.path.basename(mpirun)
failures = []


def count_calls():
    """The gmsh calls logged since the last count (the log then emptied)."""
    if not os.path.exists(calls):
        return 0
    with open(calls) as f:
        n = len(f.read().splitlines())
    os.remove(calls)
    return n


def expect(what, got, wanted):
    print("%s: %s (expected %s)" % (what, got, wanted))
    if got != wanted:
        failures.append("%s: %s, expected %s" % (what, got, wanted))


text = read_deck(example) + "\nsolver: {linear: {type: mumps}}\n"
deck = write_deck(work, text)

# 1. The .geo: one gmsh call on one process and on RANKS ranks, and the same model and answer.
one, _ = run_signorini(signorini, deck, os.path.join(work, "one"), 1, mpirun, env, "one process")
expect("gmsh calls, one process, .geo", count_calls(), 1)
many, _ = run_signorini(signorini, deck, os.path.join(work, "many"), ranks, mpirun, env, "%d ranks" % ranks)
expect("gmsh calls, %d ranks, .geo" % ranks, count_calls(), 1)
for key in ("nodes", "cells", "dofs"):
    expect("%s on %d ranks against one process" % (key, ranks), many[key], one[key])
for a, b in zip(one["checks"], many["checks"]):
    rel = abs(a["computed"] - b["computed"]) / max(abs(a["computed"]), 1e-300)
    print("check '%s': %.9g (1 process), %.9g (%d ranks), relative difference %.2e" % (
        a["name"], a["computed"], b["computed"], ranks, rel))
    if rel > 1e-6 or not b["pass"]:
        failures.append("check '%s': %.9g on %d ranks (%.2e from one process's, pass: %s)" % (
            a["name"], b["computed"], ranks, rel, b["pass"]))

# 2. A .msh: checked by one gmsh call (rank 0's), read by rank 0 and sent to the others.
geo = text.split("file: ", 1)[1].split("}", 1)[0].strip()
msh = os.path.join(work, "mesh.msh")
dim = "-2" if "plane_" in text or "axisymmetric" in text else "-3"
subprocess.run([real, geo, dim, "-format", "msh41", "-o", msh], check=True, capture_output=True)
msh_text = text.replace(geo, msh, 1)
run_signorini(signorini, write_deck(work, msh_text), os.path.join(work, "msh"), ranks, mpirun, env, ".msh deck")
expect("gmsh calls, %d ranks, .msh" % ranks, count_calls(), 1)

# 3. A .geo that Gmsh cannot mesh: every rank stops, rank 0's message printed, one gmsh call.
bad_geo = os.path.join(work, "bad.geo")
with open(geo) as f, open(bad_geo, "w") as g:
    g.write(f.read() + "\nPoint(1) = {0, 0, 0, 1};\nLine(1) = {1, 99999};\n")
bad = write_deck(work, text.replace(geo, bad_geo, 1))
p = subprocess.run([mpirun, "-np", str(ranks), signorini, "run", bad, "-q", "-o", os.path.join(work, "bad")], env=env,
                   capture_output=True, text=True, timeout=300)
print("bad .geo on %d ranks: exit code %d, stderr: %s" % (ranks, p.returncode, p.stderr.strip()[:400]))
if p.returncode == 0:
    failures.append("the bad .geo ran to the end")
if "Gmsh could not mesh" not in p.stderr and "Gmsh crashed" not in p.stderr:
    failures.append("the bad .geo's error message is missing: " + p.stderr[-500:])
expect("gmsh calls, %d ranks, bad .geo" % ranks, count_calls(), 1)

if failures:
    sys.exit("FAILED:\n  " + "\n  ".join(failures))
print("PASSED")
