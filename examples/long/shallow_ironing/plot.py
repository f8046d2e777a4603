#!/usr/bin/python3
"""Shallow ironing: the indenter's reaction forces against pseudo-time, from the solver's
reactions.csv (set IndenterTop), with the digitised published curves of
shared/reference-data/shallow-ironing (VALIDATION.md sec. 4).

    plot.py OUT.png LABEL=RESULTS_DIR [LABEL=RESULTS_DIR ...]

Prints, per run: the last time reached, V and H at t = 1.0 and 1.5 (when reached), H/V at
t = 1.5, and the oscillation of the force histories during sliding: the RMS deviation of V
and H from their running mean over a window of 0.1 in time (the signature of the jumps of
a faceted master's normal), on a uniform resampling of t in [1.1, t_end].
"""
import csv
import os
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
REF = os.path.normpath(os.path.join(HERE, "..", "..", "..", "..", "shared", "reference-data", "shallow-ironing"))
SCALE = 1e8  # the references' force unit


def history(results):
    t, h, v = [], [], []
    with open(os.path.join(results, "reactions.csv")) as f:
        for row in csv.DictReader(f):
            if row["set"] != "IndenterTop":
                continue
            t.append(float(row["time"]))
            h.append(float(row["fx"]) / SCALE)
            v.append(-float(row["fy"]) / SCALE)
    return np.array(t), np.array(h), np.array(v)


def oscillation(t, f, t0=1.1, window=0.1):
    if len(t) < 3 or t[-1] <= t0 + 2 * window:
        return float("nan")
    grid = np.linspace(t0, t[-1], 2000)
    g = np.interp(grid, t, f)
    n = max(3, int(window / (grid[1] - grid[0])) | 1)
    mean = np.convolve(g, np.ones(n) / n, mode="same")
    core = slice(n, len(g) - n)
    return float(np.sqrt(np.mean((g[core] - mean[core]) ** 2)))


def reference(name):
    path = os.path.join(REF, name)
    if not os.path.exists(path):
        return None
    return np.loadtxt(path)


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    out = sys.argv[1]
    runs = [a.rsplit("=", 1) for a in sys.argv[2:]]
    fig, (ax_v, ax_h) = plt.subplots(1, 2, figsize=(12, 4.5))
    refs = [("code_aster", "aster"), ("Hartmann, Oliver et al.", "hartmannOliver"),
            ("Fischer & Wriggers", "fischerWriggers"), ("Poulios & Renard", "pouliosRenard")]
    for label, stem in refs:
        for ax, kind in ((ax_v, "Vertical"), (ax_h, "Horizontal")):
            d = reference(stem + kind + ".dat")
            if d is not None:
                d = d[np.argsort(d[:, 0])]
                ax.plot(d[:, 0], np.abs(d[:, 1]) if kind == "Vertical" else d[:, 1], ".", ms=2, label=label)
    y = reference("yastrebov2011.dat")
    if y is not None:
        ax_v.plot(y[:, 0], np.abs(y[:, 2]), ".", ms=2, label="Yastrebov 2011")
        ax_h.plot(y[:, 0], y[:, 1], ".", ms=2, label="Yastrebov 2011")
    for label, results in runs:
        t, h, v = history(results)
        ax_v.plot(t, v, "-", lw=1.2, label=label)
        ax_h.plot(t, h, "-", lw=1.2, label=label)
        line = f"{label}: reached t = {t[-1]:.4f}"
        for tt in (1.0, 1.5):
            if t[-1] >= tt:
                vv, hh = np.interp(tt, t, v), np.interp(tt, t, h)
                line += f"; t = {tt}: V = {vv:.3f}e8, H = {hh:.3f}e8"
                if tt == 1.5:
                    line += f", H/V = {hh / vv:.3f}"
        if not np.isnan(oscillation(t, v)):
            line += f"; oscillation (RMS about the 0.1 running mean, t >= 1.1): V {oscillation(t, v):.4f}e8, " \
                    f"H {oscillation(t, h):.4f}e8"
        print(line)
    ax_v.set_title("vertical force V on the indenter (1e8)")
    ax_h.set_title("horizontal force H on the indenter (1e8)")
    for ax in (ax_v, ax_h):
        ax.set_xlabel("pseudo-time")
        ax.set_xlim(0, 2)
        ax.grid(True, alpha=0.3)
    ax_h.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print("figure:", out)


if __name__ == "__main__":
    main()
