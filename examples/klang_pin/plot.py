#!/usr/bin/python3
"""Contact pressure of examples/klang_pin against Klang's reference (VALIDATION.md sec. 3).

Usage: plot.py RESULTS_DIR[:label] [OUT.png] [more RESULTS_DIR:label ...]
Reads the last contact CSV of the pair 'pin' in each directory, prints the pressure at the
reference angles (linear interpolation between nodes), the contact half-arc and the stick
half-arc (degrees from the load line), and plots the pressure against the reference.
"""
import csv
import glob
import math
import os
import sys

REF = [(0, 17.813), (3, 17.813), (6, 17.750), (9, 17.688), (12, 17.594), (15, 17.470), (18, 17.312),
       (21, 17.125), (24, 16.906), (27, 16.656), (30, 16.343), (33, 15.937), (36, 15.406), (39, 14.781),
       (42, 14.031), (45, 13.094)]


def load(out):
    files = sorted(glob.glob(os.path.join(out, "contact_pin_01_*.csv")))
    if not files:
        sys.exit(f"no contact CSV in {out}")
    rows = list(csv.DictReader(open(files[-1])))
    pts = []
    for r in rows:
        x, y = float(r["x"]), float(r["y"])
        angle = math.degrees(math.atan2(x, -y))  # from the load line (-y), the pin's centre near 0
        pts.append((angle, float(r["pressure"]) / 1e6, r["status"]))
    pts.sort()
    return pts


def report(pts, label):
    closed = [p for p in pts if p[2] in ("stick", "slip", "closed")]
    stick = [p for p in pts if p[2] == "stick"]
    arc = max(a for a, _, _ in closed)
    stick_arc = max(a for a, _, _ in stick) if stick else 0.0
    worst = 0.0
    for ang, pref in REF:
        for (a0, p0, _), (a1, p1, _) in zip(pts, pts[1:]):
            if a0 <= ang <= a1:
                p = p0 + (p1 - p0) * (ang - a0) / (a1 - a0) if a1 > a0 else p0
                worst = max(worst, abs(p - pref) / pref)
                break
    print(f"{label}: contact half-arc {arc:.1f} deg (reference 60), stick half-arc {stick_arc:.1f} deg "
          f"(reference 26-30), largest pressure error at the reference angles {100 * worst:.2f} %")
    return closed


def main():
    first = sys.argv[1].split(":", 1)
    out = first[0]
    png = sys.argv[2] if len(sys.argv) > 2 else os.path.join(out, "klang.png")
    runs = [(out, first[1] if len(first) > 1 else "Signorini")] + [tuple(a.split(":", 1)) for a in sys.argv[3:]]
    data = [(report(load(d), lab), lab) for d, lab in runs]
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    plt.figure(figsize=(6, 4))
    plt.plot([a for a, _ in REF], [p for _, p in REF], "ks", label="Klang (reference)")
    for closed, lab in data:
        plt.plot([a for a, _, _ in closed], [p for _, p, _ in closed], "-", lw=1, label=lab)
    plt.xlabel("angle from the load line (degrees)")
    plt.ylabel("contact pressure (MPa)")
    plt.xlim(0, 65)
    plt.legend(fontsize=8)
    plt.tight_layout()
    plt.savefig(png, dpi=120)
    print(f"plot: {png}")


if __name__ == "__main__":
    main()
