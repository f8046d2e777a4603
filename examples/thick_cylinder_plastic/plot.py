#!/usr/bin/python3
"""J2 plasticity curves against their closed forms, from the CSV files the verification tests
write in build/curves/ (Plasticity.ThickCylinderFollowsHill*, Viscoplasticity.BarFollows*):

  - the thick-walled cylinder (VALIDATION.md sec. 8): applied pressure against the outer
    radius' displacement u(b), small and finite strain, with Hill's (1950) solution, and the
    plastic front against Hill's;
  - the viscoplastic bar (examples/viscoplastic_bar): stress against time at a constant strain
    rate, then held, with the Perzyna closed form.

    plot.py OUT.png [CURVES_DIR (default build/curves)]
"""
import csv
import math
import os
import sys

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

A, B, E, NU, SY = 0.1, 0.2, 210e9, 0.3, 240e6
K = SY / math.sqrt(3)
PLIM = 2 / math.sqrt(3) * SY * math.log(B / A)


def hill_pressure(c):
    return K * (1 - c * c / (B * B) + 2 * math.log(c / A))


def hill_u(c):
    return 2 * (1 - NU * NU) * K * c * c / (E * B)


def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def main():
    out = sys.argv[1]
    here = os.path.dirname(os.path.abspath(__file__))
    curves = sys.argv[2] if len(sys.argv) > 2 else os.path.join(here, "..", "..", "build", "curves")
    fig, ax = plt.subplots(1, 3, figsize=(16, 4.6))
    # Hill: elastic line up to first yield, then parametrised by the front c.
    py = hill_pressure(A)
    cs = np.linspace(A, B * 0.9999, 400)
    p_el = np.linspace(0, py, 20)
    u_el = 2 * p_el * A * A * B * (1 - NU * NU) / (E * (B * B - A * A))
    ph = np.r_[p_el, [hill_pressure(c) for c in cs]]
    uh = np.r_[u_el, [hill_u(c) for c in cs]]
    ax[0].plot(uh * 1e3, ph / PLIM, "k-", label="Hill 1950")
    ax[1].plot([hill_pressure(c) / PLIM for c in cs], cs * 1e3, "k-", label="Hill 1950")
    for name, label, marker in (("thick_cylinder_small", "small strain", "o"), ("thick_cylinder_finite", "finite strain", "s")):
        path = os.path.join(curves, name + ".csv")
        if not os.path.exists(path):
            continue
        d = read(path)
        ax[0].plot(d["u_b"] * 1e3, d["p"] / PLIM, marker, ms=4, mfc="none", label=label)
        yielded = d["front"] > A
        ax[1].plot(d["p"][yielded] / PLIM, d["front"][yielded] * 1e3, marker, ms=4, mfc="none", label=label)
    ax[0].axhline(1, color="0.6", lw=0.8)
    ax[0].set_xlabel("u(b) (mm)")
    ax[0].set_ylabel("p / p_lim")
    ax[0].set_title("thick cylinder: pressure and outer displacement")
    ax[1].set_xlabel("p / p_lim")
    ax[1].set_ylabel("plastic front c (mm; outermost yielded cell)")
    ax[1].set_title("thick cylinder: plastic front")
    path = os.path.join(curves, "viscoplastic_bar.csv")
    if os.path.exists(path):
        d = read(path)
        Eb, syb, eta, rate = 200e3, 200.0, 5000.0, 1e-4
        tc, ty, sss = eta * syb / Eb, syb / (Eb * rate), syb * (1 + eta * rate)
        t = np.linspace(0, 150, 1500)
        s100 = sss + (syb - sss) * math.exp(-(100 - ty) / tc)
        exact = np.where(t <= ty, Eb * rate * t,
                         np.where(t <= 100, sss + (syb - sss) * np.exp(-(t - ty) / tc),
                                  syb + (s100 - syb) * np.exp(-(t - 100) / tc)))
        ax[2].plot(t, exact, "k-", label="closed form (Perzyna, m = 1)")
        ax[2].plot(d["t"][::10], d["stress"][::10], "o", ms=3, mfc="none", label="computed (every 10th increment)")
        ax[2].axhline(syb, color="0.6", lw=0.8)
        ax[2].set_xlabel("t (s)")
        ax[2].set_ylabel("stress (MPa)")
        ax[2].set_title("viscoplastic bar: pull at 1e-4/s, then hold")
    for x in ax:
        x.grid(alpha=0.3)
        x.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
