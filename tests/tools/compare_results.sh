#!/usr/bin/env bash
# compare_results.sh [--golden] A B: compares two results folders of `roger run` for identical
# results. tables.md, report.json and every CSV (summary.csv, each trial's curve.csv) must be byte
# for byte the same, except the columns of wall-clock time (named wall_s or *_wall_s), which
# measure the machine, not the engine, and the path tables.md names the batch script by (as the
# command typed it); and every trial's policy.json, byte for byte. With --golden, A is a folder of
# kept files (e.g. tests/golden/quick) and only the files it holds are compared (no policies).
# A policy's curriculum path (as the run found the file) is set aside; its digest is compared. Prints each difference; exits 0
# when there is none, 1 otherwise.
set -euo pipefail
golden=0
if [ "${1:-}" = "--golden" ]; then golden=1; shift; fi
if [ $# -ne 2 ] || [ ! -d "$1" ] || [ ! -d "$2" ]; then
  echo "usage: $0 [--golden] RESULTS_A RESULTS_B (two folders written by roger run)" >&2
  exit 2
fi
a=$1 b=$2 status=0

# A CSV without its wall-clock columns.
strip_wall() {
  awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) keep[i] = ($i !~ /(^|_)wall_s$/) }
           { line = ""; for (i = 1; i <= NF; i++) if (keep[i]) line = line (line == "" ? "" : ",") $i; print line }' "$1"
}

# tables.md names the batch script as the command typed it (base.lua, or /lab/base.lua as
# scripts/slurm/submit.sh names it): that path says how the run was started, not what it found.
script_line_as_one() { sed -E 's/^Batch script `[^`]*`/Batch script `(the script)`/' "$1"; }
if ! cmp -s <(script_line_as_one "$a/tables.md") <(script_line_as_one "$b/tables.md"); then
  echo "differs: tables.md"; status=1
fi
if ! cmp -s "$a/report.json" "$b/report.json"; then echo "differs: report.json"; status=1; fi
if [ $golden -eq 1 ]; then
  files=$(cd "$a" && find . -name '*.csv' | sort)
else
  # Each in a subshell of its own: a relative B is relative to here, not to A.
  files=$( { (cd "$a" && find . -name '*.csv'); (cd "$b" && find . -name '*.csv'); } | sort -u)
fi
count=0
for f in $files; do
  count=$((count + 1))
  if [ ! -f "$a/$f" ] || [ ! -f "$b/$f" ]; then echo "only in one folder: $f"; status=1; continue; fi
  if ! cmp -s <(strip_wall "$a/$f") <(strip_wall "$b/$f"); then echo "differs: $f"; status=1; fi
done
# Each trained policy too (not kept in golden folders): the Q-table, and the skills it embeds named
# by their place in the results folder (found by a probe: a relative --out was recorded as typed).
# The curriculum's path is as the run found it (a copy of the project finds its own); its contents
# are compared by curriculum_digest beside it.
curriculum_as_one() { sed -E 's/"curriculum": *"([^"\\]|\\.)*"/"curriculum": "(as found)"/g' "$1"; }
policies=0
if [ $golden -eq 0 ]; then
  for f in $( { (cd "$a" && find . -name policy.json); (cd "$b" && find . -name policy.json); } | sort -u); do
    policies=$((policies + 1))
    if [ ! -f "$a/$f" ] || [ ! -f "$b/$f" ]; then echo "only in one folder: $f"; status=1; continue; fi
    if ! cmp -s <(curriculum_as_one "$a/$f") <(curriculum_as_one "$b/$f"); then echo "differs: $f"; status=1; fi
  done
fi
[ $status -eq 0 ] && echo "identical: tables.md, report.json, $count CSV files (wall-clock columns aside) and $policies policies"
exit $status
