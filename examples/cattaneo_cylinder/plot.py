#!/usr/bin/python3
"""Tangential traction of examples/cattaneo_cylinder against Cattaneo-Mindlin.

Usage: plot.py RESULTS_DIR [OUT.png]
Reads the last contact CSV of the pair 'cm' and reactions.csv, computes P (normal contact
force), a, p0 (Hertz, Johnson 1985 ch. 4) and c/a = sqrt(1 - Q/(mu P)) (Johnson 1985, sec.
7.2), measures the stick half-width from the node statuses, prints both and plots the
traction q(x) against q = mu p0 sqrt(1 - x^2/a^2) - (c/a) mu p0 sqrt(1 - x^2/c^2) (|x| < c).
"""
import csv
import glob
import math
import os
import sys

E, NU, R, MU = 210000.0, 0.3, 10.0, 0.3


def main():
    out = sys.argv[1]
    png = sys.argv[2] if len(sys.argv) > 2 else os.path.join(out, "cattaneo.png")
    files = sorted(glob.glob(os.path.join(out, "contact_cm_02_*.csv")))
    if not files:
        sys.exit(f"no contact CSV of step 2 in {out}")
    rows = list(csv.DictReader(open(files[-1])))
    closed = [r for r in rows if r["status"] in ("stick", "slip")]
    # Slave side forces: normal (y) and tangential (x), per unit thickness.
    P = Q = 0.0
    for r in csv.DictReader(open(os.path.join(out, "reactions.csv"))):
        if r["set"].startswith("contact:") and r["step"] == "2":
            P, Q = abs(float(r["fy"])), abs(float(r["fx"]))
    estar = E / (2 * (1 - NU * NU))
    a = math.sqrt(4 * P * R / (math.pi * estar))
    p0 = 2 * P / (math.pi * a)
    ca = math.sqrt(max(0.0, 1 - Q / (MU * P)))
    xs = [float(r["x"]) for r in closed if r["status"] == "stick"]
    x_all = sorted(float(r["x"]) for r in closed)
    # Stick half-width: midway between the outermost sticking node and the next slipping one
    # on each side, averaged over both sides (the zone is centred only to first order).
    def edge(side):
        stick = [abs(x) for x in xs if x * side >= 0]
        slip = [abs(float(r["x"])) for r in closed if r["status"] == "slip" and float(r["x"]) * side >= 0]
        s = max(stick) if stick else 0.0
        beyond = [v for v in slip if v > s]
        return 0.5 * (s + min(beyond)) if beyond else s
    c = 0.5 * (edge(1) + edge(-1))
    print(f"P = {P:.4f} N/mm, Q = {Q:.4f} N/mm, Q/(mu P) = {Q / (MU * P):.4f}")
    print(f"a = {a:.5f} mm, p0 = {p0:.2f} MPa; stick half-width c = {c:.5f} mm, c/a = {c / a:.4f} "
          f"(Cattaneo-Mindlin {ca:.4f}, error {100 * abs(c / a - ca) / ca:.2f} %)")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    xt = [float(r["x"]) for r in closed]
    qt = [abs(float(r["traction_x"])) for r in closed]
    xx = [a * (-1 + 2 * i / 400) for i in range(401)]
    cc = ca * a
    qq = [MU * p0 * math.sqrt(max(0, 1 - x * x / (a * a)))
          - (ca * MU * p0 * math.sqrt(max(0, 1 - x * x / (cc * cc))) if abs(x) < cc else 0) for x in xx]
    plt.figure(figsize=(6, 4))
    plt.plot(xx, qq, "k-", label="Cattaneo-Mindlin")
    plt.plot(xt, qt, "o", ms=3, label="Signorini (nodes)")
    plt.xlabel("x (mm)")
    plt.ylabel("tangential traction |q| (MPa)")
    plt.title(f"Partial slip, Q/(mu P) = {Q / (MU * P):.2f}: c/a = {c / a:.3f} (theory {ca:.3f})")
    plt.legend()
    plt.tight_layout()
    plt.savefig(png, dpi=120)
    print(f"plot: {png}")


if __name__ == "__main__":
    main()
