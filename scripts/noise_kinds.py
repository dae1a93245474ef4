#!/usr/bin/env python3
"""noise_kinds.py [RESULTS] [--roger PATH] [--jobs N] [--trials N] [--only NAME]...: the experiment of docs/results.md, Noise, "Kinds".

Each kind of noise other than white (bias, drift, delay, dropout, resolution) alone at the moderate
level of scripts/noise_kinds_levels.lua, and all of them together, for
  - the scripted task (`curricula/scripted.lua`'s task), unobstructed and in clutter, 200 episodes
    per cell from seed 9200000;
  - the hand-written 8-object sort (`curricula/sort_by_hand.lua`), 20 episodes from seed 9500000;
  - Table III's noise-free T/DC6 policies and training under every kind: `roger run
    scripts/noise_kinds.lua --out RESULTS` (its tables in RESULTS/tables.md; resumes if interrupted).
Writes RESULTS/kinds.json and RESULTS/kinds.md (the table of docs/results.md), each atomically,
once every figure is in. Standard library only. Default RESULTS: results/noise_kinds.

--jobs N (default 2), --trials N and --only NAME (repeatable: a run, RUN/CONTEXT or eval/NAME) go to
`roger run` as they are, to run a cheap or a partial experiment (`--trials 1 --only T --only SG
--only eval/III_none`); without them the command is `roger run scripts/noise_kinds.lua --out
RESULTS --jobs 2`, as always. A folder left partial so (report.json's "partial": trials failed or
without a result yet) is tabulated all the same, but says so: a warning on stderr, and each Table
III cell marked with the trials it leaves out ("(1 failed)", "(40 pending)"; "-" for an evaluation
with no result at all). A `roger run` that fails with failed trials (exit status 1, its partial
report written) is tabulated so too; any other failure stops the script with one line. The roger
program: --roger, else $ROGER, else the source tree's build/engine/roger, else roger on PATH.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True  # results_common, imported below, leaves no __pycache__ in scripts/
sys.path.insert(0, HERE)  # its folder: also when loaded by path or run with -P
import results_common
from results_common import (find_roger, marked, percent, positive_int, read_report, run_roger, without,
                            write_atomically)

NAME = "noise_kinds.py"  # in the messages of results_common's functions


def run_command(roger, results, jobs="2", trials=None, only=()):
    """The `roger run` of the experiment, with the options passed through."""
    cmd = [roger, "run", "scripts/noise_kinds.lua", "--out", results, "--jobs", str(jobs)]
    if trials is not None:
        cmd += ["--trials", str(trials)]
    for name in only:
        cmd += ["--only", name]
    return cmd


def kinds(path=os.path.join(HERE, "noise_kinds_levels.lua")):
    """[(name, {param: value})] of the kinds alone, then ("all", union): read from the Lua file."""
    with open(path) as f:
        text = f.read()
    out = []
    for name, body in re.findall(r'name = "(\w+)", params = \{([^}]*)\}', text):
        out.append((name, dict(re.findall(r"(\w+) = ([-\d.eE]+)", body))))
    union = {}
    for _, params in out:
        union.update(params)
    return out + [("all", union)]


def evaluate(roger, script, policy, params, episodes, seed, extra=()):
    cmd = [roger, "eval", script, "--policy", policy, "--episodes", str(episodes), "--seed", str(seed), "--json",
           *extra]
    for k, v in params.items():
        cmd += ["--set", f"{k}={v}"]
    r = json.loads(run_roger(NAME, cmd).strip().splitlines()[-1])
    return r["successes"], r["episodes"]


def table_three(results, name):
    """(successes, episodes, low, high) of evaluation III_<name>'s Total row in RESULTS/report.json,
    or None when it has none (no trial of it has a result: --only left it out, or all failed)."""
    for t in read_report(results)["tables"]:
        if t.get("evaluation") == f"III_{name}":
            total = [r for r in t.get("rows", []) if r.get("object") == "Total"]
            if not total or "episodes" not in total[0]:  # a Total of counts alone: no result yet
                return None
            r = total[0]
            n = r["episodes"]
            return round(r["success_rate"] * n), n, r["success_low"], r["success_high"]
    raise SystemExit(f"{results}/report.json has no evaluation III_{name}")


def left_out(results):
    """{evaluation: {"failed": n, "pending": m}} of the evaluations with trials without a result,
    which their cells leave out (results_common.without_result)."""
    return results_common.without_result(results, read_report(results))["eval"]


def warning(results, missing, names):
    """The stderr warning of a partial folder, or '': its Table III cells pool the other trials.
    names: the evaluations tabulated (III_<kind>)."""
    lines = [f"  evaluation {e}: {without(missing[e])}" for e in names if e in missing]
    return results_common.partial_warning(
        NAME, results, read_report(results), lines, "the evaluations III_<kind> tabulated here",
        "the Table III cells below pool only the trials with results, leaving out (cells marked so)")


def markdown(rows, missing=None):
    """The table of docs/results.md (kinds.md) from kinds.json's rows; a Table III cell marked with
    the trials it leaves out (missing: left_out), "-" when it has no result at all."""
    missing = missing or {}
    pct = lambda k, n: f"{percent(k, n)}% ({k}/{n})"
    lines = ["| kind | level | scripted, unobstructed | scripted, cluttered | sort, 8 objects | "
             "Table III's T/DC6 policies [95% CI] |", "|---|---|---|---|---|---|"]
    for r in rows:
        level = ", ".join(f"{k.replace('noise_', '')} {v}" for k, v in r["params"].items()) or "no noise"
        if r["kind"] == "all":
            level = "every level above"
        table3 = "-"
        if r["table3"]:
            k3, n3, lo, hi = r["table3"]
            table3 = f"{pct(k3, n3)} [{100 * lo:.1f}, {100 * hi:.1f}]"
        table3 = marked(table3, missing.get("III_" + r["kind"]))
        lines.append(f"| {r['kind']} | {level} | {pct(*r['unobstructed'])} | {pct(*r['cluttered'])} | "
                     f"{pct(*r['sort'])} | {table3} |")
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results", nargs="?", default="results/noise_kinds")
    ap.add_argument("--roger", help="the roger program (default: $ROGER, else the source tree's build/engine/roger, "
                    "else roger on PATH)")
    ap.add_argument("--jobs", type=positive_int, default=2, help="worker threads of roger run (default 2)")
    ap.add_argument("--trials", type=positive_int, help="trials per run, for roger run (default: the script's)")
    ap.add_argument("--only", action="append", default=[], metavar="NAME",
                    help="only this run, RUN/CONTEXT or eval/NAME, for roger run (repeatable)")
    a = ap.parse_args()
    a.roger = find_roger(NAME, a.roger)
    started = time.time()
    status = subprocess.run(run_command(a.roger, a.results, a.jobs, a.trials, a.only)).returncode
    if status != 0:
        # Exit status 1 with a fresh partial report: some trials failed (roger run listed them); the
        # others are tabulated, marked. Anything else (a refused folder, a bad script, an interrupt)
        # stops here: a report.json there would be an earlier run's.
        report = os.path.join(a.results, "report.json")
        fresh = os.path.exists(report) and os.path.getmtime(report) >= started - 1
        if not (status == 1 and fresh and (read_report(a.results).get("partial") or {}).get("failed", 0)):
            sys.exit(f"noise_kinds.py: roger run exited {status} (its messages above); nothing tabulated")
    rows = []
    for name, params in [("none", {})] + kinds():
        cells = {w: evaluate(a.roger, "curricula/scripted.lua", "task", params, 200, 9200000, ["--scenario", w])
                 for w in ("unobstructed", "cluttered")}
        cells["sort"] = evaluate(a.roger, "curricula/sort_by_hand.lua", "sort", dict(params, objects=8), 20, 9500000)
        cells["table3"] = table_three(a.results, name)
        rows.append({"kind": name, "params": params, **{k: None if v is None else list(v) for k, v in cells.items()}})
    missing = left_out(a.results)
    table = markdown(rows, missing)
    note = warning(a.results, missing, ["III_" + r["kind"] for r in rows])
    if note:
        print(note, file=sys.stderr)
    write_atomically(os.path.join(a.results, "kinds.json"), json.dumps(rows, indent=1) + "\n")
    write_atomically(os.path.join(a.results, "kinds.md"), table)
    print(table, end="")


if __name__ == "__main__":
    main()
