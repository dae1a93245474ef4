#!/usr/bin/env python3
"""transfer_figure.py RESULTS [OUT.svg]: the figure and tables of docs/results.md, "Transfer across bodies".

Reads the summary.csv and report.json of a `roger run scripts/transfer.lua` results folder and draws,
for each body of the family, the success rate of the paper's T/DC6 policies run without retraining
(b) and over a Phi_SG retrained on that body (c), in the open arena and among 3 obstacles: the mean
over the run's policies, with whiskers from the worst to the best policy. Then prints, as Markdown:
the table of (b) and (c) per body with each cell's pooled success rate and its 95% interval from
report.json (the evaluation tables' Total rows: a bootstrap that resamples whole policies,
docs/batch.md), the retrained SG/DC2's mean time-to-threshold per body, and the maturation table
(d). Standard library only.
"""
import csv
import json
import os
import sys
from collections import defaultdict

BODIES = ["long_arms", "short_arms", "wide_base", "small", "big_hands", "coarse_eyes", "wide_eyes", "frozen_eyes"]
SERIES = [("b", "open", "#7da7d9", "(b) open"), ("c", "open", "#1f4e8c", "(c) open"),
          ("b", "clutter", "#f3b27a", "(b) 3 obstacles"), ("c", "clutter", "#c0571b", "(c) 3 obstacles")]


def read_rates(path):
    rates = defaultdict(list)
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            if row["kind"] == "eval" and row["status"] == "ok":
                rates[row["evaluation"]].append(float(row["success_rate"]))
    return rates


def read_training(path):
    """Per run/context of summary.csv: the trials' times-to-threshold (s), whether each reached it,
    and their final success rates."""
    runs = defaultdict(lambda: {"times": [], "reached": [], "success": []})
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            if row["kind"] == "train" and row["status"] == "ok":
                r = runs[row["run"] + "/" + row["context"]]
                r["times"].append(float(row["time_to_threshold_s"]))
                r["reached"].append(row["reached"] == "true")
                r["success"].append(float(row["success_rate"]))
    return runs


def read_totals(path):
    """Per evaluation: the Total row of its table in report.json."""
    with open(path) as f:
        tables = json.load(f)["tables"]
    totals = {}
    for t in tables:
        rows = [r for r in t.get("rows", []) if r.get("object") == "Total"]
        if t.get("evaluation") and rows:
            totals[t["evaluation"]] = rows[0]
    return totals


def min_sec(seconds):
    s = int(seconds + 0.5)  # half away from zero, as the engine's tables round (Python's round is to even)
    return f"{s // 60}:{s % 60:02d}"


def cell(row):
    """'99.3% [98.6, 99.7]': a pooled success rate and its 95% interval, in percent."""
    if not row:
        return "-"
    hi = 100 * row["success_high"]
    return f"{100 * row['success_rate']:.1f}% [{100 * row['success_low']:.1f}, {'100' if hi >= 99.95 else f'{hi:.1f}'}]"


def mean_time(run):
    """The mean time-to-threshold of a run's trials, marked >= when some never reached it."""
    if not run or not run["times"]:
        return "-"
    m = min_sec(sum(run["times"]) / len(run["times"]))
    return m if all(run["reached"]) else "≥ " + m


def tables(totals, runs):
    out = ["| body | (b) open | (c) open | (b) 3 obstacles | (c) 3 obstacles | SG/DC2 retrained: time-to-threshold (mean) |",
           "|---|---|---|---|---|---|"]
    for body in BODIES:
        cells = [cell(totals.get(f"{k}_{body}_{w}")) for k, w in (("b", "open"), ("c", "open"), ("b", "clutter"), ("c", "clutter"))]
        out.append(f"| {body.replace('_', ' ')} | " + " | ".join(cells) + f" | {mean_time(runs.get(f'SG_{body}/DC2'))} |")
    out += ["", "| curriculum | SG/DC2 time-to-threshold | T/DC6 time-to-threshold | T/DC6 final success |", "|---|---|---|---|"]
    for label, sg, t in (("the paper's (full body throughout)", "SG", "T"),
                         ("SG with coarse eyes (32 px, 60 degrees), T full", "SG_coarse", "T_coarse"),
                         ("SG with frozen eyes, T full", "SG_frozen", "T_frozen")):
        tr = runs.get(f"{t}/DC6")
        success = f"{100 * sum(tr['success']) / len(tr['success']):.1f}%" if tr and tr["success"] else "-"
        out.append(f"| {label} | {mean_time(runs.get(f'{sg}/DC2'))} | {mean_time(tr)} | {success} |")
    return "\n".join(out)


def svg(rates):
    w, h, left, top, bottom = 980, 420, 60, 40, 90
    plot_w, plot_h = w - left - 20, h - top - bottom
    lo = 0.8  # the axis starts at 80%: every rate lies above it
    y = lambda r: top + plot_h * (1 - (r - lo) / (1 - lo))
    group = plot_w / len(BODIES)
    bar = group / (len(SERIES) + 1)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12">',
           f'<rect width="{w}" height="{h}" fill="white"/>',
           f'<text x="{left}" y="22" font-size="15" font-weight="bold">Transfer across bodies: T/DC6 learned on the paper\'s Roger</text>']
    for k in range(5):
        r = lo + k * (1 - lo) / 4
        out.append(f'<line x1="{left}" x2="{w - 20}" y1="{y(r):.1f}" y2="{y(r):.1f}" stroke="#ddd"/>')
        out.append(f'<text x="{left - 6}" y="{y(r) + 4:.1f}" text-anchor="end">{100 * r:.0f}%</text>')
    for i, body in enumerate(BODIES):
        x0 = left + i * group + bar / 2
        for j, (kind, world, colour, _) in enumerate(SERIES):
            vals = rates.get(f"{kind}_{body}_{world}", [])
            if not vals:
                continue
            mean = sum(vals) / len(vals)
            x = x0 + j * bar
            out.append(f'<rect x="{x:.1f}" y="{y(mean):.1f}" width="{bar * 0.9:.1f}" '
                       f'height="{top + plot_h - y(mean):.1f}" fill="{colour}"/>')
            cx = x + bar * 0.45
            out.append(f'<line x1="{cx:.1f}" x2="{cx:.1f}" y1="{y(min(vals)):.1f}" y2="{y(max(vals)):.1f}" stroke="#333"/>')
        out.append(f'<text x="{left + (i + 0.5) * group:.1f}" y="{top + plot_h + 18}" text-anchor="middle">'
                   f'{body.replace("_", " ")}</text>')
    for j, (_, _, colour, label) in enumerate(SERIES):
        lx = left + j * 200
        out.append(f'<rect x="{lx}" y="{h - 40}" width="14" height="14" fill="{colour}"/>')
        out.append(f'<text x="{lx + 20}" y="{h - 28}">{label}</text>')
    out.append(f'<text x="{left}" y="{h - 8}" fill="#555">(b) the policy and its Phi_SG as learned; '
               '(c) over a Phi_SG retrained on the body. Bars: mean over policies; whiskers: worst and best policy.</text>')
    out.append("</svg>")
    return "\n".join(out) + "\n"


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit("usage: transfer_figure.py RESULTS_FOLDER [OUT.svg]")
    rates = read_rates(sys.argv[1] + "/summary.csv")
    if not any(k.startswith(("b_", "c_")) for k in rates):
        sys.exit(f"{sys.argv[1]}/summary.csv holds no evaluation of scripts/transfer.lua")
    report = os.path.join(sys.argv[1], "report.json")
    if not os.path.exists(report):
        sys.exit(f"{report} does not exist: run `roger report {sys.argv[1]}` first")
    out = sys.argv[2] if len(sys.argv) == 3 else sys.argv[1] + "/transfer.svg"
    with open(out + ".tmp", "w") as f:
        f.write(svg(rates))
    os.replace(out + ".tmp", out)
    print("wrote", out)
    print()
    print(tables(read_totals(report), read_training(sys.argv[1] + "/summary.csv")))


if __name__ == "__main__":
    main()
