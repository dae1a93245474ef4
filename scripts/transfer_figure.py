#!/usr/bin/env python3
"""transfer_figure.py RESULTS [OUT.svg]: the figure and tables of docs/results.md, "Transfer across bodies".

Reads the summary.csv and report.json of a `roger run scripts/transfer.lua` results folder and draws,
for each body of the family, the success rate of the paper's T/DC6 policies run without retraining
(b) and over a Phi_SG retrained on that body (c), in the open arena and among 3 obstacles: the mean
over the run's policies, with whiskers from the worst to the best policy. Then prints, as Markdown:
the table of (b) and (c) per body with each cell's pooled success rate and its 95% interval from
report.json (the evaluation tables' Total rows: a bootstrap that resamples whole policies,
docs/batch.md), the retrained SG/DC2's mean time-to-threshold per body, and the maturation table
(d). A trial that never reached its threshold counts with its whole training time, and the mean is
then marked "≥". A partial folder (trials failed, or without a result yet) is drawn all the same,
from the trials with results, but says so: a warning on stderr naming the evaluations and runs
concerned, their cells marked "(1 failed)", "(2 pending)", and in the figure a note and a "*" over
their bars. Everything is read and computed before the SVG is written, atomically. Standard
library only.
"""
import csv
import os
import sys
from collections import defaultdict

sys.dont_write_bytecode = True  # results_common, imported below, leaves no __pycache__ in scripts/
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # its folder: also when loaded by path or run with -P
from results_common import (marked, partial_of, partial_warning, read_report, require_svg_path, total_rows, without,
                            without_result, write_atomically)

NAME = "transfer_figure.py"  # in the messages of results_common's functions
BODIES = ["long_arms", "short_arms", "wide_base", "small", "big_hands", "coarse_eyes", "wide_eyes", "frozen_eyes"]
SERIES = [("b", "open", "#7da7d9", "(b) open"), ("c", "open", "#1f4e8c", "(c) open"),
          ("b", "clutter", "#f3b27a", "(b) 3 obstacles"), ("c", "clutter", "#c0571b", "(c) 3 obstacles")]


def read_rates(path):
    """Per evaluation of summary.csv: the success rates of its trials with a result."""
    rates = defaultdict(list)
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            if row["kind"] == "eval" and row["status"] == "ok":
                rates[row["evaluation"]].append(float(row["success_rate"]))
    return rates


def read_training(path):
    """Per run/context of summary.csv: the trials' times-to-threshold (s), whether each reached it,
    and their final success rates. A trial that never reached its threshold has no time-to-threshold
    (summary.csv leaves it empty): its whole training time (train_sim_s) stands in, a lower bound."""
    runs = defaultdict(lambda: {"times": [], "reached": [], "success": []})
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            if row["kind"] == "train" and row["status"] == "ok":
                r = runs[row["run"] + "/" + row["context"]]
                reached = row["reached"] == "true" and row["time_to_threshold_s"] != ""
                r["times"].append(float(row["time_to_threshold_s"] if reached else row["train_sim_s"]))
                r["reached"].append(reached)
                r["success"].append(float(row["success_rate"]))
    return runs


def warning(results, report, missing):
    """The stderr warning of a folder with trials without results, or '': the rates pool the others."""
    lines = [f"  evaluation {e}: {without(m)}" for e, m in sorted(missing["eval"].items())]
    lines += [f"  training {k}: {without(m)}" for k, m in sorted(missing["train"].items())]
    return partial_warning(NAME, results, report, lines, "the evaluations and runs tabulated here",
                           "the rates below pool only the trials with results, leaving out (cells marked so)")


def min_sec(seconds):
    s = int(seconds + 0.5)  # half away from zero, as the engine's tables round (Python's round is to even)
    return f"{s // 60}:{s % 60:02d}"


def cell(row):
    """'99.3% [98.6, 99.7]': a pooled success rate and its 95% interval, in percent."""
    if not row or "success_rate" not in row:  # no row, or a Total of counts alone (no result yet)
        return "-"
    hi = 100 * row["success_high"]
    return f"{100 * row['success_rate']:.1f}% [{100 * row['success_low']:.1f}, {'100' if hi >= 99.95 else f'{hi:.1f}'}]"


def mean_time(run):
    """The mean time-to-threshold of a run's trials, marked >= when some never reached it."""
    if not run or not run["times"]:
        return "-"
    m = min_sec(sum(run["times"]) / len(run["times"]))
    return m if all(run["reached"]) else "≥ " + m


def tables(totals, runs, missing):
    ev = lambda name: marked(cell(totals.get(name)), missing["eval"].get(name))
    tr = lambda key, text=None: marked(mean_time(runs.get(key)) if text is None else text, missing["train"].get(key))
    out = ["| body | (b) open | (c) open | (b) 3 obstacles | (c) 3 obstacles | SG/DC2 retrained: time-to-threshold (mean) |",
           "|---|---|---|---|---|---|"]
    for body in BODIES:
        cells = [ev(f"{k}_{body}_{w}") for k, w in (("b", "open"), ("c", "open"), ("b", "clutter"), ("c", "clutter"))]
        out.append(f"| {body.replace('_', ' ')} | " + " | ".join(cells) + f" | {tr(f'SG_{body}/DC2')} |")
    out += ["", "| curriculum | SG/DC2 time-to-threshold | T/DC6 time-to-threshold | T/DC6 final success |", "|---|---|---|---|"]
    for label, sg, t in (("the paper's (full body throughout)", "SG", "T"),
                         ("SG with coarse eyes (32 px, 60 degrees), T full", "SG_coarse", "T_coarse"),
                         ("SG with frozen eyes, T full", "SG_frozen", "T_frozen")):
        t6 = runs.get(f"{t}/DC6")
        success = f"{100 * sum(t6['success']) / len(t6['success']):.1f}%" if t6 and t6["success"] else "-"
        out.append(f"| {label} | {tr(f'{sg}/DC2')} | {tr(f'{t}/DC6')} | {tr(f'{t}/DC6', success)} |")
    return "\n".join(out)


def svg(rates, partial="", short=()):
    """The figure. partial: partial_of(report.json); short: the evaluations with trials without a
    result, whose bars get a "*"."""
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
                if f"{kind}_{body}_{world}" in short:  # no bar at all: the "*" says why
                    out.append(f'<text x="{x0 + (j + 0.45) * bar:.1f}" y="{y(lo) - 3:.1f}" text-anchor="middle" '
                               'fill="#b00">*</text>')
                continue
            mean = sum(vals) / len(vals)
            x = x0 + j * bar
            out.append(f'<rect x="{x:.1f}" y="{y(mean):.1f}" width="{bar * 0.9:.1f}" '
                       f'height="{top + plot_h - y(mean):.1f}" fill="{colour}"/>')
            cx = x + bar * 0.45
            out.append(f'<line x1="{cx:.1f}" x2="{cx:.1f}" y1="{y(min(vals)):.1f}" y2="{y(max(vals)):.1f}" stroke="#333"/>')
            if f"{kind}_{body}_{world}" in short:
                out.append(f'<text x="{cx:.1f}" y="{y(max(vals)) - 3:.1f}" text-anchor="middle" fill="#b00">*</text>')
        out.append(f'<text x="{left + (i + 0.5) * group:.1f}" y="{top + plot_h + 18}" text-anchor="middle">'
                   f'{body.replace("_", " ")}</text>')
    for j, (_, _, colour, label) in enumerate(SERIES):
        lx = left + j * 200
        out.append(f'<rect x="{lx}" y="{h - 40}" width="14" height="14" fill="{colour}"/>')
        out.append(f'<text x="{lx + 20}" y="{h - 28}">{label}</text>')
    out.append(f'<text x="{left}" y="{h - 8}" fill="#555">(b) the policy and its Phi_SG as learned; '
               '(c) over a Phi_SG retrained on the body. Bars: mean over policies; whiskers: worst and best policy.</text>')
    if any("fill=\"#b00\">*</text>" in line for line in out):
        # In the picture too: a figure travels without the stderr that came with it.
        out.append(f'<text x="{w - 20}" y="35" text-anchor="end" fill="#b00" font-size="11">partial results'
                   f'{": " + partial if partial else ""}; * bars: only the trials with results</text>')
    out.append("</svg>")
    return "\n".join(out) + "\n"


def main():
    if len(sys.argv) not in (2, 3):
        print("usage: transfer_figure.py RESULTS_FOLDER [OUT.svg]", file=sys.stderr)
        sys.exit(2)
    # One line, as the other figure scripts say it (found by a probe: a Python traceback).
    if not os.path.isfile(os.path.join(sys.argv[1], "summary.csv")):
        sys.exit(f"transfer_figure: {sys.argv[1]} is not a results folder of roger run (no summary.csv)")
    summary = sys.argv[1] + "/summary.csv"
    rates = read_rates(summary)
    if not any(k.startswith(("b_", "c_")) for k in rates):
        waiting = [m for e, m in without_result(sys.argv[1])["eval"].items() if e.startswith(("b_", "c_"))]
        if waiting:  # planned, none with a result: not the folder of another script
            sys.exit(f"{summary}: no evaluation of scripts/transfer.lua has a result yet "
                     f"({without({k: sum(m[k] for m in waiting) for k in ('failed', 'pending')})})")
        sys.exit(f"{sys.argv[1]}/summary.csv holds no evaluation of scripts/transfer.lua")
    out = sys.argv[2] if len(sys.argv) == 3 else sys.argv[1] + "/transfer.svg"
    require_svg_path("transfer_figure", out)
    # Everything before the one file written: a folder the tables cannot read leaves no figure behind.
    report = read_report(sys.argv[1])
    totals = total_rows(report)
    missing = without_result(sys.argv[1], report)
    text = tables(totals, read_training(summary), missing)
    picture = svg(rates, partial_of(report), set(missing["eval"]))
    if warning(sys.argv[1], report, missing):
        print(warning(sys.argv[1], report, missing), file=sys.stderr)
    write_atomically(out, picture)
    print("wrote", out)
    print()
    print(text)


if __name__ == "__main__":
    main()
