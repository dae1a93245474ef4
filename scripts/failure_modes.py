#!/usr/bin/env python3
"""failure_modes.py: where the learned transport policies fail in the generalization worlds.

Replays, with `roger render`, every failing episode of some trials' final T/DC6 policies in the
cluttered worlds (Table III's scenario) and sorts each by what its timeline shows:

  thrash      the learned Phi_SG switched between Phi7's preshape and phi3 at least 20 times
              (each switch undoes the other's progress; the grasp never closes)
  detour      the learned Phi_SG switched between tracking (Phi6's phi0) and Phi7's approach
              (phi1) at least 20 times: phi1's path turns the base away from the stimulus round
              an obstacle, phi0 (which wants the base facing it) is no longer converged, and the
              policy turns back to it, then forward along the path, tick after tick
  preshape    Phi_SG ended running Phi7's preshape (phi4 <| phi2), which never converged
  grasp       Phi_SG ended running phi3, which never converged
  approach    Phi_SG ended running Phi7's approach (phi1) or the search (Phi6)
  unbalanced  the object was carried to the goal and is held, but phi5 never converged there
  dropped     transport lost the grasp (phi5 NOREF) away from the goal
  other       anything else

  scripts/failure_modes.py RESULTS_DIR [--trials 0,1,2] [--episodes 50] [--seed 4000] [--roger PATH]

RESULTS_DIR is a results folder of scripts/paper.lua (its trials/T/DC6/<i>/policy.json are read).
Prints one table row per shape, then the totals. docs/results.md quotes its output. The roger
program: --roger, else $ROGER, else the source tree's build/engine/roger, else roger on PATH; a
missing one, or a roger command that fails, stops the script with a one-line error.
"""
import argparse
import collections
import json
import os
import sys
import tempfile

sys.dont_write_bytecode = True  # results_common, imported below, leaves no __pycache__ in scripts/
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # its folder: also when loaded by path or run with -P
from results_common import find_roger, positive_int, run_roger, seed_int

NAME = "failure_modes.py"  # in the messages of results_common's functions
SHAPES = ["circle", "triangle", "pentagon", "spade"]


def roger(args, exe):
    """roger's stdout; a failing command stops the script with roger's own last line, not a traceback."""
    return run_roger(NAME, [exe] + args)


def failing_seeds(exe, policy, shape, first, episodes):
    """The seeds among first..first+episodes-1 on which the policy fails."""
    out = []
    for seed in range(first, first + episodes):
        line = roger(["eval", "curricula/paper.lua", "--policy", policy, "--scenario", "cluttered", "--set",
                      "shape=" + shape, "--episodes", "1", "--seed", str(seed), "--json"], exe).splitlines()[-1]
        if json.loads(line)["successes"] == 0:
            out.append(seed)
    return out


def classify(episode):
    """The failure mode of one recorded episode (see the module's docstring)."""
    paths = [">".join(d["path"][2:4]) for d in episode["decisions"]]
    def switches_between(x, y):
        return sum(1 for a, b in zip(paths, paths[1:]) if {a, b} == {x, y})
    switches = switches_between("Phi7>phi4 <| phi2", "phi3")
    last = {g["name"]: g["states"][-1] for g in episode["gammas"]}
    held = all(t["force"] > 0 for t in episode["frames"][-1]["touch"])
    top = episode["decisions"][-1]["path"][1] if episode["decisions"] and len(episode["decisions"][-1]["path"]) > 1 else ""
    if switches >= 20:
        return "thrash"
    if switches_between("Phi6>phi0", "Phi7>phi1") >= 20:
        return "detour"
    if top == "Phi_SG":
        final = paths[-1] if paths else ""
        if final == "Phi7>phi4 <| phi2":
            return "preshape"
        if final == "phi3":
            return "grasp"
        return "approach"
    if held and last.get("phi1") == "CONV" and last.get("phi5") != "CONV":
        return "unbalanced"
    if last.get("phi5") == "NOREF":
        return "dropped"
    return "other"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results")
    ap.add_argument("--trials", default="0,1,2,3,4")
    ap.add_argument("--episodes", type=positive_int, default=50)
    ap.add_argument("--seed", type=seed_int, default=4000)
    ap.add_argument("--roger", help="the roger program (default: $ROGER, else the source tree's "
                    "build/engine/roger, else roger on PATH)")
    ap.add_argument("--verbose", action="store_true", help="also print each failing episode and its mode")
    a = ap.parse_args()
    a.roger = find_roger(NAME, a.roger)
    # Every trial's policy before the table's first line (found by a probe: a missing one stopped the
    # script after its header was printed).
    try:
        trials = [int(t) for t in a.trials.split(",")]
    except ValueError:
        ap.error(f"--trials: expected trial numbers separated by commas (0,1,2), got '{a.trials}'")
    for trial in trials:
        policy = os.path.join(a.results, "trials", "T", "DC6", "%03d" % trial, "policy.json")
        if trial < 0 or not os.path.isfile(policy):
            sys.exit(f"failure_modes: trial {trial}: no T/DC6 policy at {policy} (a results folder of roger run "
                     "scripts/quick.lua or scripts/paper.lua, with that trial finished, is expected)")
    modes = ["thrash", "detour", "preshape", "grasp", "approach", "unbalanced", "dropped", "other"]
    total = collections.Counter()
    episodes_total = 0
    print("| shape | episodes | failures | " + " | ".join(modes) + " |")
    print("|---|---|---|" + "---|" * len(modes))
    with tempfile.TemporaryDirectory() as tmp:
        for shape in SHAPES:
            counts = collections.Counter()
            n = 0
            for trial in trials:
                policy = os.path.join(a.results, "trials", "T", "DC6", "%03d" % trial, "policy.json")
                n += a.episodes
                for seed in failing_seeds(a.roger, policy, shape, a.seed, a.episodes):
                    folder = os.path.join(tmp, "%s-%s-%d" % (shape, trial, seed))
                    roger(["render", "curricula/paper.lua", "--policy", policy, "--scenario", "cluttered", "--set",
                           "shape=" + shape, "--seed", str(seed), "--every", "1", "--out", folder], a.roger)
                    with open(os.path.join(folder, "episode.json")) as f:
                        mode = classify(json.load(f))
                    counts[mode] += 1
                    if a.verbose:
                        print("  %s trial %s seed %d: %s" % (shape, trial, seed, mode), file=sys.stderr)
            total += counts
            episodes_total += n
            print("| %s | %d | %d | %s |" % (shape, n, sum(counts.values()), " | ".join(str(counts[m]) for m in modes)))
    print("| **all** | %d | %d | %s |" % (episodes_total, sum(total.values()), " | ".join(str(total[m]) for m in modes)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
