#!/usr/bin/python3
"""Drag force of the shoe over the mound of coarse quads (tests/verification/test_smoothing_3d.cpp),
faceted against smoothed master (smoothing: hermite, bicubic patches).

    SIGNORINI_SMOOTHING_CSV=/tmp/smoothing_3d.csv build/tests/verification_tests --gtest_filter='Smoothing3D*'
    /usr/bin/python3 tests/verification/plot_smoothing_3d.py /tmp/smoothing_3d.csv docs/figures/smoothing_3d.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

rows = list(csv.DictReader(open(sys.argv[1])))
ux = [float(r["ux"]) for r in rows]
plt.figure(figsize=(6.5, 4))
plt.plot(ux, [float(r["H_faceted"]) for r in rows], "-", lw=1, label="faceted quads")
plt.plot(ux, [float(r["H_smoothed"]) for r in rows], "-", lw=1.5, label="smoothing: hermite (bicubic patches)")
for x in (0.5, 1.0, 1.5, 2.0, 2.5, 3.0):
    plt.axvline(x - 0.5, color="0.85", lw=0.6, zorder=0)
plt.xlabel("shoe displacement along x (facet edges every 0.5)")
plt.ylabel("horizontal force H on the shoe's top")
plt.title("Dragging a shoe over a mound of 0.5 x 0.25 quads (3D, frictionless)")
plt.legend(fontsize=8)
plt.tight_layout()
plt.savefig(sys.argv[2], dpi=120)
print("figure:", sys.argv[2])
