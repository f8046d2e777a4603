"""A restart file written on N MPI ranks (issue 15): partitioned, each rank holds the
quadrature-point history of its own cells only, so writing the file gathers them (every rank
takes part, rank 0 writes). The thick cylinder with J2 plasticity is pressurized to 0.9 p_lim
(its plastic zone out to 150 mm of the 200) and then unloaded, so that the end state (the
residual displacements and stresses) is all plastic strain; the run on N ranks writes a
restart file after each step. Then the unloading is run again from the first step's file, on
N ranks and on one process (the file is the same whatever the ranks that wrote it), and both
must end where the uninterrupted run ends: every field of the last increment (displacements,
reactions, stresses, the plastic history) and the residual displacement (checked against
Hill's solution less the elastic unloading) to TOLERANCE. A file that held rank 0's
cells' history alone restarts the other cells unstrained, and misses by far more.
Usage: restart_ranks.py SIGNORINI EXAMPLE_DECK RANKS TOLERANCE WORKDIR"""
import os
import shutil
import sys

from mpi_case import agree, fields, launcher, read_deck, run_signorini, write_deck

signorini, deck, ranks, tolerance, work = sys.argv[1:6]
ranks, tolerance = int(ranks), float(tolerance)
os.makedirs(work, exist_ok=True)
text = read_deck(deck)
# The step, then the same step unloading to zero pressure; a restart file after each step.
first, last = text.index("  - name: pressurize"), text.index("\noutput:")
step = text[first:last + 1]
assert "pressure: 172.8815e6" in step and "0.0556" in step, "the deck's step changed: update this test"
unload = step.replace("name: pressurize", "name: unload").replace("pressure: 172.8815e6", "pressure: 0")
text = text[:last + 1] + unload + text[last + 1:]
# The deck's checks are of the loaded state; after the unloading (elastic: 0.9 p_lim is below
# the 2 p_e = 207.8 MPa of reversed yielding) the outer radius keeps Hill's u(b) less the
# elastic (Lame, plane strain) 2 (1 - nu^2) p a^2 b / (E (b^2 - a^2)) = 9.9886e-5 m.
text = text[:text.index("\nchecks:")] + """
checks:
  - {name: "residual u_r at the outer radius (m)", quantity: displacement, at: [0.2, 0], component: x,
     expected: 3.4978e-5, tolerance: 0.03, reference: "Hill 1950, ch. V, less the elastic unloading (Lame)"}
"""
text = text.replace("vtu: every_increment}", "vtu: every_increment, restart: every_step}")
assert "restart: every_step" in text, "the deck's output line changed: update this test"
text += "\nsolver: {linear: {type: mumps}}\n"
copy = write_deck(work, text)

mpirun, env = launcher()


def run(n, name, *extra):
    out = os.path.join(work, name)
    shutil.rmtree(out, ignore_errors=True)
    summary, _ = run_signorini(signorini, copy, out, n, mpirun, env, name, *extra)
    assert summary["status"] == "completed", (name, summary["status"])
    assert summary["mpi_ranks"] == n, (name, summary["mpi_ranks"])
    return summary, fields(out, n)


whole, f_whole = run(ranks, "whole")
assert whole["algebra"].startswith("partitioned"), whole["algebra"]
restart = os.path.join(work, "whole", "restart_0001.bin")
assert os.path.exists(restart) and os.path.exists(os.path.join(work, "whole", "restart_0002.bin"))
for n in (ranks, 1):
    again, f_again = run(n, "restarted_np%d" % n, "--restart", restart)
    assert again.get("restarted_after_step") == 1, again.get("restarted_after_step")
    worst = agree(f_whole, f_again, tolerance)
    for a, b in zip(whole["checks"], again["checks"]):
        err = abs(a["computed"] - b["computed"]) / max(abs(a["computed"]), 1e-300)
        assert err <= tolerance and b["pass"], "%s: %r uninterrupted, %r restarted on %d" % (a["name"], a["computed"],
                                                                                            b["computed"], n)
        worst = max(worst, err)
    print("restarted from the %d ranks' file on %d: the fields and checks agree with the uninterrupted run to %.1e"
          % (ranks, n, worst))
