#!/usr/bin/env python3
"""transfer_figure.py RESULTS [OUT.svg]: the figure of docs/results.md, "Transfer across bodies".

Reads the summary.csv of a `roger run scripts/transfer.lua` results folder and draws, for each body
of the family, the success rate of the paper's T/DC6 policies run without retraining (b) and over a
Phi_SG retrained on that body (c), in the open arena and among 3 obstacles: the mean over the
run's policies, with whiskers from the worst to the best policy. Standard library only.
"""
import csv
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
    out = sys.argv[2] if len(sys.argv) == 3 else sys.argv[1] + "/transfer.svg"
    with open(out + ".tmp", "w") as f:
        f.write(svg(rates))
    import os
    os.replace(out + ".tmp", out)
    print("wrote", out)


if __name__ == "__main__":
    main()
