#!/usr/bin/python3
"""The crushed tube (examples/tube_crush, test SelfContact.TubeCrushedUntilItsInnerWallTouchesItself):
bar force against closure with the thin-ring closed form of its start, and the deformed
walls at the end (the half model mirrored), with the closed nodes of the self-contact marked;
with the file of SelfContact.TubeFoldAsMortarGivesTheNodeToSegmentForce, a third panel: the
end of the crush with the fold as mortar and as node-to-segment (linear cells).
Reads the CSV files the tests write in build/curves/.

    plot.py OUT.png [CURVES_DIR (default build/curves)]
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

R, T, E, NU = 10.0, 1.0, 10.0, 0.45
EI = E / (1 - NU * NU) * T ** 3 / 12
COEF = math.pi / 4 - 2 / math.pi  # closure = COEF P R^3 / EI (Timoshenko, Strength of Materials I, sec. 84)


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "tube_crush.png"
    curves = sys.argv[2] if len(sys.argv) > 2 else "build/curves"
    curve = read(os.path.join(curves, "tube_crush.csv"))
    shape = read(os.path.join(curves, "tube_crush_shape.csv"))
    mortar_csv = os.path.join(curves, "tube_crush_mortar.csv")
    mortar = read(mortar_csv) if os.path.exists(mortar_csv) else None
    fig, axes = plt.subplots(1, 3 if mortar else 2, figsize=(16 if mortar else 11, 4.6))
    a1, a2 = axes[0], axes[1]
    c = [float(r["closure"]) for r in curve]
    f = [float(r["force"]) for r in curve]
    a1.plot(c, f, "o-", ms=3, label="Signorini (force of a bar on the whole ring)")
    cl = [0, 2.0]
    a1.plot(cl, [x * EI / (COEF * R ** 3) for x in cl], "k--", label="thin ring, linear (Timoshenko)")
    touch = next((x for x, y in zip(c, f) if y > 2 * f[0] * x / c[0] and x > 15), None)
    if touch:
        a1.axvline(touch, color="r", lw=0.8, ls=":", label="inner wall touches (force then rises steeply)")
    a1.set_xlabel("closure of the bars 2d (mm)")
    a1.set_ylabel("bar force P (N per mm of depth)")
    a1.set_ylim(0, 1.6 * max(y for x, y in zip(c, f) if x < 18))
    a1.set_title("Force against closure")
    a1.legend(loc="lower right")
    for wall, style in (("Inner", "b-"), ("Outer", "k-")):
        pts = sorted((float(r["angle"]), float(r["x"]), float(r["y"]), r["closed"] == "1") for r in shape if r["wall"] == wall)
        xs = [p[1] for p in pts]
        ys = [p[2] for p in pts]
        a2.plot(xs, ys, style, lw=1)
        a2.plot([-x for x in xs], ys, style, lw=1)
        cx = [p[1] for p in pts if p[3]]
        cy = [p[2] for p in pts if p[3]]
        if cx:
            a2.plot(cx + [-x for x in cx], cy + cy, "ro", ms=3, label="closed self-contact nodes")
    a2.set_aspect("equal")
    a2.set_title("Deformed walls at the end")
    a2.legend(loc="upper right")
    if mortar:
        a3 = axes[2]
        for disc, style in (("node_to_segment", "k-"), ("mortar", "ro")):
            pts = [(float(r["closure"]), float(r["force"])) for r in mortar if r["discretization"] == disc]
            pts = [p for p in pts if p[0] > 17]
            label = "fold as node_to_segment (Lagrange)" if disc == "node_to_segment" else \
                "fold as mortar (Lagrange)"
            a3.plot([p[0] for p in pts], [p[1] for p in pts], style, ms=3, lw=1, label=label)
        a3.set_xlabel("closure of the bars 2d (mm)")
        a3.set_ylabel("bar force P (N per mm of depth)")
        a3.set_title("End of the crush, linear cells (24 and 20 per quarter)")
        a3.legend(loc="upper left")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print("wrote", out)


if __name__ == "__main__":
    main()
