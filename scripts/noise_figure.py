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
draws). A partial folder (report.json's "partial": trials failed or without a result yet) is drawn
all the same, from the trials with results, but says so: a warning on stderr, the policies' points
concerned marked "(1 failed)", "(2 pending)" in the lines printed and "*" in the figure, with a
note. The roger program: --roger, else $ROGER, else the source tree's build/engine/roger, else
roger on PATH. Standard library only; everything is computed first, then each file written
atomically.
"""
import json
import math
import os
import sys

sys.dont_write_bytecode = True  # results_common, imported below, leaves no __pycache__ in scripts/
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # its folder: also when loaded by path or run with -P
import results_common
from results_common import (find_roger, marked, percent, read_report, require_results_folder, require_svg_path,
                            run_roger, without, write_atomically)

NAME = "noise_figure.py"  # in the messages of results_common's functions
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
    r = json.loads(run_roger(NAME, cmd).strip().splitlines()[-1])
    return r["successes"], r["episodes"]


def table_three(results):
    """(successes, episodes, low, high) per scale of the noise-free T/DC6 policies: the Total row of
    each evaluation III_x<scale> in RESULTS/report.json (written by roger run or roger report)."""
    path = os.path.join(results, "report.json")
    tables = read_report(results)["tables"]
    points = {}
    for s in SCALES:
        for t in tables:
            if t.get("evaluation") != f"III_x{scale_name(s)}":
                continue
            total = [r for r in t.get("rows", []) if r.get("object") == "Total"]
            if not total or "success_low" not in total[0]:
                sys.exit(f"{path}: evaluation III_x{scale_name(s)} has no Total row with an interval (not run "
                         "yet?); the figure needs every III_x* evaluation of scripts/noise.lua: run them all "
                         "(without --only, or with an --only eval/III_x... for each)")
            r = total[0]
            n = r["episodes"]
            points[s] = (round(r["success_rate"] * n), n, r["success_low"], r["success_high"])
    return points


def left_out(results):
    """{scale: {"failed": n, "pending": m}} of the evaluations III_x<scale> with trials without a
    result, which their points leave out (results_common.without_result)."""
    names = {f"III_x{scale_name(s)}": s for s in SCALES}
    missing = results_common.without_result(results, read_report(results))["eval"]
    return {names[e]: m for e, m in missing.items() if e in names}


def partial_of(results):
    """'of 14 trials, 1 failed' when RESULTS/report.json says the folder is partial, else ''."""
    return results_common.partial_of(read_report(results))


def warning(results, missing):
    """The stderr warning of a partial folder, or '': the policies' points pool the other trials."""
    lines = [f"  evaluation III_x{scale_name(s)}: {without(m)}" for s, m in sorted(missing.items())]
    return results_common.partial_warning(
        NAME, results, read_report(results), lines, "the evaluations III_x* drawn here",
        "the policies' points below pool only the trials with results, leaving out (marked so)")


def printed(points, missing):
    """The lines printed: each series' points, those of the policies marked with the trials they leave out."""
    out = []
    for label, pts in points.items():
        short = missing if label == SERIES[2][0] else {}
        out.append(label + ": " + ", ".join(marked(f"{s} M {percent(k, n)}% ({k}/{n}) [{100 * lo:.1f}, {100 * hi:.1f}]",
                                                   short.get(s)) for s, (k, n, lo, hi) in sorted(pts.items()) if n))
    return out


def with_wilson(pts):
    """The scripted series: (successes, episodes) with their Wilson interval."""
    return {s: (k, n) + wilson(k, n) for s, (k, n) in pts.items()}


def svg(points, partial="", short=()):
    """The figure. partial: partial_of(RESULTS); short: the scales whose policies' point leaves
    trials out (marked "*")."""
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
            if label == SERIES[2][0] and s in short:
                out.append(f'<text x="{cx + 5:.1f}" y="{y(k / n) - 5:.1f}" fill="#b00">*</text>')
    for j, (label, colour) in enumerate(SERIES):
        lx = left + j * 230
        out.append(f'<rect x="{lx}" y="{h - 52}" width="14" height="14" fill="{colour}"/>')
        out.append(f'<text x="{lx + 20}" y="{h - 40}">{label}</text>')
    # Two lines: one would run past the picture's right edge.
    out.append(f'<text x="{left}" y="{h - 14}" fill="#555" font-size="11">M = image 10 levels, joints 0.01 rad, '
               'base 0.01 m/rad, touch 0.1, effort 0.1.</text>')
    out.append(f'<text x="{left}" y="{h - 2}" fill="#555" font-size="11">Whiskers: 95% intervals (policies: '
               'resampled by policy and shared layout; scripted: Wilson).</text>')
    if any("fill=\"#b00\">*</text>" in line for line in out):
        # In the picture too: a figure travels without the stderr that came with it.
        out.append(f'<text x="{w - 30}" y="35" text-anchor="end" fill="#b00" font-size="11">partial results'
                   f'{": " + partial if partial else ""}; * points: only the trials with results</text>')
    out.append("</svg>")
    return "\n".join(out) + "\n"


def main():
    args = [a for a in sys.argv[1:]]
    roger = None
    if "--roger" in args:
        i = args.index("--roger")
        if i + 1 == len(args):
            sys.exit("usage: noise_figure.py RESULTS_FOLDER [OUT.svg] [--roger PATH]")
        roger = args[i + 1]
        del args[i:i + 2]
    if len(args) not in (1, 2):
        sys.exit("usage: noise_figure.py RESULTS_FOLDER [OUT.svg] [--roger PATH]")
    results = args[0]
    require_results_folder(NAME, results)
    if len(args) == 2:
        require_svg_path(NAME, args[1])
    table = table_three(results)
    if not table:
        sys.exit(f"{results} holds no evaluation III_x... of scripts/noise.lua (trials/eval/III_x*)")
    missing = left_out(results)
    roger = find_roger(NAME, roger)
    points = {SERIES[2][0]: table}
    for label, scenario in ((SERIES[0][0], "unobstructed"), (SERIES[1][0], "cluttered")):
        points[label] = with_wilson({s: scripted(roger, scenario, s) for s in SCALES})
    # Everything before the files: a failure on the way leaves neither behind.
    figures = json.dumps({label: {str(s): {"successes": k, "episodes": n, "low": lo, "high": hi}
                                  for s, (k, n, lo, hi) in pts.items()} for label, pts in points.items()}, indent=1)
    picture = svg(points, partial_of(results), set(missing))
    if warning(results, missing):
        print(warning(results, missing), file=sys.stderr)
    write_atomically(os.path.join(results, "scripted_noise.json"), figures)
    out = args[1] if len(args) == 2 else os.path.join(results, "noise.svg")
    write_atomically(out, picture)
    print("wrote", out)
    print("\n".join(printed(points, missing)))


if __name__ == "__main__":
    main()
