#!/usr/bin/env bash
# run_kill_test.sh ROGER SOURCE_DIR [SEED]: `roger run` killed with SIGKILL at seeded random moments
# resumes, with the same command, to exactly the results of an uninterrupted run.
#
# tests/scripts/kill_batch.lua (training, training on a learned skill, evaluation, tables and
# figures) runs once uninterrupted, then again into a second folder, killed at least 10 times:
# during training, during the evaluation phase and while the report is written (at least twice
# each), each kill a seeded random delay after the log line that opens that part. After every
# kill, nothing in the folder is half-written under its final name: every JSON and JSON Lines file
# parses (jq), every PNG ends with its IEND chunk and every SVG with </svg>, tables.md ends with its
# closing paragraph. A run is then left to finish, and the two folders must be the same: tables,
# report, every CSV (tests/tools/compare_results.sh, wall-clock columns aside) and every trial's
# policy.json and episodes.jsonl byte for byte (the folder's own path aside). The first kill of the report comes before any
# report exists, so the resumed run is what finishes it.
#
# Exit status: 0 passed, 1 failed, 77 skipped (jq is not installed: .ci/install installs it;
# under CI=true that fails).
set -euo pipefail

if [ $# -lt 2 ]; then
  echo "usage: $0 ROGER SOURCE_DIR [SEED]" >&2
  exit 1
fi
roger=$(readlink -f "$1")
cd "$2"
RANDOM=${3:-20261125}  # the kill delays are a function of the seed
# shellcheck source=tests/tools/skip.sh
. tests/tools/skip.sh  # skip: exit 77, or a failure under CI=true
command -v jq >/dev/null 2>&1 || skip "jq is not installed (apt-get install jq, as .ci/install does)"

work=$(mktemp -d /tmp/roger_kill_XXXXXX)
child=
cleanup() {
  if [ -n "$child" ]; then kill -9 "$child" 2>/dev/null || true; fi
  rm -rf "$work"
}
trap cleanup EXIT
script=tests/scripts/kill_batch.lua
whole=$work/whole killed=$work/killed
fail() { echo "FAILED: $*"; exit 1; }

"$roger" run "$script" --jobs 2 --out "$whole" >"$work/whole.log" 2>&1 || { cat "$work/whole.log"; fail "the uninterrupted run"; }

# How long each part takes on this machine now (ms), to aim the kills: the longest trial of each
# training phase, the evaluation phase (its trials on two jobs) and a run with only the report left.
wall_ms() { jq -s "map(.wall_s) | $1 * 1000 | floor" "$whole"/trials/$2/*/*/result.json; }
search_grasp_ms=$(wall_ms max SG) transport_ms=$(wall_ms max T) evaluation_ms=$(wall_ms 'add / 2' 'eval/*')
start=$(date +%s%N)
"$roger" run "$script" --jobs 2 --out "$whole" >/dev/null 2>&1 || fail "the report-only run"
report_ms=$(( ($(date +%s%N) - start) / 1000000 ))
echo "this machine: a search-grasp trial ${search_grasp_ms} ms, a transport trial ${transport_ms} ms," \
     "the evaluations ${evaluation_ms} ms, a run with only the report left ${report_ms} ms"

# Which part of the run is left in the killed folder: training, evaluation or report.
part_left() {
  local id
  for id in $(jq -r '.trials[]' "$killed/manifest.json" 2>/dev/null); do
    if [ ! -f "$killed/trials/$id/result.json" ]; then
      case $id in eval/*) echo evaluation ;; *) echo training ;; esac
      return
    fi
  done
  echo report
}

# Fails when a file under its final name is half-written.
check_whole_files() {
  local f
  while IFS= read -r -d '' f; do
    jq empty "$f" >/dev/null 2>&1 || fail "after kill $kills: $f does not parse"
  done < <(find "$killed" \( -name '*.json' -o -name '*.jsonl' \) ! -name '.*' -print0)
  while IFS= read -r -d '' f; do
    [ "$(tail -c 8 "$f" | od -An -tx1 | tr -d ' \n')" = "49454e44ae426082" ] || fail "after kill $kills: $f is cut short"
  done < <(find "$killed" -name '*.png' ! -name '.*' -print0)
  while IFS= read -r -d '' f; do
    tail -c 16 "$f" | grep -q '</svg>' || fail "after kill $kills: $f is cut short"
  done < <(find "$killed" -name '*.svg' ! -name '.*' -print0)
  if [ -f "$killed/tables.md" ]; then
    tail -n 1 "$killed/tables.md" | grep -q "a context that does not shows its own time alone.$" || fail "after kill $kills: tables.md is cut short"
  fi
}

# The number of trials with a result in the killed folder.
finished() { { find "$killed/trials" -name result.json 2>/dev/null || true; } | wc -l; }

# Whether the moment `trigger` has come in the run logging to $1: "finished:N" once N trials have
# a result, "evaluated" once the evaluation phase has ended (the report is next), else a regular
# expression of the log.
moment_came() {
  local log=$1
  case $trigger in
    finished:*) [ "$(finished)" -ge "${trigger#finished:}" ] ;;
    evaluated) sed -n '/phase 3\/3/,$p' "$log" 2>/dev/null | grep -Eq 'trials: ([0-9]+)/\1 done.*, 0 running, 0 left' ;;
    *) grep -Eq "$trigger" "$log" 2>/dev/null ;;
  esac
}

# Starts the run, waits for the moment `trigger` and then a random delay below max_ms, and kills
# it. Returns 1 (no kill) when the run ended first.
kill_at() {
  local log=$work/attempt.log waited=0
  "$roger" run "$script" --jobs 2 --out "$killed" >"$log" 2>&1 &
  child=$!
  while kill -0 "$child" 2>/dev/null && ! moment_came "$log"; do
    sleep 0.01
    waited=$((waited + 1))
    [ $waited -lt 6000 ] || fail "waited a minute for the moment '$trigger' of roger run"
  done
  sleep "$(printf '0.%03d' $(( (RANDOM * 32768 + RANDOM) % max_ms )))"
  if kill -9 "$child" 2>/dev/null; then
    wait "$child" 2>/dev/null || true
    child=
    return 0
  fi
  wait "$child" 2>/dev/null || true
  child=
  return 1
}

# Whether a run that started with part $1 left and was killed in part $2 ("none": it ended) went
# past a part that still needs kills.
order() { case $1 in training) echo 1 ;; evaluation) echo 2 ;; report) echo 3 ;; *) echo 4 ;; esac; }
skipped_needed() {
  local p
  for p in training evaluation report; do
    [ "$(order "$p")" -ge "$(order "$1")" ] && [ "$(order "$p")" -lt "$(order "$2")" ] || continue
    if [ "$p" = report ]; then [ $report_first -eq 0 ] && return 0; else [ "${killed_in[$p]}" -lt 2 ] && return 0; fi
  done
  return 1
}

kills=0 attempts=0 report_first=0
declare -A killed_in=([training]=0 [evaluation]=0 [report]=0) shrink=([training]=1 [evaluation]=1 [report]=1)
enough() {
  [ $kills -ge 10 ] && [ "${killed_in[training]}" -ge 2 ] && [ "${killed_in[evaluation]}" -ge 2 ] &&
    [ "${killed_in[report]}" -ge 2 ] && [ $report_first -eq 1 ]
}
while ! enough; do
  attempts=$((attempts + 1))
  [ $attempts -le 40 ] || fail "40 attempts and still only $kills kills (training ${killed_in[training]}, evaluation ${killed_in[evaluation]}, report ${killed_in[report]}, report killed before it first existed: $report_first)"
  before=training
  [ -f "$killed/manifest.json" ] && before=$(part_left)
  # Training: a random moment within half a search-grasp trial after the next trial finishes, so
  # every kill falls elsewhere and the run moves on (transport: see below). Evaluation: within its trials, then, after two
  # such kills, within half a report of their end: the report is being written for the first time.
  # Report: within a report-only run.
  aim=$before
  case $before in
    training) trigger="finished:$(( $(finished) + 1 ))" max_ms=$((search_grasp_ms / 2)) ;;
    evaluation) trigger='phase 3/3' max_ms=$evaluation_ms ;;
    report) trigger='trials, curriculum' max_ms=$report_ms ;;
  esac
  # Once search-grasp is done, the transport trials left run side by side and end together: the
  # moment after the next one finishes is the end of training. While training still needs kills,
  # a kill aims within half a transport trial of the transport phase's start instead (the run then
  # keeps what it had); after that the run moves on.
  sg_done=$( { find "$killed/trials/SG" -name result.json 2>/dev/null || true; } | wc -l)
  if [ "$before" = training ] && [ "$sg_done" -ge 4 ]; then
    max_ms=$((transport_ms / 2))
    [ "${killed_in[training]}" -ge 2 ] || trigger='phase 2/3: T'
  fi
  if [ "$before" = evaluation ] && [ "${killed_in[evaluation]}" -ge 2 ]; then
    aim=report trigger=evaluated max_ms=$((report_ms / 2))
  fi
  max_ms=$((max_ms / shrink[$aim]))
  [ "$max_ms" -ge 10 ] || max_ms=10
  # A kill that comes too late for its part (the run got past it, or ended) is undone while that
  # part still needs kills: the folder goes back to its copy from before the attempt, and the next
  # attempt waits half as long at most.
  rm -rf "$work/before" && cp -a "$killed" "$work/before" 2>/dev/null || true
  had_report=0
  [ -f "$killed/report.json" ] && had_report=1
  landed=none
  if kill_at; then landed=$(part_left); fi
  first_report=0
  [ "$landed" = report ] && [ $had_report -eq 0 ] && [ ! -f "$killed/report.json" ] && first_report=1
  if skipped_needed "$before" "$landed" || { [ "$trigger" = evaluated ] && [ $first_report -eq 0 ]; }; then
    echo "attempt $attempts: too late for the $aim (at '$trigger' + up to $max_ms ms): undone"
    rm -rf "$killed" && cp -a "$work/before" "$killed"
    shrink[$aim]=$((shrink[$aim] * 2))
    continue
  fi
  [ "$landed" != none ] || { echo "attempt $attempts: the run ended before the kill"; continue; }
  kills=$((kills + 1))
  killed_in[$landed]=$((killed_in[$landed] + 1))
  [ $first_report -eq 0 ] || report_first=1
  echo "kill $kills: during the $landed (at '$trigger' + up to $max_ms ms; $(finished) trials done)"
  check_whole_files
done

"$roger" run "$script" --jobs 2 --out "$killed" >"$work/last.log" 2>&1 || { cat "$work/last.log"; fail "the resumed run"; }
check_whole_files
# From the work folder, with both folders named relative to it, as a user compares (the tool
# once looked for the second inside the first).
(src=$PWD && cd "$work" && bash "$src/tests/tools/compare_results.sh" whole killed) ||
  fail "the results differ from the uninterrupted run's"
for id in $(jq -r '.trials[]' "$whole/manifest.json"); do
  for f in policy.json episodes.jsonl; do
    [ -f "$whole/trials/$id/$f" ] || continue
    # A policy names the file of each learned skill it used, inside its own results folder.
    cmp -s <(sed "s|$whole/|OUT/|g" "$whole/trials/$id/$f") <(sed "s|$killed/|OUT/|g" "$killed/trials/$id/$f") ||
      fail "trials/$id/$f differs"
  done
done
echo "passed: $kills kills (training ${killed_in[training]}, evaluation ${killed_in[evaluation]}, report ${killed_in[report]}), results identical"
