#!/usr/bin/python3
"""The dovetail (examples/dovetail, test Dovetail.BladeHeldByItsFlanksThroughASpinUpAndDown):
the flank pressure and accumulated slip along the blade's flank at speed and back at idle, and
the plastic zone (equivalent plastic strain of the cells near the flank, at idle). Reads the CSV
files the test writes in build/curves/.

    plot.py OUT.png [CURVES_DIR (default build/curves)]
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "dovetail.png"
    curves = sys.argv[2] if len(sys.argv) > 2 else "build/curves"
    flank = read(os.path.join(curves, "dovetail_flank.csv"))
    zone = read(os.path.join(curves, "dovetail_plastic.csv"))
    fig, (a1, a2, a3) = plt.subplots(1, 3, figsize=(15, 4.6))
    for state, style, label in (("speed", "o-", "at 1000 rad/s"), ("idle", "s--", "back at 300 rad/s")):
        rows = sorted((float(r["s"]), float(r["pressure"]), float(r["slip"])) for r in flank if r["state"] == state)
        a1.plot([r[0] for r in rows], [r[1] for r in rows], style, ms=3, label=label)
        a2.plot([r[0] for r in rows], [r[2] for r in rows], style, ms=3, label=label)
    for a, t, y in ((a1, "Flank pressure", "contact pressure (MPa)"), (a2, "Accumulated slip", "slip (mm)")):
        a.set_xlabel("distance along the flank from the blade's lower corner (mm)")
        a.set_ylabel(y)
        a.set_title(t)
        a.legend()
    x = [float(r["x"]) for r in zone]
    y = [float(r["y"]) for r in zone]
    e = [float(r["eps_p"]) for r in zone]
    sc = a3.scatter(x, y, c=e, s=6, cmap="viridis")
    a3.plot([20, 10], [252, 262], "r-", lw=1, label="flank (x + y = 272)")
    fig.colorbar(sc, ax=a3, label="equivalent plastic strain")
    a3.set_aspect("equal")
    a3.set_title("Plastic zone at idle (cells near the flank)")
    a3.legend(loc="lower left")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print("wrote", out)


if __name__ == "__main__":
    main()
