#!/usr/bin/env bash
# run_interrupt_test.sh ROGER SOURCE_DIR: Ctrl-C stops `roger run` cleanly, and resuming finishes it.
#
# scripts/quick.lua is interrupted with SIGINT once its first trial has a result. The run must:
# say that it is stopping, keep every finished trial and record no failure (no error.json), write
# summary.csv and the partial report (tables.md marks the rest pending), leave status.json not
# running, and exit 130 with a last line saying how to resume. The same command then finishes the
# run to exactly the golden results (tests/golden/quick). A second SIGINT soon after the first stops
# the run at once (the signal's default action: no report), saying so, and that folder resumes to
# the golden results too; one SIGINT delivered twice at once (as GNU timeout does) is one Ctrl-C. SIGTERM (Slurm's scancel, a job's time limit) stops it as one Ctrl-C does, and it
# exits 143, as a shell reports a command SIGTERM stopped. A closed output pipe (`| head -1`) stops it
# as one Ctrl-C does, and it exits 141.
set -euo pipefail
set -m  # job control: the background run gets SIGINT (without it, a shell starts it ignoring SIGINT)

if [ $# -lt 2 ]; then
  echo "usage: $0 ROGER SOURCE_DIR" >&2
  exit 1
fi
roger=$(readlink -f "$1")
cd "$2"
work=$(mktemp -d /tmp/roger_interrupt_XXXXXX)
child=
cleanup() {
  if [ -n "$child" ]; then kill -9 "$child" 2>/dev/null || true; fi
  rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "FAILED: $*"; [ -f "$work/log" ] && sed 's/^/  | /' "$work/log"; exit 1; }

# Starts the run into $1, waits until a trial has a result, sends SIGINT (or signal $3) $2 times
# (0.04 s apart: twice roger's 20 ms within which two are one request; or at once when $4 is
# "at-once") and sets `status` to the run's exit status.
interrupt() {
  local out=$1 signal=${3:-INT} gap=0.04 waited=0
  [ "${4:-}" != at-once ] || gap=0
  "$roger" run scripts/quick.lua --jobs 2 --out "$out" >"$work/log" 2>&1 &
  child=$!
  until [ -n "$(find "$out/trials" -name result.json 2>/dev/null | head -1)" ]; do
    kill -0 "$child" 2>/dev/null || fail "the run ended before its first trial had a result"
    sleep 0.05
    waited=$((waited + 1))
    [ $waited -lt 2400 ] || fail "waited two minutes for the first trial"
  done
  kill -"$signal" "$child"
  second_sent=
  if [ "$2" -eq 2 ]; then
    # At once: two builtins in a row, microseconds apart (no sleep process between them, whose
    # start on a busy machine could take longer than roger's 20 ms).
    if [ "$gap" != 0 ]; then sleep "$gap"; fi
    if kill -"$signal" "$child" 2>/dev/null; then second_sent=yes; fi
  fi
  wait_child
}

# Sends SIGINT to the background command $child, then waits for it (wait_child); `signal_sent`
# says whether the signal found the process.
stop_child() {
  signal_sent=
  if kill -INT "$child" 2>/dev/null; then signal_sent=yes; fi
  wait_child
}

# Waits for the background command $child and sets `status` to its exit status.
wait_child() {
  status=0
  wait "$child" || status=$?
  child=
}

# Starts the run into $1 in the background ($child) and returns once it says it writes its report.
start_until_report() {
  "$roger" run scripts/quick.lua --jobs 2 --out "$1" >"$work/log" 2>&1 &
  child=$!
  until grep -q "^roger run: writing the report" "$work/log"; do
    kill -0 "$child" 2>/dev/null || fail "the run into $1 ended before it began its report"
    sleep 0.01
  done
}

resume_to_golden() {
  "$roger" run scripts/quick.lua --jobs 2 --out "$1" >"$work/log" 2>&1 || fail "the resumed run of $1"
  bash tests/tools/compare_results.sh --golden tests/golden/quick "$1" >/dev/null || fail "$1 resumed is not the golden run"
}

interrupt "$work/once" 1
[ "$status" -eq 130 ] || fail "exit status $status after one Ctrl-C, not 130"
grep -q "^roger: stopping: " "$work/log" || fail "no line says the run is stopping"
[ "$(tail -n 1 "$work/log")" = "roger run: interrupted; the trials that were running start afresh when you run the same command again" ] ||
  fail "the last line does not say how to resume"
grep -Eq "^roger run: [0-9]+ of 24 trials done in .*, [0-9]+ not run yet" "$work/log" || fail "no count of the trials done"
[ -z "$(find "$work/once/trials" -name error.json)" ] || fail "an interrupted trial was recorded as failed"
[ -f "$work/once/summary.csv" ] || fail "no summary.csv"
grep -q "pending" "$work/once/tables.md" || fail "the partial report marks nothing pending"
grep -q '"running": false' "$work/once/status.json" || fail "status.json still says running"
resume_to_golden "$work/once"

# A Ctrl-C once every trial is done, while the report is written again (found by a probe: it said
# "finishing the episodes in flight", wrote the report and exited 0): the report is finished, the
# run says the stop came after its trials, and exits 130.
# On idle cores the report can be written and the run over before the Ctrl-C comes (it found no
# process, or a run that had finished: exit 0): that attempt says nothing, and is made again.
for attempt in 1 2 3 4 5; do
  rm -rf "$work/report"
  cp -a "$work/once" "$work/report"
  rm -f "$work/report/tables.md" "$work/report/report.json" "$work/report"/figure*
  start_until_report "$work/report"
  stop_child
  [ -n "$signal_sent" ] && [ "$status" -ne 0 ] && break
done
[ -n "$signal_sent" ] && [ "$status" -ne 0 ] || fail "five runs finished their report before the Ctrl-C came"
[ "$status" -eq 130 ] || fail "exit status $status after a Ctrl-C during the report, not 130"
grep -q "^roger: stopping: finishing the report of the finished trials, then exiting" "$work/log" ||
  fail "the line of the stop does not say the report is finished"
[ "$(tail -n 1 "$work/log")" = "roger run: stopped on request after its trials had ended, during the report, which was completed" ] ||
  fail "the last line does not say the report was completed"
[ -f "$work/report/tables.md" ] && [ -f "$work/report/report.json" ] || fail "the report was not finished"

# A kill once the report of a resumed run has begun (found by a probe: summary.csv, written first,
# said all 24 trials were ok beside the earlier partial report of 8): summary.csv is written after
# the report, so whenever the kill lands the two say the same.
interrupt "$work/killed" 1
[ "$status" -eq 130 ] && grep -q "Partial report" "$work/killed/tables.md" || fail "no partial report to begin with"
start_until_report "$work/killed"
kill -KILL "$child"
wait_child
pending_rows=$(grep -c ',pending,' "$work/killed/summary.csv" || true)
if grep -q "Partial report" "$work/killed/tables.md"; then
  [ "$pending_rows" -gt 0 ] || fail "summary.csv says every trial is done beside a partial report"
else
  [ "$pending_rows" -eq 0 ] || fail "summary.csv says trials are pending beside a whole report"
fi
resume_to_golden "$work/killed"

# On idle cores a run stopped after its first trial can finish its partial report within the 0.04 s
# before the second Ctrl-C, which then finds no process: that attempt says nothing, and is made
# again (a fresh folder), up to ten times.
for attempt in 1 2 3 4 5 6 7 8 9 10; do
  rm -rf "$work/twice"
  interrupt "$work/twice" 2 INT
  [ -n "$second_sent" ] && break
done
[ -n "$second_sent" ] || fail "ten runs ended before their second Ctrl-C came"
[ "$status" -eq 130 ] || fail "exit status $status after two Ctrl-C, not 130 (killed by SIGINT)"
! grep -q "^roger run: interrupted" "$work/log" || fail "the second Ctrl-C did not stop the run at once"
grep -q "^roger: stopped at once by a second Ctrl-C" "$work/log" || fail "no line says the second Ctrl-C stopped it"
resume_to_golden "$work/twice"

# One request delivered twice at once (GNU timeout signals the command and then its process group)
# is one Ctrl-C: the run stops cleanly.
interrupt "$work/double" 2 INT at-once
[ "$status" -eq 130 ] || fail "exit status $status after one Ctrl-C delivered twice, not 130"
[ "$(tail -n 1 "$work/log")" = "roger run: interrupted; the trials that were running start afresh when you run the same command again" ] ||
  fail "one Ctrl-C delivered twice stopped the run at once"

interrupt "$work/term" 1 TERM
[ "$status" -eq 143 ] || fail "exit status $status after SIGTERM, not 143"
grep -q "^roger: stopping (SIGTERM): " "$work/log" || fail "no line says the run is stopping on SIGTERM"
[ "$(tail -n 1 "$work/log")" = "roger run: interrupted; the trials that were running start afresh when you run the same command again" ] ||
  fail "after SIGTERM the last line does not say how to resume"
[ -z "$(find "$work/term/trials" -name error.json)" ] || fail "a trial SIGTERM stopped was recorded as failed"

# A task of a Slurm array (--shard slurm) stopped by SIGTERM (scancel, its --time) says how to
# submit its shard again, not "run the same command again", which is the array's (found by a probe).
SLURM_ARRAY_TASK_ID=0 ROGER_SHARDS=2 "$roger" run scripts/quick.lua --jobs 2 --shard slurm --out "$work/slurm" \
  >"$work/log" 2>&1 &
child=$!
until [ -n "$(find "$work/slurm/trials" -name result.json 2>/dev/null | head -1)" ]; do
  kill -0 "$child" 2>/dev/null || fail "the shard ended before its first trial had a result"
  sleep 0.05
done
kill -TERM "$child"
wait_child
[ "$status" -eq 143 ] || fail "exit status $status of a shard after SIGTERM, not 143"
[ "$(tail -n 1 "$work/log")" = "roger run: interrupted; the trials that were running start afresh when you submit this shard again (scripts/slurm/submit.sh scripts/quick.lua 2 --array=0, with the same ROGER_OUT and ROGER_ARGS)" ] ||
  fail "a stopped task of a Slurm array does not say how to submit its shard again"
grep -Eq "not run yet \(to continue, submit this shard again: scripts/slurm/submit.sh scripts/quick.lua 2 --array=0," "$work/log" ||
  fail "a stopped task of a Slurm array counts what is left without saying how to run it"
# Its record says it was interrupted, and the status the page reads tells it from shard 1, which
# has not started (found by a probe: a cancelled shard read as a queued one).
python3 - "$work/slurm" <<'PY' || fail "the stopped shard's record or status does not say it was interrupted"
import json, sys
record = json.load(open(sys.argv[1] + "/shards/0-of-2.json"))
status = json.load(open(sys.argv[1] + "/status.json"))
states = [s["state"] for s in status["shards"]]
ok = (record["state"] == "interrupted" and record["slurm"] is True and record["pending"] > 0 and
      states == ["interrupted", "not started"] and status["shards"][0]["pending"] == record["pending"] and
      status["slurm"] is True and status["waiting"] == "shards" and status["interrupted"] is True)
print("record:", record, "status shards:", status["shards"]) if not ok else None
sys.exit(0 if ok else 1)
PY

# A closed output pipe (`roger run ... 2>&1 | head -1`, head gone after its line) stops the run as
# one Ctrl-C does (found by a probe: SIGPIPE killed it before any trial, its status left running),
# and it exits 141, as a shell reports a command a closed pipe stopped.
set +e  # the pipeline fails (pipefail): its first command's status is the one read
"$roger" run scripts/quick.lua --jobs 2 --out "$work/pipe" 2>&1 | head -1 >"$work/pipe_head"
pipe_status=${PIPESTATUS[0]}
set -e
[ "$pipe_status" -eq 141 ] || fail "exit status $pipe_status after the output pipe closed, not 141"
grep -q "^roger run: scripts/quick.lua -> $work/pipe (24 trials" "$work/pipe_head" || fail "head did not get the run's first line"
grep -q '"running": false' "$work/pipe/status.json" && grep -q '"interrupted": true' "$work/pipe/status.json" ||
  fail "after a closed pipe status.json does not say the run stopped, interrupted"
[ -z "$(find "$work/pipe/trials" -name error.json 2>/dev/null)" ] || fail "a trial the closed pipe stopped was recorded as failed"
resume_to_golden "$work/pipe"

# roger train: a trial stopped part-way is no result. It says so, writes nothing and leaves its
# folder as it was (here an earlier trial's policy.json). What it trains is said before its first
# training episode (its skills trained first), not only at the end, so it is there when stopped.
mkdir -p "$work/train"
echo '{"earlier": true}' >"$work/train/policy.json"
"$roger" train curricula/sorting.lua --stage Sort4 --context Learned --out "$work/train" >"$work/log" 2>&1 &
child=$!
for _ in $(seq 600); do
  grep -q "^roger train: curricula/sorting.lua stage Sort4 context Learned seed 1 (4 actions) in sorting$" "$work/log" &&
    break
  sleep 0.1
done
grep -q "^  skill Phi_SG        trained first: stage SG context DC2" "$work/log" ||
  fail "roger train: what it trains was not said before training"
stop_child
[ "$status" -eq 130 ] || fail "roger train: exit status $status after Ctrl-C, not 130"
grep -q "^roger: stopping: the trial ends at its next episode and writes nothing" "$work/log" ||
  fail "roger train: no line says it is stopping"
[ "$(tail -n 1 "$work/log")" = "roger train: stopped; nothing written ($work/train is as it was)" ] ||
  fail "roger train: the last line does not say nothing was written"
[ "$(cat "$work/train/policy.json")" = '{"earlier": true}' ] && [ "$(ls -A "$work/train")" = policy.json ] ||
  fail "roger train: the folder changed"
# roger eval stopped by Ctrl-C says so and prints no figures (it ended without a word).
"$roger" eval curricula/scripted.lua --policy task --episodes 1000000 --json >"$work/eval.out" 2>"$work/log" &
child=$!
sleep 1
kill -0 "$child" 2>/dev/null || fail "roger eval: ended before the Ctrl-C"
stop_child
[ "$status" -eq 130 ] || fail "roger eval: exit status $status after Ctrl-C, not 130"
[ "$(tail -n 1 "$work/log")" = "roger eval: stopped; no figures (an evaluation stopped part-way is no result)" ] ||
  fail "roger eval: the last line does not say it stopped"
[ ! -s "$work/eval.out" ] || fail "roger eval: figures printed after a Ctrl-C"
echo "passed: one Ctrl-C keeps what finished and reports it; one during the report finishes it and exits 130; a kill during the report leaves summary.csv agreeing with the report; two stop at once, but not one delivered twice; both resume to the golden run; SIGTERM stops as one Ctrl-C and exits 143, a closed output pipe too and exits 141; roger train says what it trains at its start, and stopped writes nothing and says so; roger eval stopped says so and prints no figures"
