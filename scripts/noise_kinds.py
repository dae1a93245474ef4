#!/usr/bin/env python3
"""noise_kinds.py [RESULTS] [--roger PATH] [--jobs N]: the experiment of docs/results.md, Noise, "Kinds".

Each kind of noise other than white (bias, drift, delay, dropout, resolution) alone at the moderate
level of scripts/noise_kinds_levels.lua, and all of them together, for
  - the scripted task (`curricula/scripted.lua`'s task), unobstructed and in clutter, 200 episodes
    per cell from seed 9200000;
  - the hand-written 8-object sort (`curricula/sort_by_hand.lua`), 20 episodes from seed 9500000;
  - Table III's noise-free T/DC6 policies and training under every kind: `roger run
    scripts/noise_kinds.lua --out RESULTS` (its tables in RESULTS/tables.md; resumes if interrupted).
Writes RESULTS/kinds.json and RESULTS/kinds.md (the table of docs/results.md), each atomically.
Standard library only. Default RESULTS: results/noise_kinds.
"""
import argparse
import json
import os
import re
import subprocess


HERE = os.path.dirname(os.path.abspath(__file__))


def default_roger():
    """The engine built beside this script (the source tree's build/engine/roger), else roger on PATH."""
    built = os.path.join(HERE, os.pardir, "build", "engine", "roger")
    return built if os.access(built, os.X_OK) else "roger"


def kinds(path=os.path.join(HERE, "noise_kinds_levels.lua")):
    """[(name, {param: value})] of the kinds alone, then ("all", union): read from the Lua file."""
    text = open(path).read()
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
    r = json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout.strip().splitlines()[-1])
    return r["successes"], r["episodes"]


def table_three(results, name):
    """(successes, episodes, low, high) of evaluation III_<name>'s Total row in RESULTS/report.json."""
    with open(os.path.join(results, "report.json")) as f:
        tables = json.load(f)["tables"]
    for t in tables:
        if t.get("evaluation") == f"III_{name}":
            r = [r for r in t["rows"] if r["object"] == "Total"][0]
            n = r["episodes"]
            return round(r["success_rate"] * n), n, r["success_low"], r["success_high"]
    raise SystemExit(f"{results}/report.json has no evaluation III_{name}")


def write_atomically(path, text):
    with open(path + ".tmp", "w") as f:
        f.write(text)
    os.replace(path + ".tmp", path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results", nargs="?", default="results/noise_kinds")
    ap.add_argument("--roger", default=default_roger(),
                    help="the roger program (default: the source tree's build/engine/roger, else roger on PATH)")
    ap.add_argument("--jobs", default="2")
    a = ap.parse_args()
    subprocess.run([a.roger, "run", "scripts/noise_kinds.lua", "--out", a.results, "--jobs", a.jobs], check=True)
    rows = []
    for name, params in [("none", {})] + kinds():
        cells = {w: evaluate(a.roger, "curricula/scripted.lua", "task", params, 200, 9200000, ["--scenario", w])
                 for w in ("unobstructed", "cluttered")}
        cells["sort"] = evaluate(a.roger, "curricula/sort_by_hand.lua", "sort", dict(params, objects=8), 20, 9500000)
        cells["table3"] = table_three(a.results, name)
        rows.append({"kind": name, "params": params, **{k: list(v) for k, v in cells.items()}})
    write_atomically(os.path.join(a.results, "kinds.json"), json.dumps(rows, indent=1) + "\n")
    pct = lambda k, n: f"{100 * k / n:.1f}% ({k}/{n})"
    lines = ["| kind | level | scripted, unobstructed | scripted, cluttered | sort, 8 objects | "
             "Table III's T/DC6 policies [95% CI] |", "|---|---|---|---|---|---|"]
    for r in rows:
        level = ", ".join(f"{k.replace('noise_', '')} {v}" for k, v in r["params"].items()) or "no noise"
        if r["kind"] == "all":
            level = "every level above"
        k3, n3, lo, hi = r["table3"]
        lines.append(f"| {r['kind']} | {level} | {pct(*r['unobstructed'])} | {pct(*r['cluttered'])} | "
                     f"{pct(*r['sort'])} | {pct(k3, n3)} [{100 * lo:.1f}, {100 * hi:.1f}] |")
    write_atomically(os.path.join(a.results, "kinds.md"), "\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
