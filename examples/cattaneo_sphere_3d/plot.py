#!/usr/bin/python3
"""Tangential traction of examples/cattaneo_sphere_3d against Cattaneo-Mindlin (sphere).

Usage: plot.py RESULTS_DIR [OUT.png]
Reads the last contact CSV of the pair 'cm' (step 2) and reactions.csv; from the normal
contact force P of the half model (2P on the whole sphere) computes the Hertz radius a and
peak pressure p0 (Johnson 1985, ch. 4) and c/a = (1 - Q/(mu P))^(1/3) (Johnson 1985,
sec. 7.2); measures the stick radius as the solver's check does (the radius that best
separates sticking from slipping nodes) and the contact radius likewise (closed from open);
plots the nodal tangential traction |q_x| against the radius with
q(r) = mu p0 sqrt(1 - r^2/a^2) - (c/a) mu p0 sqrt(1 - r^2/c^2) for r < c (first term alone
for c < r < a).
"""
import csv
import glob
import math
import os
import sys

E, NU, R, MU = 1.40625e7, 0.25, 1.0, 0.3


def radius(points):
    """points: (r, inside) pairs; the threshold with the fewest nodes on the wrong side."""
    pts = sorted(points)
    wrong = sum(1 for _, i in pts if i)
    best, ts = wrong, []
    for k, (r, i) in enumerate(pts):
        wrong += -1 if i else 1
        if k + 1 < len(pts) and pts[k + 1][0] == r:
            continue
        t = 0.5 * (r + pts[k + 1][0]) if k + 1 < len(pts) else r
        if wrong < best:
            best, ts = wrong, []
        if wrong == best:
            ts.append(t)
    return sum(ts) / len(ts) if ts else 0.0


def main():
    out = sys.argv[1]
    png = sys.argv[2] if len(sys.argv) > 2 else os.path.join(out, "cattaneo_sphere.png")
    files = sorted(glob.glob(os.path.join(out, "contact_cm_02_*.csv")))
    if not files:
        sys.exit(f"no contact CSV of step 2 in {out}")
    rows = list(csv.DictReader(open(files[-1])))
    P = Q = 0.0
    for r in csv.DictReader(open(os.path.join(out, "reactions.csv"))):
        if r["set"].startswith("contact:") and r["step"] == "2":
            P, Q = abs(float(r["fz"])), abs(float(r["fx"]))
    estar = E / (2 * (1 - NU * NU))
    a = (3 * (2 * P) * R / (4 * estar)) ** (1 / 3)
    p0 = 3 * (2 * P) / (2 * math.pi * a * a)
    ca = max(0.0, 1 - Q / (MU * P)) ** (1 / 3)
    rad = lambda r: math.hypot(float(r["x"]), float(r["y"]))
    closed = [r for r in rows if r["status"] in ("stick", "slip")]
    c = radius([(rad(r), r["status"] == "stick") for r in closed])
    a_fe = radius([(rad(r), r["status"] in ("stick", "slip")) for r in rows])
    print(f"half model: P = {P:.2f}, Q = {Q:.2f}, Q/(mu P) = {Q / (MU * P):.4f}")
    print(f"Hertz a = {a:.5f}, p0 = {p0:.4e}; measured contact radius {a_fe:.5f} ({100 * (a_fe / a - 1):+.2f} %)")
    print(f"stick radius c = {c:.5f}: c/a = {c / a:.4f} (Cattaneo-Mindlin {ca:.4f}, error {100 * (c / a / ca - 1):+.2f} %); "
          f"c/a_measured = {c / a_fe:.4f}")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    cc = ca * a
    rr = [a * 1.2 * i / 400 for i in range(401)]
    qq = [MU * p0 * math.sqrt(max(0, 1 - x * x / (a * a))) - (ca * MU * p0 * math.sqrt(max(0, 1 - x * x / (cc * cc))) if x < cc else 0)
          for x in rr]
    pp = [MU * p0 * math.sqrt(max(0, 1 - x * x / (a * a))) for x in rr]
    plt.figure(figsize=(6.5, 4.2))
    plt.plot(rr, qq, "k-", label="Cattaneo-Mindlin q(r)")
    plt.plot(rr, pp, "k:", lw=0.8, label="mu p(r) (Hertz)")
    for status, mark in (("stick", "o"), ("slip", "x")):
        sel = [r for r in closed if r["status"] == status]
        plt.plot([rad(r) for r in sel], [abs(float(r["traction_x"])) for r in sel], mark, ms=3,
                 label=f"Signorini, {status} nodes")
    plt.axvline(cc, color="0.6", lw=0.8)
    plt.xlabel("radius r")
    plt.ylabel("tangential traction |q_x|")
    plt.title(f"Sphere, Q/(mu P) = {Q / (MU * P):.2f}: c/a = {c / a:.3f} (theory {ca:.3f})")
    plt.legend(fontsize=8)
    plt.tight_layout()
    plt.savefig(png, dpi=120)
    print(f"plot: {png}")


if __name__ == "__main__":
    main()
