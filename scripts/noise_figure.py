#!/usr/bin/env python3
"""noise_figure.py RESULTS [OUT.svg] [--roger PATH]: the figure of docs/results.md, "Noise".

Success against the scale of the moderate noise M (0, 0.5, 1, 2, 4, 8) for
  - the scripted task, unobstructed and in clutter: `roger eval curricula/scripted.lua --policy task`,
    200 episodes per point from seed 9200000 (run here; the figures go to RESULTS/scripted_noise.json);
  - Table III's noise-free T/DC6 policies: the evaluations III_x<scale> of a `roger run
    scripts/noise.lua` results folder, every policy's episodes pooled: the Total rows of its
    report.json, with the interval `roger report` gives them (a bootstrap that resamples whole
    policies, and layouts wherever policies share them: docs/batch.md).
Each scripted point has its 95% Wilson interval (one policy, distinct worlds: the worlds are the
draws). Standard library only; writes the SVG atomically.
"""
import json
import math
import os
import subprocess
import sys

SCALES = [0, 0.5, 1, 2, 4, 8]
M = {"noise_image": "10", "noise_joints": "0.01", "noise_base": "0.01", "noise_touch": "0.1", "noise_effort": "0.1"}
SERIES = [("scripted, unobstructed", "#1f4e8c"), ("scripted, cluttered", "#7da7d9"),
          ("T/DC6 policies, 3 obstacles", "#c0571b")]


def wilson(k, n, z=1.959964):
    """The 95% Wilson score interval of k successes in n draws."""
    if n == 0:
        return 0.0, 0.0
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return max(0.0, c - h), min(1.0, c + h)


def scale_name(s):
    return str(s).replace(".", "_")


def scripted(roger, scenario, scale):
    """(successes, episodes) of the scripted task at one scale."""
    cmd = [roger, "eval", "curricula/scripted.lua", "--policy", "task", "--scenario", scenario,
           "--episodes", "200", "--seed", "9200000", "--json", "--set", f"noise_scale={scale}"]
    for k, v in M.items():
        cmd += ["--set", f"{k}={v}"]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    r = json.loads(out.strip().splitlines()[-1])
    return r["successes"], r["episodes"]


def table_three(results):
    """(successes, episodes, low, high) per scale of the noise-free T/DC6 policies: the Total row of
    each evaluation III_x<scale> in RESULTS/report.json (written by roger run or roger report)."""
    path = os.path.join(results, "report.json")
    if not os.path.exists(path):
        sys.exit(f"{path} does not exist: run `roger report {results}` first")
    with open(path) as f:
        tables = json.load(f)["tables"]
    points = {}
    for s in SCALES:
        for t in tables:
            if t.get("evaluation") != f"III_x{scale_name(s)}":
                continue
            total = [r for r in t["rows"] if r["object"] == "Total"]
            if not total or "success_low" not in total[0]:
                sys.exit(f"{path}: evaluation III_x{scale_name(s)} has no Total row with an interval (not run "
                         "yet?); the figure needs every III_x* evaluation of scripts/noise.lua: run them all "
                         "(without --only, or with an --only eval/III_x... for each)")
            r = total[0]
            n = r["episodes"]
            points[s] = (round(r["success_rate"] * n), n, r["success_low"], r["success_high"])
    return points


def with_wilson(pts):
    """The scripted series: (successes, episodes) with their Wilson interval."""
    return {s: (k, n) + wilson(k, n) for s, (k, n) in pts.items()}


def svg(points):
    w, h, left, top, bottom = 760, 440, 60, 40, 80
    plot_w, plot_h = w - left - 30, h - top - bottom
    x = lambda i: left + plot_w * i / (len(SCALES) - 1)
    y = lambda r: top + plot_h * (1 - r)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12">',
           f'<rect width="{w}" height="{h}" fill="white"/>',
           f'<text x="{left}" y="22" font-size="15" font-weight="bold">Success against the scale of the noise M</text>']
    for k in range(6):
        r = k / 5
        out.append(f'<line x1="{left}" x2="{w - 30}" y1="{y(r):.1f}" y2="{y(r):.1f}" stroke="#ddd"/>')
        out.append(f'<text x="{left - 6}" y="{y(r) + 4:.1f}" text-anchor="end">{100 * r:.0f}%</text>')
    for i, s in enumerate(SCALES):
        out.append(f'<text x="{x(i):.1f}" y="{top + plot_h + 18}" text-anchor="middle">{s} M</text>')
    for (label, colour) in SERIES:
        pts = points.get(label, {})
        line = [(x(SCALES.index(s)), y(k / n)) for s, (k, n, _, _) in sorted(pts.items()) if n]
        if line:
            out.append(f'<polyline fill="none" stroke="{colour}" stroke-width="2" points="' +
                       " ".join(f"{a:.1f},{b:.1f}" for a, b in line) + '"/>')
        for s, (k, n, lo, hi) in pts.items():
            if not n:
                continue
            cx = x(SCALES.index(s))
            out.append(f'<line x1="{cx:.1f}" x2="{cx:.1f}" y1="{y(lo):.1f}" y2="{y(hi):.1f}" stroke="{colour}"/>')
            out.append(f'<circle cx="{cx:.1f}" cy="{y(k / n):.1f}" r="3.5" fill="{colour}"/>')
    for j, (label, colour) in enumerate(SERIES):
        lx = left + j * 230
        out.append(f'<rect x="{lx}" y="{h - 52}" width="14" height="14" fill="{colour}"/>')
        out.append(f'<text x="{lx + 20}" y="{h - 40}">{label}</text>')
    # Two lines: one would run past the picture's right edge.
    out.append(f'<text x="{left}" y="{h - 14}" fill="#555" font-size="11">M = image 10 levels, joints 0.01 rad, '
               'base 0.01 m/rad, touch 0.1, effort 0.1.</text>')
    out.append(f'<text x="{left}" y="{h - 2}" fill="#555" font-size="11">Whiskers: 95% intervals (policies: '
               'resampled by policy and shared layout; scripted: Wilson).</text>')
    out.append("</svg>")
    return "\n".join(out) + "\n"


def default_roger():
    """The engine built beside this script (the source tree's build/engine/roger), else roger on PATH."""
    built = os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "build", "engine", "roger")
    return built if os.access(built, os.X_OK) else "roger"


def main():
    args = [a for a in sys.argv[1:]]
    roger = default_roger()
    if "--roger" in args:
        i = args.index("--roger")
        roger = args[i + 1]
        del args[i:i + 2]
    if len(args) not in (1, 2):
        sys.exit("usage: noise_figure.py RESULTS_FOLDER [OUT.svg] [--roger PATH]")
    results = args[0]
    table = table_three(results)
    if not table:
        sys.exit(f"{results} holds no evaluation III_x... of scripts/noise.lua (trials/eval/III_x*)")
    points = {SERIES[2][0]: table}
    for label, scenario in ((SERIES[0][0], "unobstructed"), (SERIES[1][0], "cluttered")):
        points[label] = with_wilson({s: scripted(roger, scenario, s) for s in SCALES})
    with open(os.path.join(results, "scripted_noise.json"), "w") as f:
        json.dump({label: {str(s): {"successes": k, "episodes": n, "low": lo, "high": hi} for s, (k, n, lo, hi) in pts.items()}
                   for label, pts in points.items()}, f, indent=1)
    out = args[1] if len(args) == 2 else os.path.join(results, "noise.svg")
    with open(out + ".tmp", "w") as f:
        f.write(svg(points))
    os.replace(out + ".tmp", out)
    print("wrote", out)
    for label, pts in points.items():
        print(label + ": " + ", ".join(f"{s} M {100 * k / n:.1f}% ({k}/{n}) [{100 * lo:.1f}, {100 * hi:.1f}]"
                                       for s, (k, n, lo, hi) in sorted(pts.items()) if n))


if __name__ == "__main__":
    main()
