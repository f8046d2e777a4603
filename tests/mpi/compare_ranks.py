"""Runs a shipped example with a PETSc linear solver on 1 and on N MPI ranks and checks that
the two runs agree (issue 15): both complete, summary.json says how many ranks solved, and
every reference check of the deck gives the same computed value to `tolerance` (relative).
The last increment's ParaView fields (displacements, reactions, stresses, and the
quadrature-point history of plastic bodies, which with partitioned assembly each rank updates
for its own cells only) must agree too, to `tolerance` relative to each field's largest value.
With ALGEBRA ("partitioned" or "replicated"), summary.json must say that the N ranks shared the
algebra that way.
With PARTITION (rcb or ptscotch), the N ranks share the cells out that way (solver.linear.partition).
COMPARE_DECK_EDIT ("old=>new|..."), COMPARE_RESIDUAL_TOLERANCE: see below.
LINEAR "auto" leaves the choice to the solver, which under mpirun must pick mumps (the example
being below the default iterative_above), or what COMPARE_EXPECT_AUTO names (gamg for an
unsymmetric 3D model, at any size); "auto@K" sets iterative_above K, below the example's
unknowns, and the N ranks must pick gamg (a symmetric 3D example whose multipliers the
distributed backend condenses). summary.json's linear type says what was picked.
--step=one runs the one-process run alone (WORKDIR/np1) and checks that it completed;
--step=many then runs the N ranks and compares them with it (the suite runs the two as two
tests, the first a fixture of the second, so that the one-process run takes one core beside
other tests while the N ranks hold N; session 70). Without --step, both in turn.
Usage: compare_ranks.py [--step=one|many] SIGNORINI EXAMPLE_DECK LINEAR RANKS TOLERANCE WORKDIR [ALGEBRA [PARTITION]]"""
import hashlib
import json
import os
import re
import sys

from mpi_case import agree, fields, launcher, read_deck, run_signorini, write_deck

args = sys.argv[1:]
step = "both"
if args and args[0].startswith("--step="):
    step = args.pop(0)[len("--step="):]
    assert step in ("one", "many"), "--step=%s: one or many" % step
signorini, deck, linear, ranks, tolerance, work = args[0:6]
expected_algebra = args[6] if len(args) > 6 else None
partition = args[7] if len(args) > 7 else "rcb"
ranks, tolerance = int(ranks), float(tolerance)
os.makedirs(work, exist_ok=True)
text = read_deck(deck)  # a solver section of our own below
linear_type, _, iterative_above = linear.partition("@")
extra = ", iterative_above: %s" % iterative_above if iterative_above else ""
# COMPARE_RESIDUAL_TOLERANCE: Newton's tolerance for both runs, for an example whose fields at the
# default 1e-8 differ by more than TOLERANCE between two converged runs (their inexact Newton
# iterates differ: a distributed GAMG aggregates otherwise).
newton = os.environ.get("COMPARE_RESIDUAL_TOLERANCE")
newton = ", residual_tolerance: %s" % newton if newton else ""
text += "\nsolver: {linear: {type: %s, rtol: 1e-10, partition: %s%s}%s}\n" % (linear_type, partition, extra, newton)
# COMPARE_DECK_EDIT: "old=>new|old=>new": text replaced in the deck (each must be found; a
# backslash-n in either is a line break), to run a shipped example with another discretization
# or enforcement.
for edit in filter(None, os.environ.get("COMPARE_DECK_EDIT", "").split("|")):
    old, new = (part.replace("\\n", "\n") for part in edit.split("=>"))
    assert old in text, "COMPARE_DECK_EDIT: %r is not in %s" % (old, deck)
    text = text.replace(old, new)
copy = write_deck(work, text)

# SIGNORINI_CHECK_CONDENSED_PRODUCT: the partitioned backend checks its T^T J T (condensed
# contact multipliers, or friction's Z^T (J + Delta) T) applied to a vector against its factors
# applied in turn, at every solve, and stops the run if they differ.
# SIGNORINI_CHECK_CELL_SUMS: it checks the owners' sums of the internal forces against the
# whole vector's reduction at every residual, and stops the run if they differ.
mpirun, env = launcher(SIGNORINI_CHECK_CONDENSED_PRODUCT="1", SIGNORINI_CHECK_CELL_SUMS="1")


def run(n):
    return run_signorini(signorini, copy, os.path.join(work, "np%d" % n), n, mpirun, env, "np %d" % n)


# What the one-process run was made from: the deck's text and the program's file (its size and
# time), so that --step=many refuses a one-process run of another deck or another build.
stamp = {"deck": hashlib.sha256(text.encode()).hexdigest(),
         "signorini": [os.stat(signorini).st_size, os.stat(signorini).st_mtime_ns]}
stamp_path = os.path.join(work, "np1", "made_from.json")
if step == "many":
    assert os.path.exists(stamp_path), "%s: no one-process run (run --step=one first)" % stamp_path
    with open(stamp_path) as f:
        assert json.load(f) == stamp, "%s: the one-process run is of another deck or build" % stamp_path
    with open(os.path.join(work, "np1", "summary.json")) as f:
        one = json.load(f)
else:
    if os.path.exists(stamp_path):
        os.remove(stamp_path)
    one, _ = run(1)
    assert one["status"] == "completed", one["status"]
    with open(stamp_path, "w") as f:
        json.dump(stamp, f)
    if step == "one":
        print("%s with %s on one process: %s, %d Newton iterations" % (
            os.path.basename(deck), linear, one["status"], one["total_iterations"]))
        sys.exit(0)
many, log = run(ranks)
assert one["status"] == "completed" and many["status"] == "completed", (one["status"], many["status"])
assert one["mpi_ranks"] == 1 and many["mpi_ranks"] == ranks, (one["mpi_ranks"], many["mpi_ranks"])
assert log.count("Solved") == 1, "rank 0 alone should print the summary:\n" + log
if linear_type == "auto":
    # COMPARE_EXPECT_AUTO: what auto picks on the ranks when it is not the default rule's (gamg
    # above iterative_above, else mumps): gamg for an unsymmetric 3D system at any size.
    picked = os.environ.get("COMPARE_EXPECT_AUTO", "gamg" if iterative_above else "mumps")
    assert many["linear"]["type"] == picked, "auto on %d ranks: %s, not %s" % (ranks, many["linear"]["type"], picked)
# Each increment that solved names its last solve's method and preconditioner (summary.json,
# issue 15); one converged at its first residual has none.
methods = {inc.get("linear_method", "") for inc in many["increments"] if inc["iterations"] > 0}
expected_method = {"gamg": ", gamg (", "hypre": ", hypre (", "mumps": "(mumps)"}.get(many["linear"]["type"], "")
# COMPARE_EXPECT_METHOD: "a|b": each increment's method holds one of these instead (a run whose
# solves go whole to MUMPS).
accepted = os.environ.get("COMPARE_EXPECT_METHOD", expected_method).split("|")
assert all(m and any(a in m for a in accepted) for m in methods), "linear_method %s for %s" % (methods, accepted)
# The ranks take Newton's steps of one process: the same system solved to the same forcing
# terms (the coupled contact rows' flexible GMRES too), only the preconditioner's aggregation
# differs, so a few iterations more at most.
assert many["total_iterations"] <= one["total_iterations"] + max(2, one["total_iterations"] // 5), \
    "%d Newton iterations on %d ranks against %d on one" % (many["total_iterations"], ranks, one["total_iterations"])
# Mortar's slave facets are dealt out to the ranks, each integrating its share (the checks and
# fields below then show that the exchanged constraints are the one-process ones). Nitsche's
# method (segment_to_segment's class, on mortar's segments or its own) deals its points out when
# the assembly is partitioned, each rank building and assembling its own (the residual and the
# nodal state summed over the ranks); other pairs are evaluated whole on every rank.
nitsche = "method: nitsche" in text
mortar = re.search(r"discretization: mortar", text) is not None and not nitsche
assert one["contact_evaluation"] in ("one process", "no contact pair"), one["contact_evaluation"]
if mortar:
    assert many["contact_evaluation"].startswith("mortar's slave facets dealt out to the %d ranks" % ranks), \
        many["contact_evaluation"]
elif nitsche and many["algebra"].startswith("partitioned"):
    assert many["contact_evaluation"].startswith("Nitsche's points dealt out to the %d ranks" % ranks), \
        many["contact_evaluation"]
else:
    assert not many["contact_evaluation"].startswith("mortar") and "Nitsche" not in many["contact_evaluation"], \
        many["contact_evaluation"]
if expected_algebra:
    assert many["algebra"].startswith(expected_algebra), many["algebra"]
    if expected_algebra == "partitioned":
        shared_by = {"rcb": "coordinate bisection", "ptscotch": "PT-Scotch"}[partition]
        assert many["algebra"].endswith("cells shared out by %s)" % shared_by), many["algebra"]


f1, f2 = fields(os.path.join(work, "np1"), 1), fields(os.path.join(work, "np%d" % ranks), ranks)
worst_field = agree(f1, f2, tolerance)
print("%d fields of the last increment agree to %.1e" % (len(f1), worst_field))
worst = 0.0
for a, b in zip(one["checks"], many["checks"]):
    assert a["name"] == b["name"]
    err = abs(a["computed"] - b["computed"]) / max(abs(a["computed"]), 1e-300)
    worst = max(worst, err)
    assert err <= tolerance, "%s: %r on 1 rank, %r on %d" % (a["name"], a["computed"], b["computed"], ranks)
    assert b["pass"], b["name"]
# The partitioned backend keeps the tangent of the bodies whose internal force is linear in u
# (Analysis::evaluate): assembled once per sparse pattern, not at every tangent evaluation.
tangents = many["tangents"]
if expected_algebra == "partitioned" and tangents["linear_bodies_assembled"] > 0:
    assert tangents["linear_bodies_assembled"] < tangents["evaluated"], tangents
def krylov_iterations(summary):
    """The Krylov iterations of every Newton iteration of the run, in order."""
    return [k for inc in summary["increments"] for k in inc.get("krylov_iterations", [])]


krylov = krylov_iterations(many)
# COMPARE_KRYLOV_RATIO: the N ranks' Krylov iterations over the run, at most this multiple of one
# process's (the coupled contact rows' condensation on the partitioned matrix leaving out no more
# than one process does: each GMRES correction on J is one more Krylov solve).
krylov_ratio = os.environ.get("COMPARE_KRYLOV_RATIO")
if krylov_ratio:
    total_one = sum(krylov_iterations(one))
    assert total_one > 0 and sum(krylov) <= float(krylov_ratio) * total_one, \
        "%d Krylov iterations on %d ranks against %d on one (at most %s times)" % (sum(krylov), ranks, total_one,
                                                                               krylov_ratio)
    print("Krylov iterations: %d on %d ranks, %d on one" % (sum(krylov), ranks, total_one))
print("%s with %s: 1 and %d ranks agree to %.1e (%d Newton iterations on 1 rank, %d on %d; Krylov per Newton "
      "iteration on %d ranks: %s; algebra: %s)" % (os.path.basename(deck), linear, ranks, worst, one["total_iterations"],
                                                   many["total_iterations"], ranks, ranks, krylov[:8], many["algebra"]))
