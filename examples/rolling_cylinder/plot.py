#!/usr/bin/python3
"""Rigid bodies that turn (tests RigidRotation.*): the 2D roller (analytic and meshed) rolled
and driven, and the 3D ball (analytic and meshed) twisted to full slip. Reads the CSV files
the tests write in build/curves/.

    plot.py OUT.png [CURVES_DIR (default build/curves)]
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

R, E, NU, MU, Q = 10.0, 200e3, 0.3, 0.3, 1000.0
ESTAR = E / (1 - NU * NU)


def read(curves, name):
    path = os.path.join(curves, name + ".csv")
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "rolling.png"
    curves = sys.argv[2] if len(sys.argv) > 2 else "build/curves"
    fig, (a1, a2, a3) = plt.subplots(1, 3, figsize=(15, 4.4))
    for name, style in (("rolling_cylinder", "o-"), ("rolling_rigid_mesh", "x--")):
        rows = read(curves, name)
        if not rows:
            continue
        label = "analytic cylinder" if name == "rolling_cylinder" else "meshed rigid roller"
        for step, what in ((1, "free rolling"), (3, "driven against Q")):
            r = [x for x in rows if x["step"] in (step - 1, step)]
            r = [x for x in r if x["step"] == step or x is r[-1] or x == [y for y in r if y["step"] == step - 1][-1]]
            a1.plot([x["turn"] for x in r], [1e3 * (x["advance"] - R * x["turn"]) for x in r], style, ms=4,
                    label=f"{label}, {what}")
        r = [x for x in rows if x["step"] >= 2]
        a2.plot([x["turn"] for x in r], [abs(x["moment"]) for x in r], style, ms=4, label=f"{label}: reaction moment")
    a1.axhline(0, color="k", ls=":", lw=1, label="rolling without creep")
    a1.set_xlabel("turn (rad)")
    a1.set_ylabel("advance - R x turn (micrometres)")
    a1.set_title("Roller, plane strain: creep (free, then driven)")
    a1.legend(fontsize=7)
    a2.axhline(Q * R, color="k", ls=":", label="Q R")
    a2.set_xlabel("turn (rad)")
    a2.set_ylabel("moment (N mm / mm)")
    a2.set_title("Roller held back by Q, then driven")
    a2.legend(fontsize=7)
    for name, style in (("rolling_ball", "o-"), ("rolling_rigid_ball", "x--")):
        all_rows = read(curves, name)
        before = [x for x in all_rows if x["step"] == 1]
        rows = before[-1:] + [x for x in all_rows if x["step"] == 2]
        if len(rows) < 2:
            continue
        label = "analytic ball" if name == "rolling_ball" else "meshed rigid ball"
        a3.plot([x["rotation_z"] for x in rows], [x["moment_z"] for x in rows], style, ms=4, label=label)
        lubkin = [3 * math.pi / 16 * MU * x["P"] * (3 * x["P"] * R / (4 * ESTAR)) ** (1 / 3) for x in rows]
        a3.plot([x["rotation_z"] for x in rows], lubkin, "k:" if name == "rolling_ball" else "k-.", lw=1,
                label=f"(3 pi/16) mu P a ({label}'s P)")
    a3.set_xlabel("rotation about the vertical (rad)")
    a3.set_ylabel("moment about the vertical (N mm)")
    a3.set_title("Ball, 3D: twist to full slip")
    a3.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
