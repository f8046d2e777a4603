#!/usr/bin/python3
"""Brinell indentation: load-depth curve (loading and unloading), mean pressure over the
yield stress against the contact radius with Tabor's 2.8, and the residual imprint, from a
run of brinell.yaml (reactions.csv and the contact_indenter_SS_IIII.csv files).

    plot.py OUT.png RESULTS_DIR

Prints the maximum force, the residual depth at the axis and the Brinell hardness
HB = 2 F / (pi D (D - sqrt(D^2 - d^2))) (N/mm^2) with d the imprint's rim diameter after
unloading (the diameter of its highest ring).
"""
import csv
import glob
import math
import os
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

R, DEPTH, SY = 1.0, 0.08, 400.0  # the deck's sphere radius, depth (mm) and yield stress (MPa)


def contact_file(path):
    rows = []
    with open(path) as f:
        for row in csv.DictReader(f):
            if row["status"] == "far":
                continue
            rows.append((float(row["x"]), float(row["y"]), row["status"] == "closed" or row["status"] == "stick"
                         or row["status"] == "slip"))
    rows.sort()
    return rows


def radius(rows):
    inside = max((x for x, _, c in rows if c), default=0.0)
    beyond = [x for x, _, c in rows if not c and x > inside]
    return 0.5 * (inside + min(beyond)) if beyond else inside


def main():
    out, results = sys.argv[1], sys.argv[2]
    depth, force, steps = [], [], []
    with open(os.path.join(results, "reactions.csv")) as f:
        for row in csv.DictReader(f):
            if row["set"] != "obstacle:indenter":
                continue
            step, frac = int(row["step"]), float(row["fraction"])
            depth.append(DEPTH * (frac if step == 1 else 1 - frac))
            force.append(-float(row["fy"]))
            steps.append(step)
    press = sorted(glob.glob(os.path.join(results, "contact_indenter_01_*.csv")))
    lift = sorted(glob.glob(os.path.join(results, "contact_indenter_02_*.csv")))
    a_over_r, pm = [], []
    loading = [f for f, s in zip(force, steps) if s == 1]
    for path, F in zip(press, loading):
        a = radius(contact_file(path))
        if a > 0:
            a_over_r.append(a / R)
            pm.append(F / (math.pi * a * a) / SY)
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.5))
    d, F, s = np.array(depth), np.array(force), np.array(steps)
    ax[0].plot(np.r_[0, d[s == 1]], np.r_[0, F[s == 1]], "o-", ms=3, label="loading")
    ax[0].plot(np.r_[DEPTH, d[s == 2]], np.r_[F[s == 1][-1], F[s == 2]], "s-", ms=3, label="unloading")
    ax[0].set_xlabel("indenter displacement (mm)")
    ax[0].set_ylabel("force F (N)")
    ax[0].legend()
    ax[0].grid(alpha=0.3)
    ax[1].plot(a_over_r, pm, "o-", ms=3, label="computed F / (pi a^2)")
    ax[1].axhline(2.8, color="k", lw=1, label="Tabor 2.8")
    ax[1].axhspan(2.52, 3.08, color="0.85", label="asserted band (from a/R = 0.3)")
    ax[1].set_xlabel("contact radius a / R (deformed surface)")
    ax[1].set_ylabel("p_m / sigma_y")
    ax[1].set_ylim(0, 3.5)
    ax[1].legend(loc="lower right")
    ax[1].grid(alpha=0.3)
    hb = None
    if lift:
        rows = contact_file(lift[-1])
        x = np.array([r[0] for r in rows])
        y = np.array([r[1] for r in rows])
        ax[2].plot(x, y * 1e3, "-", label="residual imprint (after lifting)")
        if press:
            rows = contact_file(press[-1])
            ax[2].plot([r[0] for r in rows], [r[1] * 1e3 for r in rows], "--", label="at the maximum depth")
        xs = np.linspace(0, 0.5, 100)
        ax[2].plot(xs, (R - DEPTH - np.sqrt(R * R - xs * xs)) * 1e3, ":", color="k", label="sphere at the maximum depth")
        ax[2].axhline(0, color="0.6", lw=0.8)
        ax[2].set_xlim(0, 1.0)
        ax[2].set_ylim(-90, 50)
        ax[2].set_xlabel("r (mm)")
        ax[2].set_ylabel("surface height (um)")
        ax[2].legend(loc="lower right")
        ax[2].grid(alpha=0.3)
        rim = x[np.argmax(y)]
        dd = 2 * rim
        hb = 2 * max(force) / (math.pi * 2 * R * (2 * R - math.sqrt(4 * R * R - dd * dd)))
        print(f"residual depth {-y[0]:.4f} mm at r = {x[0]:.3f}; rim at r = {rim:.3f} mm, {y.max() * 1e3:.1f} um high")
    fig.suptitle("Brinell indentation, J2 elastic-perfectly plastic, finite strain (examples/brinell)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"maximum force {max(force):.1f} N; p_m / sigma_y from a/R = 0.3: "
          f"{min(p for p, a in zip(pm, a_over_r) if a >= 0.3):.3f}-{max(p for p, a in zip(pm, a_over_r) if a >= 0.3):.3f}"
          + (f"; Brinell hardness HB = {hb:.0f} N/mm^2 ({hb / SY:.2f} sigma_y)" if hb else ""))


if __name__ == "__main__":
    main()
