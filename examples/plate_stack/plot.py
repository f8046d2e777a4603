#!/usr/bin/python3
"""The plate stack (examples/plate_stack, test MultiBody.PlateStackPairsAndEquilibrium): the
contact pressure at the closed nodes of each interface, the slipping ones marked. Reads build/curves/plate_stack.csv.

    plot.py OUT.png [CURVES_DIR (default build/curves)]
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "plate_stack.png"
    curves = sys.argv[2] if len(sys.argv) > 2 else "build/curves"
    with open(os.path.join(curves, "plate_stack.csv")) as f:
        rows = list(csv.DictReader(f))
    fig, ax = plt.subplots(figsize=(7, 4.2))
    for pair in sorted({r["pair"] for r in rows}):
        # The closed nodes (a pair's slave surface is the plate's whole outline: its other faces
        # are open in this pair).
        r = sorted((float(x["x"]), float(x["pressure"]), int(x["status"])) for x in rows
                   if x["pair"] == pair and int(x["status"]) >= 2)
        line, = ax.plot([x for x, _, _ in r], [p for _, p, _ in r], "-", label=pair)
        for status, marker, fill in ((3, "o", "none"), (2, ".", None)):
            pts = [(x, p) for x, p, s in r if s == status]
            if pts:
                ax.plot([x for x, _ in pts], [p for _, p in pts], marker, mfc=fill or line.get_color(),
                        color=line.get_color(), ms=5)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("contact pressure (MPa)")
    ax.set_title("Plate stack: pressure on each interface (circles: slipping, dots: sticking)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
