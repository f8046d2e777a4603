"""Hertz contact of a cylinder on a block, from Python: a small mesh study of the peak
pressure against Hertz's p0 (VALIDATION.md sec. 1). Run from the repository's root after
`make build`:  PYTHONPATH=build/python python3 examples/python/hertz_cylinder.py"""
import os

import yaml

import signorini

here = os.path.dirname(os.path.abspath(__file__))
example = os.path.join(here, "..", "hertz_cylinder")
with open(os.path.join(example, "hertz_cylinder.yaml")) as f:
    deck = yaml.safe_load(f)
deck["mesh"]["file"] = os.path.join(example, deck["mesh"]["file"])  # a dict's paths are from the current directory
p0 = next(c["expected"] for c in deck["checks"] if c["quantity"] == "contact_pressure_max")

signorini.set_log_level("warning")
print("   hc    nodes  increments  p0 (computed)  error vs Hertz")
for hc in (0.02, 0.01, 0.005):
    deck["mesh"]["parameters"]["hc"] = hc
    r = signorini.run(deck, progress=None)
    if not r.completed:
        print(f"{hc:5.3f}  gave up: {r.failure}")
        continue
    pair = next(iter(r.contact.values()))
    pmax = pair.pressure[pair.status >= 2].max()
    print(f"{hc:5.3f} {r.coordinates.shape[0]:8d} {r.increments:11d}  {pmax:13.5g}  {100 * (pmax - p0) / p0:+8.2f} %")
