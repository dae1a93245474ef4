#!/usr/bin/env python3
"""check_failure_modes.py: scripts/failure_modes.py on scripts/quick.lua's results counts every
failing episode once, in one mode, and as many as `roger eval` counts (CTest failure_modes).

  check_failure_modes.py --roger build/engine/roger --work DIR
"""
import argparse
import json
import os
import shutil
import subprocess
import sys


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--roger", required=True)
    ap.add_argument("--work", required=True)
    a = ap.parse_args()
    shutil.rmtree(a.work, ignore_errors=True)
    results = os.path.join(a.work, "quick")
    subprocess.run([a.roger, "run", "scripts/quick.lua", "--out", results], check=True, capture_output=True)
    out = subprocess.run([sys.executable, "scripts/failure_modes.py", results, "--trials", "0,1", "--episodes", "25",
                          "--roger", a.roger], check=True, capture_output=True, text=True).stdout
    rows = [line for line in out.splitlines() if line.startswith("| ") and not line.startswith("| shape")]
    total = [r for r in rows if "**all**" in r]
    if len(rows) != 5 or len(total) != 1:
        print("expected four shapes and a total:\n" + out)
        return 1
    failures_total = 0
    for row in rows:
        cells = [c.strip() for c in row.strip("|").split("|")]
        failures, modes = int(cells[2]), [int(c) for c in cells[3:]]
        if failures != sum(modes):
            print("a row whose modes do not add up to its failures: " + row)
            return 1
        if "**all**" not in row:
            failures_total += failures
    # The same episodes through roger eval: as many failures.
    counted = 0
    for shape in ["circle", "triangle", "pentagon", "spade"]:
        for trial in ["000", "001"]:
            policy = os.path.join(results, "trials", "T", "DC6", trial, "policy.json")
            line = subprocess.run([a.roger, "eval", "curricula/paper.lua", "--policy", policy, "--scenario", "cluttered",
                                   "--set", "shape=" + shape, "--episodes", "25", "--seed", "4000", "--json"],
                                  check=True, capture_output=True, text=True).stdout.splitlines()[-1]
            counted += 25 - json.loads(line)["successes"]
    if counted != failures_total or int(total[0].strip("|").split("|")[2]) != counted:
        print("failure_modes counted %d failures, roger eval %d:\n%s" % (failures_total, counted, out))
        return 1
    print("failure_modes: %d failing episodes of 200, each in one mode, as roger eval counts" % counted)
    shutil.rmtree(a.work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
