#!/usr/bin/python3
"""Elastic-plastic sphere on a rigid flat: P/P_c and A/A_c against omega/omega_c with Kogut &
Etsion's (2002) fits, from a run of kogut_etsion.yaml (reactions.csv's contact row and the
contact_flat_01_IIII.csv files; A = pi a^2, a midway between the outermost closed node and the
next open one, deformed positions).

    plot.py OUT.png RESULTS_DIR
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

R, E, NU, Y, OMEGA = 10.0, 210e3, 0.3, 300.0, 1.0884e-2  # the deck's values
ES = E / (1 - NU * NU)
K, H = 0.454 + 0.41 * NU, 2.8 * Y
WC = (math.pi * K * H / (2 * ES)) ** 2 * R
PC = 4.0 / 3.0 * ES * math.sqrt(R) * WC ** 1.5
AC = math.pi * R * WC


def fit_p(w):
    return np.where(w <= 6, 1.03 * w ** 1.425, 1.40 * w ** 1.263)


def fit_a(w):
    return np.where(w <= 6, 0.93 * w ** 1.136, 0.94 * w ** 1.146)


def radius(path):
    rows = []
    with open(path) as f:
        for row in csv.DictReader(f):
            if row["status"] != "far":
                rows.append((float(row["x"]), row["status"] == "closed"))
    rows.sort()
    inside = max((x for x, c in rows if c), default=0.0)
    beyond = [x for x, c in rows if not c and x > inside]
    return 0.5 * (inside + min(beyond)) if beyond else inside


def main():
    out, results = sys.argv[1], sys.argv[2]
    w, p = [], []
    with open(os.path.join(results, "reactions.csv")) as f:
        for row in csv.DictReader(f):
            if row["set"] == "contact:flat":
                w.append(OMEGA * float(row["fraction"]) / WC)
                p.append(float(row["fy"]) / PC)
    files = sorted(glob.glob(os.path.join(results, "contact_flat_01_*.csv")))
    a = [math.pi * radius(path) ** 2 / AC for path in files]
    w, p, a = np.array(w), np.array(p), np.array(a[: len(w)])
    ws = np.logspace(0, 2, 100)
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.5))
    ax[0].loglog(w, p, "o", ms=4, label="computed")
    ax[0].loglog(ws, fit_p(ws), "k-", label="Kogut & Etsion 2002 fit")
    ax[0].fill_between(ws, 0.9 * fit_p(ws), 1.1 * fit_p(ws), color="0.85", label="+-10 % (asserted)")
    ax[0].set_xlabel("omega / omega_c")
    ax[0].set_ylabel("P / P_c")
    ax[1].loglog(w, a, "o", ms=4, label="computed")
    ax[1].loglog(ws, fit_a(ws), "k-", label="Kogut & Etsion 2002 fit")
    ax[1].fill_between(ws, 0.9 * fit_a(ws), 1.1 * fit_a(ws), color="0.85", label="+-10 % (asserted)")
    ax[1].set_xlabel("omega / omega_c")
    ax[1].set_ylabel("A / A_c")
    for x in ax:
        x.set_xlim(0.2, 120)
        x.grid(alpha=0.3, which="both")
        x.legend()
    fig.suptitle("Elastic-plastic sphere on a rigid flat (examples/kogut_etsion)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    sel = (w >= 1) & (w <= 110)
    print(f"{sel.sum()} loads from w = 1 to 100: P {100 * np.max(np.abs(p[sel] / fit_p(w[sel]) - 1)):.1f} %, "
          f"A {100 * np.max(np.abs(a[sel] / fit_a(w[sel]) - 1)):.1f} % at most from the fits")


if __name__ == "__main__":
    main()
