#!/usr/bin/env python3
"""The validation report (issue 17, item 3): runs every shipped example (each deck carries its
reference values and their sources), then writes one HTML page with the table of every
check (computed, reference, error, tolerance, pass), the contact pressure profiles against
Hertz, the friction tractions against the Coulomb bound with the reference stick-zone
half-width (Cattaneo-Mindlin), and the Newton convergence of every run, from the runs'
summary.json and contact CSV files.

Usage: scripts/report.py [--build build] [--out results/report] [--only a,b] [--reuse]
(`make report` runs it on every example; --reuse skips the runs whose summary.json exists)."""
import argparse
import csv
import glob
import html
import json
import math
import os
import subprocess
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def last_contact_csv(run_dir):
    """The last increment's contact CSV of each pair: {pair: rows}."""
    out = {}
    for path in sorted(glob.glob(os.path.join(run_dir, "contact_*_*_*.csv"))):
        pair = os.path.basename(path)[len("contact_"):].rsplit("_", 2)[0]
        out[pair] = path  # sorted: the last one wins
    rows = {}
    for pair, path in out.items():
        with open(path) as f:
            rows[pair] = [r for r in csv.DictReader(f)]
    return rows


def check_value(summary, *starts):
    for c in summary.get("checks", []):
        if any(c["name"].lower().startswith(s) for s in starts):
            return c["expected"]
    return None


def pressure_plot(name, summary, rows, out_dir, three_d):
    """Nodal pressure against the distance from the first contact point, with Hertz's
    p0 sqrt(1 - (r/a)^2) when the deck gives p0 and a."""
    p0 = check_value(summary, "peak pressure")
    a = check_value(summary, "contact half-width", "contact radius")
    if not any(r["status"] not in ("far", "open") for r in rows):
        return None
    def dist(r):
        x, y = float(r["x"]), float(r["y"])
        return math.hypot(x, y) if three_d else abs(x)
    pts = sorted((dist(r), float(r["pressure"])) for r in rows if r["status"] != "far")
    fig, ax = plt.subplots(figsize=(5.5, 3.6))
    ax.plot([d for d, _ in pts], [p for _, p in pts], "o", ms=3, label="Signorini (nodal pressure)")
    if p0 and a:
        xs = [a * i / 200 for i in range(201)]
        ax.plot(xs, [p0 * math.sqrt(max(0.0, 1 - (x / a) ** 2)) for x in xs], "-", label="Hertz")
        ax.set_xlim(0, 2 * a)
    ax.set_xlabel("distance from the first contact point (r)" if three_d else "|x|")
    ax.set_ylabel("contact pressure")
    ax.set_title(name)
    ax.legend()
    fig.tight_layout()
    png = name + "_pressure.png"
    fig.savefig(os.path.join(out_dir, png), dpi=110)
    plt.close(fig)
    return png


def friction_plot(name, summary, rows, out_dir, mu):
    """Tangential traction against the Coulomb bound mu p, with the reference stick zone."""
    if not rows or "traction_x" not in rows[0]:
        return None
    pts = sorted((float(r["x"]), float(r["traction_x"]), float(r["pressure"])) for r in rows if r["status"] != "far")
    if not pts:
        return None
    fig, ax = plt.subplots(figsize=(5.5, 3.6))
    ax.plot([x for x, _, _ in pts], [abs(q) for _, q, _ in pts], "o", ms=3, label="|tangential traction|")
    if mu:
        ax.plot([x for x, _, _ in pts], [mu * p for _, _, p in pts], "-", label="Coulomb bound mu p")
    c = check_value(summary, "stick-zone half-width")
    a = check_value(summary, "contact half-width")
    for v, lab in ((c, "c"), (a, "a")):
        if v:
            ax.axvline(v, ls="--", lw=0.8, color="gray")
            ax.axvline(-v, ls="--", lw=0.8, color="gray")
            ax.text(v, 0, " " + lab + " (ref.)", fontsize=7, ha="left", va="bottom")
    if a:
        ax.set_xlim(-1.6 * a, 1.6 * a)
    ax.set_xlabel("x")
    ax.set_ylabel("traction")
    ax.set_title(name + ": stick zone inside, slip at the bound")
    ax.legend(fontsize=8)
    fig.tight_layout()
    png = name + "_friction.png"
    fig.savefig(os.path.join(out_dir, png), dpi=110)
    plt.close(fig)
    return png


def newton_plot(summaries, out_dir):
    """The relative residual of every Newton iteration of the increment with the most
    iterations, per example: the convergence rate at a glance."""
    fig, ax = plt.subplots(figsize=(7, 4.2))
    for name, s in summaries.items():
        incs = s.get("increments", [])
        if not incs:
            continue
        inc = max(incs, key=lambda i: len(i.get("residuals", [])))
        res = [r for r in inc.get("residuals", []) if r and r > 0]
        if len(res) > 1:
            ax.semilogy(range(len(res)), res, "-o", ms=2.5, lw=1, label=name)
    ax.set_xlabel("Newton iteration (the example's hardest increment)")
    ax.set_ylabel("|R| / F")
    ax.axhline(1e-8, ls="--", lw=0.8, color="gray")
    ax.legend(fontsize=6, ncol=2)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "newton.png"), dpi=110)
    plt.close(fig)
    return "newton.png"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=os.path.join(root, "build"))
    ap.add_argument("--out", default=os.path.join(root, "results", "report"))
    ap.add_argument("--only", default="", help="comma-separated example names")
    ap.add_argument("--reuse", action="store_true", help="keep runs whose summary.json exists")
    args = ap.parse_args()
    exe = os.path.join(args.build, "signorini")
    if not os.path.exists(exe):
        sys.exit("report: %s not found (make build)" % exe)
    decks = sorted(glob.glob(os.path.join(root, "examples", "*", "*.yaml")))
    decks = [d for d in decks if "/long/" not in d]
    if args.only:
        keep = set(args.only.split(","))
        decks = [d for d in decks if os.path.splitext(os.path.basename(d))[0] in keep]
        missing = keep - {os.path.splitext(os.path.basename(d))[0] for d in decks}
        if missing:
            sys.exit("report: no example named " + ", ".join(sorted(missing)))
    os.makedirs(args.out, exist_ok=True)
    summaries, rows_of, failures = {}, {}, []
    for deck in decks:
        name = os.path.splitext(os.path.basename(deck))[0]
        run_dir = os.path.join(args.out, "runs", name)
        summary_path = os.path.join(run_dir, "summary.json")
        if not (args.reuse and os.path.exists(summary_path)):
            t = time.time()
            p = subprocess.run([exe, "run", deck, "-q", "-o", run_dir], capture_output=True, text=True)
            print("report: %-28s exit %d, %.1f s" % (name, p.returncode, time.time() - t), flush=True)
            if p.returncode not in (0, 3):
                failures.append((name, (p.stderr or p.stdout)[-500:]))
        if not os.path.exists(summary_path):
            continue
        with open(summary_path) as f:
            summaries[name] = json.load(f)
        rows_of[name] = last_contact_csv(run_dir)
        with open(deck) as f:
            rows_of[name]["__deck__"] = f.read()

    # Plots.
    figures = []
    for name, s in summaries.items():
        deck_text = rows_of[name].pop("__deck__")
        mu = None
        if "mu:" in deck_text:
            try:
                mu = float(deck_text.split("mu:")[1].split(",")[0].split("}")[0])
            except ValueError:
                mu = None
        for pair, rows in rows_of[name].items():
            if check_value(s, "peak pressure"):
                png = pressure_plot(name, s, rows, args.out, s["analysis"]["dimension"] == "3d")
                if png:
                    figures.append((name, png, "contact pressure against Hertz"))
            if rows and "traction_x" in rows[0] and check_value(s, "stick-zone half-width"):
                png = friction_plot(name, s, rows, args.out, mu)
                if png:
                    figures.append((name, png, "tangential traction and the Coulomb bound"))
            break  # the first pair
    newton = newton_plot(summaries, args.out) if summaries else None

    # The page.
    passed = sum(c["pass"] for s in summaries.values() for c in s.get("checks", []))
    total = sum(len(s.get("checks", [])) for s in summaries.values())
    h = ["<!DOCTYPE html><html><head><meta charset='utf-8'><title>Signorini validation report</title>",
         "<style>body{font-family:sans-serif;max-width:1100px;margin:auto}table{border-collapse:collapse;"
         "font-size:13px}td,th{border:1px solid #ccc;padding:3px 6px}.fail{background:#fdd}.ok{background:#dfd}"
         "img{max-width:48%;margin:4px}</style></head><body>",
         "<h1>Signorini validation report</h1>",
         "<p>%d examples run, %d of %d reference checks pass (%s). Each reference and its source is "
         "in the example's deck and README; VALIDATION.md has the numbers.</p>"
         % (len(summaries), passed, total, time.strftime("%Y-%m-%d %H:%M"))]
    if failures:
        h.append("<h2>Runs that failed</h2><ul>")
        for name, err in failures:
            h.append("<li><b>%s</b>: <pre>%s</pre></li>" % (html.escape(name), html.escape(err)))
        h.append("</ul>")
    h.append("<h2>Checks</h2><table><tr><th>example</th><th>status</th><th>increments</th><th>Newton "
             "iterations</th><th>time (s)</th><th>check</th><th>computed</th><th>reference</th><th>error</th>"
             "<th>tolerance</th><th></th></tr>")
    for name, s in summaries.items():
        checks = s.get("checks", []) or [None]
        for k, c in enumerate(checks):
            cells = ""
            if k == 0:
                span = len(checks)
                cells = ("<td rowspan=%d>%s</td><td rowspan=%d>%s</td><td rowspan=%d>%d</td><td rowspan=%d>%d</td>"
                         "<td rowspan=%d>%.1f</td>" % (span, html.escape(name), span, s["status"], span,
                                                       len(s["increments"]), span, s["total_iterations"], span,
                                                       s["timings"]["total_s"]))
            if c is None:
                cells += "<td colspan=6>(no reference check)</td>"
            else:
                cells += ("<td>%s</td><td>%.6g</td><td>%.6g</td><td>%.3f %%</td><td>%.3g %%</td><td class='%s'>%s</td>"
                          % (html.escape(c["name"]), c["computed"], c["expected"], 100 * c["error"],
                             100 * c["tolerance"], "ok" if c["pass"] else "fail", "ok" if c["pass"] else "FAILED"))
            h.append("<tr>%s</tr>" % cells)
    h.append("</table>")
    if figures:
        h.append("<h2>Contact profiles</h2>")
        for name, png, what in figures:
            h.append("<img src='%s' alt='%s: %s'>" % (png, html.escape(name), html.escape(what)))
    if newton:
        h.append("<h2>Newton convergence</h2><p>The relative residual per iteration of each example's "
                 "hardest increment (tolerance 1e-8 dashed).</p><img src='%s' style='max-width:80%%'>" % newton)
    h.append("</body></html>")
    page = os.path.join(args.out, "index.html")
    with open(page, "w") as f:
        f.write("\n".join(h))
    print("report: %s (%d examples, %d/%d checks pass, %d figures)" % (page, len(summaries), passed, total,
                                                                        len(figures) + (1 if newton else 0)))
    return 1 if failures or passed < total else 0


if __name__ == "__main__":
    sys.exit(main())
