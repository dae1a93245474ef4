#!/usr/bin/env bash
# run_slurm_test.sh ROGER SOURCE_DIR: runs scripts/slurm/ on a real one-node Slurm cluster that
# it starts itself, and checks that a sharded run of scripts/quick.lua gives the same results as
# an unsharded one.
#
# As root: a temporary folder holds everything (config, munge key, daemons' state, logs, pid
# files, results); munged, slurmctld and slurmd run on it, on their own socket and ports, beside
# whatever Slurm or munge the machine may run. Then submit.sh submits quick.lua as an array of 3
# shards and its report; once both are done, the results are compared with `roger run` unsharded
# (tests/tools/compare_results.sh). Then one trial of shard 1 is deleted: `roger report` must fail
# naming it and its shard, and `submit.sh ... --array=1` must redo that trial alone and give the
# same results again. submit.sh's refusals (a bad N, no sbatch) are checked first. On exit, whatever happened, the jobs are cancelled, the
# daemons it started are stopped by their PIDs and the folder is removed.
#
# Exit status: 0 passed, 77 skipped (not root, or Slurm/munge not installed: `.ci/install`
# installs them; under CI=true these fail instead), 1 failed (with the daemons' and jobs' logs).
set -euo pipefail

if [ $# -ne 2 ]; then
  echo "usage: $0 ROGER SOURCE_DIR" >&2
  exit 1
fi
roger=$(readlink -f "$1")
src=$(readlink -f "$2")
export PATH=$PATH:/usr/sbin:/sbin

# shellcheck source=tests/tools/skip.sh
. "$src/tests/tools/skip.sh"  # skip: exit 77, or a failure under CI=true
[ "$(id -u)" -eq 0 ] || skip "needs root (it starts munged as the munge user, and slurmctld and slurmd)"
for tool in munged slurmctld slurmd sbatch squeue sinfo scontrol scancel; do
  command -v "$tool" >/dev/null 2>&1 || skip "$tool is not installed (apt-get install slurm-wlm munge, as .ci/install does)"
done

# --- the temporary folder, and what to do on the way out ------------------------------------------

tmp=$(mktemp -d /tmp/roger-slurm.XXXXXX)
# The munge user reads its folder below it, and the jobs (as root) everything.
chmod 0755 "$tmp"
mkdir "$tmp/munge" "$tmp/state" "$tmp/spool" "$tmp/log"
pids=()         # the daemons started here, in the order to stop them (last first)
jobs_ids=()     # the jobs submitted here
failed=0

log() { echo "run_slurm_test: $*"; }

print_logs() {
  local f
  for f in "$tmp"/log/* "$tmp"/munge/munged.log "$tmp"/sharded/slurm/*.out; do
    [ -f "$f" ] || continue
    echo "----- $f"
    # The tail: a failing daemon's last lines, without pages of startup chatter.
    tail -n 60 "$f"
  done
  echo "-----"
}

# Stops one process started here: SIGTERM, up to 20 s to go, then SIGKILL; reaps it.
stop_pid() {
  local pid=$1 i state
  kill -TERM "$pid" 2>/dev/null || return 0
  for ((i = 0; i < 200; i++)); do
    state=$(awk '{print $3}' "/proc/$pid/stat" 2>/dev/null || true)
    [ -z "$state" ] || [ "$state" = Z ] && break
    sleep 0.1
  done
  if [ -n "$state" ] && [ "$state" != Z ]; then
    log "PID $pid did not stop on SIGTERM; killing it"
    kill -KILL "$pid" 2>/dev/null || true
  fi
  wait "$pid" 2>/dev/null || true
}

cleanup() {
  local status=$? i
  set +e
  [ $failed -eq 1 ] && status=1
  if [ $status -ne 0 ] && [ $status -ne 77 ]; then
    log "FAILED (exit status $status); the logs:"
    print_logs
  fi
  # Jobs still running would outlive slurmd (slurmstepd and roger are not its children).
  if [ ${#jobs_ids[@]} -gt 0 ] && [ ${#pids[@]} -ge 2 ]; then
    scancel "${jobs_ids[@]}" 2>/dev/null
    for ((i = 0; i < 30; i++)); do
      [ -z "$(squeue -h -j "$(IFS=,; echo "${jobs_ids[*]}")" 2>/dev/null)" ] && break
      sleep 1
    done
  fi
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do stop_pid "${pids[i]}"; done
  rm -rf "$tmp"
  exit $status
}
trap cleanup EXIT
trap 'exit 1' INT TERM HUP

fail() {
  log "FAILED: $*"
  failed=1
  exit 1
}

# --- submit.sh's refusals, which need no cluster --------------------------------------------------

submit=$src/scripts/slurm/submit.sh
for n in 0 -1 abc 2x; do
  if out=$(bash "$submit" scripts/quick.lua "$n" 2>&1); then fail "submit.sh took N=$n"; fi
  grep -q "positive integer" <<< "$out" || fail "submit.sh N=$n: unclear message: $out"
done
if out=$(PATH=/nonexistent /bin/bash "$submit" scripts/quick.lua 3 2>&1); then fail "submit.sh ran without sbatch"; fi
grep -q "sbatch not found" <<< "$out" || fail "submit.sh without sbatch: unclear message: $out"
# Options that would break the pair of jobs: one --output for both, a name that hides which is
# which, a dependency in a form submit.sh cannot route to the array alone (on the report it would
# replace the wait for the shards). Refused before anything is made.
for option in --output=x.out -o -J --job-name=x "-d 5" --export=NONE --export=PATH --comment=x; do
  rm -rf "$tmp/refused"
  # shellcheck disable=SC2086  # "-d 5": two words, as a user types them
  if out=$(ROGER_OUT=$tmp/refused bash "$submit" scripts/quick.lua 3 $option 2>&1); then fail "submit.sh took $option"; fi
  grep -q "submit.sh's\|--dependency=LIST" <<< "$out" || fail "submit.sh $option: unclear message: $out"
  [ ! -e "$tmp/refused" ] || fail "submit.sh $option made $tmp/refused before refusing"
done
# An --array task past the last shard would run a shard of no N (`roger run` refuses K >= N, but
# only once the job starts, in its log); submit.sh refuses it at once, naming the shards.
for array in 3 0-3 1,5 2-1 x; do
  rm -rf "$tmp/refused"
  if out=$(ROGER_OUT=$tmp/refused bash "$submit" scripts/quick.lua 3 --array=$array 2>&1); then
    fail "submit.sh took --array=$array for 3 shards"
  fi
  grep -q "^submit.sh: --array=$array: .*the tasks are the shards 0 to 2 of N=3" <<< "$out" ||
    fail "submit.sh --array=$array: unclear message: $out"
  [ ! -e "$tmp/refused" ] || fail "submit.sh --array=$array made $tmp/refused before refusing"
done
log "submit.sh refuses a bad N, a missing sbatch, --output, --job-name, -d, --export, and --array tasks past N-1"

# submit.sh's own choices before any job, seen through an sbatch that records its arguments (the
# jobs themselves run on the real cluster below). Found by a probe: the default results folder was
# results/<the file's name>, where roger run writes results/<the script's name>; a script roger
# check refuses is refused before anything waits in the queue.
mkdir -p "$tmp/recorder" "$tmp/elsewhere"
printf '#!/bin/sh\necho "cwd=$PWD script=$ROGER_SCRIPT $*" >> %s/recorder/args\necho 7\n' "$tmp" > "$tmp/recorder/sbatch"
chmod +x "$tmp/recorder/sbatch"
printf 'return { name = "renamed", curriculum = "paper", trials = 1,\n  runs = { { name = "SG", stage = "SG", contexts = { "B1" } } } }\n' \
  > "$tmp/elsewhere/file_name.lua"
(cd "$tmp/elsewhere" && PATH=$tmp/recorder:$PATH ROGER_BIN=$roger bash "$submit" file_name.lua 2 >/dev/null) ||
  fail "submit.sh refused a sound script"
grep -q -- "--output=$tmp/elsewhere/results/renamed/slurm/shard-%a-%A.out" "$tmp/recorder/args" ||
  fail "submit.sh's default results folder is not roger run's: $(cat "$tmp/recorder/args")"
rm -f "$tmp/recorder/args"
printf 'return { name = "broken", curriculum = "paper", runs = { { name = "SG", stage = "SGG" } } }\n' \
  > "$tmp/elsewhere/broken.lua"
if out=$(cd "$tmp/elsewhere" && PATH=$tmp/recorder:$PATH ROGER_BIN=$roger bash "$submit" broken.lua 2 2>&1); then
  fail "submit.sh submitted a script roger check refuses"
fi
grep -q "has no stage 'SGG'" <<< "$out" && grep -q "nothing was submitted" <<< "$out" ||
  fail "submit.sh on a broken script: unclear message: $out"
[ ! -e "$tmp/recorder/args" ] || fail "submit.sh called sbatch for a script roger check refuses"
# Found by a probe: the jobs ran in the repository, where a batch script's curriculum =
# "curricula/paper.lua" found the project's file instead of the lab's own beside it; they run
# where submit.sh was called, as roger run would there.
(cd "$tmp/elsewhere" && PATH=$tmp/recorder:$PATH ROGER_BIN=$roger bash "$submit" file_name.lua 2 >/dev/null) ||
  fail "submit.sh refused a sound script"
[ "$(grep -c "^cwd=$tmp/elsewhere " "$tmp/recorder/args")" = 2 ] ||
  fail "submit.sh did not submit the jobs from the folder it was called in: $(cat "$tmp/recorder/args")"
rm -f "$tmp/recorder/args"
# A bare name is the project's script of that name (roger check took 'quick' for a curriculum).
(cd "$tmp/elsewhere" && PATH=$tmp/recorder:$PATH ROGER_BIN=$roger bash "$submit" quick 2 >/dev/null) ||
  fail "submit.sh refused the bare name quick"
grep -q "script=$src/scripts/quick.lua " "$tmp/recorder/args" ||
  fail "submit.sh quick did not submit scripts/quick.lua: $(cat "$tmp/recorder/args")"
rm -f "$tmp/recorder/args"
# ROGER_ARGS's --set goes to the check: a misspelt parameter is refused before the queue.
if out=$(cd "$tmp/elsewhere" && PATH=$tmp/recorder:$PATH ROGER_BIN=$roger ROGER_ARGS="--jobs 1 --set mas=0.7" \
  bash "$submit" file_name.lua 2 2>&1); then
  fail "submit.sh submitted with --set mas=0.7"
fi
grep -q "no parameter 'mas'" <<< "$out" && grep -q "with --set mas=0.7 (above): nothing was submitted" <<< "$out" ||
  fail "submit.sh with a misspelt --set: unclear message: $out"
[ ! -e "$tmp/recorder/args" ] || fail "submit.sh called sbatch with a --set roger check refuses"
# The results folder is checked as the shards will open it (found by a probe: a folder of shards of
# another N, or made by another build of roger, failed every task once it had waited in the queue).
(cd "$tmp/elsewhere" && "$roger" run file_name.lua --shard 0/3 --jobs 1 >/dev/null 2>&1) ||
  fail "roger run file_name.lua --shard 0/3 failed"
if out=$(cd "$tmp/elsewhere" && PATH=$tmp/recorder:$PATH ROGER_BIN=$roger bash "$submit" file_name.lua 2 2>&1); then
  fail "submit.sh submitted 2 shards to a folder of shards of N = 3"
fi
grep -q "holds shards of N = 3" <<< "$out" && grep -q "roger run refuses the tasks' command .*: nothing was submitted" <<< "$out" ||
  fail "submit.sh on a folder of another N: unclear message: $out"
sed -i 's/"engine": *"[^"]*"/"engine": "0000000000000000"/' "$tmp/elsewhere/results/renamed/manifest.json"
if out=$(cd "$tmp/elsewhere" && PATH=$tmp/recorder:$PATH ROGER_BIN=$roger bash "$submit" file_name.lua 3 2>&1); then
  fail "submit.sh submitted to a folder made by another build of roger"
fi
grep -q "made by another build of the engine (engine 0000000000000000)" <<< "$out" ||
  fail "submit.sh on another build's folder: unclear message: $out"
[ ! -e "$tmp/recorder/args" ] || fail "submit.sh called sbatch for a results folder roger run would refuse"
rm -rf "$tmp/elsewhere/results/renamed"
# And ROGER_ARGS as the tasks pass them: a misspelt option, an --only that names nothing.
for args in "--tirals 2" "--only SGX" "--jobs 2"; do
  if out=$(cd "$tmp/elsewhere" && PATH=$tmp/recorder:$PATH ROGER_BIN=$roger ROGER_ARGS="$args" bash "$submit" file_name.lua 2 2>&1); then
    fail "submit.sh submitted with ROGER_ARGS=$args"
  fi
  grep -q "nothing was submitted" <<< "$out" || fail "submit.sh with ROGER_ARGS=$args: unclear message: $out"
done
[ ! -e "$tmp/recorder/args" ] || fail "submit.sh called sbatch with ROGER_ARGS roger run refuses"
[ ! -e "$tmp/elsewhere/results/renamed" ] || fail "submit.sh's checks made the results folder"
# Found by a probe: ROGER_ARGS=--dry-run passed, every task ran nothing and the report job failed.
if out=$(cd "$tmp/elsewhere" && PATH=$tmp/recorder:$PATH ROGER_BIN=$roger ROGER_ARGS="--dry-run" bash "$submit" file_name.lua 2 2>&1); then
  fail "submit.sh submitted with ROGER_ARGS=--dry-run"
fi
grep -q "ROGER_ARGS has --dry-run: every task would run nothing" <<< "$out" ||
  fail "submit.sh with ROGER_ARGS=--dry-run: unclear message: $out"
[ ! -e "$tmp/recorder/args" ] || fail "submit.sh called sbatch with ROGER_ARGS=--dry-run"
# More shards than the cluster's job arrays take is said, not left to sbatch (found by a probe).
printf '#!/bin/sh\necho "MaxArraySize            = 1001"\n' > "$tmp/recorder/scontrol"
chmod +x "$tmp/recorder/scontrol"
if out=$(cd "$tmp/elsewhere" && PATH=$tmp/recorder:$PATH ROGER_BIN=$roger bash "$submit" file_name.lua 5000 2>&1); then
  fail "submit.sh submitted 5000 shards past MaxArraySize 1001"
fi
grep -q "N = 5000 shards: this cluster's MaxArraySize is 1001, so a job array's tasks are 0 to 1000" <<< "$out" ||
  fail "submit.sh past MaxArraySize: unclear message: $out"
[ ! -e "$tmp/recorder/args" ] || fail "submit.sh called sbatch past MaxArraySize"
rm -f "$tmp/recorder/scontrol"
# A shard submitted again while tasks of an earlier array still run: the new report waits for them
# (found by a probe: it ran first, failed on their trials, and no report followed them). squeue
# here names two earlier arrays of this folder and one of another (each array's comment names its
# folder: found by a probe, a sweep's other points held the report too); a whole new array waits
# for no earlier one. The real cluster below checks the comment Slurm keeps.
printf '#!/bin/sh\nprintf "41|roger-out:%s\\n41|roger-out:%s\\n43|roger-out:/elsewhere\\n42|roger-out:%s\\n"\n' \
  "$tmp/elsewhere/results/renamed" "$tmp/elsewhere/results/renamed" "$tmp/elsewhere/results/renamed" \
  > "$tmp/recorder/squeue"
chmod +x "$tmp/recorder/squeue"
(cd "$tmp/elsewhere" && PATH=$tmp/recorder:$PATH ROGER_BIN=$roger bash "$submit" file_name.lua 2 --array=1 >/dev/null) ||
  fail "submit.sh refused --array=1"
grep -q -- "--dependency=afterok:7,afterany:41:42 " "$tmp/recorder/args" ||
  fail "the resubmitted shard's report does not wait for the earlier arrays: $(cat "$tmp/recorder/args")"
rm -f "$tmp/recorder/args"
(cd "$tmp/elsewhere" && PATH=$tmp/recorder:$PATH ROGER_BIN=$roger bash "$submit" file_name.lua 2 >/dev/null) ||
  fail "submit.sh refused a sound script"
grep -q -- "--dependency=afterok:7 " "$tmp/recorder/args" ||
  fail "a whole array's report waits for other jobs: $(cat "$tmp/recorder/args")"
rm -f "$tmp/recorder/args" "$tmp/recorder/squeue"
log "submit.sh writes where roger run writes, submits from its caller's folder, takes a bare script name, checks ROGER_ARGS and the results folder with the tasks' own command (--dry-run), has a resubmitted shard's report wait for earlier arrays, and refuses a script roger check refuses before submitting"

# --- munge --------------------------------------------------------------------------------------

id munge >/dev/null 2>&1 || fail "no munge user (the munge package creates it)"
# munged checks its files: the key readable by munge only, the socket's folder open to all.
chown munge:munge "$tmp/munge"
chmod 0755 "$tmp/munge"
key=$tmp/munge/munge.key
if command -v mungekey >/dev/null 2>&1; then
  mungekey --create --keyfile="$key"
else
  dd if=/dev/urandom of="$key" bs=1024 count=1 status=none
fi
chown munge:munge "$key"
chmod 0400 "$key"
socket=$tmp/munge/munge.socket
# Foreground (-F) and exec'd by setpriv as the munge user: $! is munged itself.
setpriv --reuid=munge --regid=munge --init-groups \
  munged -F --key-file="$key" --socket="$socket" --pid-file="$tmp/munge/munged.pid" \
  --log-file="$tmp/munge/munged.log" --seed-file="$tmp/munge/munged.seed" \
  >"$tmp/log/munged.stdout" 2>&1 &
pids+=($!)
for ((i = 0; i < 100; i++)); do
  [ -S "$socket" ] && break
  kill -0 "${pids[0]}" 2>/dev/null || fail "munged exited"
  sleep 0.1
done
[ -S "$socket" ] || fail "munged made no socket in 10 s"
log "munged runs (PID ${pids[0]}) on $socket"

# --- slurm.conf ---------------------------------------------------------------------------------

host=$(hostname -s)
cpus=$(nproc)
# RealMemory in MB, less a margin for the system; slurmd refuses a node claiming more than it has.
memory=$(awk '/^MemTotal:/ { m = int($2 / 1024) - 512; print (m < 256 ? 256 : m) }' /proc/meminfo)

# A free TCP port from $1 on (nothing accepts a connection on it).
free_port() {
  local p=$1
  while (exec 3<>"/dev/tcp/127.0.0.1/$p") 2>/dev/null; do p=$((p + 1)); done
  echo "$p"
}
ctld_port=$(free_port 16817)
slurmd_port=$(free_port $((ctld_port + 1)))

conf=$tmp/slurm.conf
cat >"$conf" <<EOF
# A one-node cluster for run_slurm_test.sh; everything under $tmp.
ClusterName=rogertest
SlurmctldHost=$host
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$socket
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldLogFile=$tmp/log/slurmctld.log
SlurmdLogFile=$tmp/log/slurmd.log
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MailProg=/bin/true
# Finished jobs stay known to scontrol long enough to read their state and exit code.
MinJobAge=3600
NodeName=$host CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
# No Slurm or roger settings of the caller's environment (say, a CI job that is itself a Slurm
# job) leak into the commands and jobs here.
for v in $(compgen -e | grep -E '^(SLURM|SBATCH|SALLOC|SRUN|ROGER)_' || true); do unset "$v"; done
export SLURM_CONF=$conf

# --- slurmctld and slurmd, in the foreground (-D) so that $! are their PIDs -----------------------

slurmctld -D -f "$conf" >"$tmp/log/slurmctld.stdout" 2>&1 &
pids+=($!)
slurmd -D -f "$conf" >"$tmp/log/slurmd.stdout" 2>&1 &
pids+=($!)
log "slurmctld (PID ${pids[1]}, port $ctld_port) and slurmd (PID ${pids[2]}, port $slurmd_port) started on $host: $cpus CPUs, ${memory} MB"

state=
for ((i = 0; i < 60; i++)); do
  kill -0 "${pids[1]}" 2>/dev/null || fail "slurmctld exited"
  kill -0 "${pids[2]}" 2>/dev/null || fail "slurmd exited"
  state=$(sinfo -h -N -n "$host" -o %T 2>/dev/null || true)
  [ "$state" = idle ] && break
  sleep 1
done
[ "$state" = idle ] || fail "node $host not idle after 60 s (sinfo says '${state:-nothing}')"
log "sinfo: node $host is idle"

# --- submitting, waiting, checking ----------------------------------------------------------------

sharded=$tmp/sharded
cd "$src"

# The state of a job (or of every task of an array), from scontrol (no accounting here).
job_states() { scontrol -o show job "$1" | grep -o 'JobState=[A-Z_]*' | cut -d= -f2 | sort | uniq -c | xargs; }
job_field() { scontrol -o show job "$1" | grep -oE "(^| )$2=[^ ]*" | cut -d= -f2-; }

# submit_and_check TASKS [sbatch options...]: submits quick.lua as 3 shards with submit.sh, waits
# (600 s at most) until the array and the report have left the queue, and checks that the array's
# TASKS (task numbers) and the report completed with exit code 0 and wrote their output files.
submit_and_check() {
  local tasks=$1 submitted array_id report_id queued states code k report_out start=$SECONDS deadline
  shift
  submitted=$(ROGER_BIN=$roger ROGER_OUT=$sharded bash "$submit" scripts/quick.lua 3 "$@") ||
    fail "submit.sh failed: $submitted"
  echo "$submitted"
  array_id=$(awk '$1 == "array" { print $2 }' <<< "$submitted")
  report_id=$(awk '$1 == "report" { print $2 }' <<< "$submitted")
  [[ $array_id =~ ^[0-9]+$ && $report_id =~ ^[0-9]+$ ]] || fail "submit.sh printed no job ids: $submitted"
  [ "$(wc -l <<< "$submitted")" -eq 2 ] || fail "submit.sh printed more than the two job ids: $submitted"
  jobs_ids+=("$array_id" "$report_id")

  deadline=$((SECONDS + 600))
  while :; do
    queued=$(squeue -h -j "$array_id,$report_id" -o '%i %T %r' 2>&1) || fail "squeue failed: $queued"
    [ -z "$queued" ] && break
    # A report held by a failed task would wait forever; submit.sh asks Slurm to cancel it.
    grep -q DependencyNeverSatisfied <<< "$queued" && fail "the report waits for an array that failed: $queued"
    [ $SECONDS -lt $deadline ] || fail "the jobs did not finish in 600 s: $queued"
    sleep 2
  done
  log "both jobs left the queue after $((SECONDS - start)) s"

  states=$(job_states "$array_id")
  log "array $array_id: $states"
  [ "$states" = "$(wc -w <<< "$tasks") COMPLETED" ] || fail "not every task of the array completed: $states"
  for code in $(job_field "$array_id" ExitCode); do
    [ "$code" = 0:0 ] || fail "a task of the array exited with $code"
  done
  states=$(job_field "$report_id" JobState)
  code=$(job_field "$report_id" ExitCode)
  log "report $report_id: $states, exit code $code"
  [ "$states" = COMPLETED ] && [ "$code" = 0:0 ] || fail "the report job did not succeed"

  for k in $tasks; do
    [ -f "$sharded/slurm/shard-$k-$array_id.out" ] || fail "no output of task $k"
    log "task $k's output:"
    sed 's/^/  | /' "$sharded/slurm/shard-$k-$array_id.out"
  done
  report_out=$sharded/slurm/report-$report_id.out
  [ -f "$report_out" ] || fail "no output of the report job"
  log "the report job's output:"
  sed 's/^/  | /' "$report_out"
  if grep -qiE 'error|missing' "$report_out"; then fail "the report job's output mentions an error"; fi
  for f in tables.md summary.csv report.json manifest.json; do
    [ -s "$sharded/$f" ] || fail "the sharded folder has no $f"
  done
  # The dashboard's status: the report job closed it, so the page shows the report.
  python3 -c 'import json, sys; s = json.load(open(sys.argv[1])); sys.exit(0 if s.get("report") == "written" and "waiting" not in s and not s["running"] else 1)' \
    "$sharded/status.json" || fail "status.json does not say the report is written: $(cat "$sharded/status.json")"
}

# --- the sharded run, and the same script unsharded -------------------------------------------------

log "quick.lua as 3 shards of 2 CPUs each (trials 0 and 1: shard 2 has nothing to do) and its report"
submit_and_check "0 1 2" --cpus-per-task=2
# The sbatch option reached both jobs, and each task runs as many trials at once as it has CPUs.
for id in "${jobs_ids[@]}"; do
  for cpus in $(job_field "$id" NumCPUs); do
    [ "$cpus" = 2 ] || fail "job $id has $cpus CPUs, not the 2 of --cpus-per-task=2"
  done
done
for k in 0 1 2; do
  grep -q -- "--jobs 2 " "$sharded/slurm/shard-$k-${jobs_ids[0]}.out" || fail "task $k did not run roger with --jobs 2"
  # Each shard's first start: none resumes (found by a probe: all but the first said "resuming").
  ! grep -q "^roger run: resuming" "$sharded/slurm/shard-$k-${jobs_ids[0]}.out" || fail "task $k said it resumed on its first start"
done

log "roger run scripts/quick.lua unsharded, for comparison"
start=$SECONDS
"$roger" run scripts/quick.lua --out "$tmp/plain" >"$tmp/log/plain.out" 2>&1 ||
  { cat "$tmp/log/plain.out"; fail "the unsharded run failed"; }
log "unsharded run took $((SECONDS - start)) s"
bash "$src/tests/tools/compare_results.sh" "$tmp/plain" "$sharded" || fail "the sharded results differ from the unsharded"

# --- a lost trial: the report names it and its shard; resubmitting that shard redoes only it ------

victim=eval/generalization/circle/001
[ -f "$sharded/trials/$victim/result.json" ] || fail "no trial $victim in the sharded folder"
rm -rf "${sharded:?}/trials/$victim"
if out=$("$roger" report "$sharded" 2>&1); then fail "roger report succeeded with $victim missing: $out"; fi
grep -q "$victim" <<< "$out" && grep -q "shard 1 of 3" <<< "$out" ||
  fail "roger report did not name $victim and shard 1 of 3: $out"
grep -q "shards of a Slurm array: scripts/slurm/submit.sh SCRIPT N --array=K for each shard K named above" <<< "$out" ||
  fail "roger report does not say how to submit the shard again: $out"
log "with $victim removed, roger report fails:"
sed 's/^/  | /' <<< "$out"

# A shard submitted again waits for the earlier arrays of its own folder only, which Slurm tells
# by the comment submit.sh gives each array (found by a probe: another folder's array of the same
# script held the report). Here held arrays, cancelled once their dependencies are read.
held_ids() { awk '$1 == "array" || $1 == "report" { print $2 }' <<< "$1" | xargs; }
other=$(ROGER_BIN=$roger ROGER_OUT=$tmp/other bash "$submit" scripts/quick.lua 3 --hold) || fail "submit.sh --hold: $other"
same=$(ROGER_BIN=$roger ROGER_OUT=$sharded bash "$submit" scripts/quick.lua 3 --array=2 --hold) ||
  fail "submit.sh --array=2 --hold: $same"
again=$(ROGER_BIN=$roger ROGER_OUT=$sharded bash "$submit" scripts/quick.lua 3 --array=1 --hold) ||
  fail "submit.sh --array=1 --hold: $again"
other_array=$(awk '$1 == "array" { print $2 }' <<< "$other") same_array=$(awk '$1 == "array" { print $2 }' <<< "$same")
waits=$(job_field "$(awk '$1 == "report" { print $2 }' <<< "$again")" Dependency)
# shellcheck disable=SC2046  # the ids, one word each
scancel $(held_ids "$other") $(held_ids "$same") $(held_ids "$again")
grep -q "afterany:${same_array}_" <<< "$waits" || fail "the shard's report does not wait for its folder's array $same_array: $waits"
! grep -q "${other_array}_" <<< "$waits" || fail "the shard's report waits for another folder's array $other_array: $waits"
log "a shard submitted again waits for its folder's earlier array, not another's: $waits"
# A job sbatch refuses leaves no folder behind (found by a probe: an empty one stayed).
# Nor the parents mkdir -p made for it (found by a probe: ROGER_OUT=a/b/c left a/ and a/b/).
if out=$(ROGER_BIN=$roger ROGER_OUT=$tmp/refused/a/b ROGER_LOGS=$tmp/refused_logs/x bash "$submit" scripts/quick.lua 3 --partition=nosuch 2>&1); then
  fail "submit.sh succeeded with --partition=nosuch"
fi
grep -q "submit.sh: sbatch failed" <<< "$out" || fail "submit.sh --partition=nosuch: unclear message: $out"
[ ! -e "$tmp/refused" ] || fail "submit.sh left $tmp/refused behind when sbatch refused the array"
[ ! -e "$tmp/refused_logs" ] || fail "submit.sh left $tmp/refused_logs behind when sbatch refused the array"

touch "$tmp/before-resume"
sleep 1
log "shard 1 again (submit.sh ... 3 --array=1) and a new report"
# With a dependency of the user's (here on the first array, long done): it holds the array, and the
# report still waits for the array (a --dependency of its own would have replaced that wait).
first_array=${jobs_ids[0]}
submit_and_check 1 --array=1 --dependency=afterok:"$first_array"
resumed_array=${jobs_ids[2]} resumed_report=${jobs_ids[3]}
array_end=$(job_field "$resumed_array" EndTime) report_start=$(job_field "$resumed_report" StartTime)
[[ ! $report_start < $array_end ]] || fail "the report started at $report_start, before the array ended at $array_end"
log "with --dependency=afterok:$first_array the report still started after the array ($report_start, $array_end)"
redone=$(cd "$sharded/trials" && find . -name result.json -newer "$tmp/before-resume" | sort | xargs)
[ "$redone" = "./$victim/result.json" ] || fail "shard 1 redid '${redone:-nothing}', not just $victim"
grep -q "^roger run: resuming $sharded" "$sharded/slurm/shard-1-$resumed_array.out" || fail "shard 1 again did not say it resumed"
log "shard 1 redid $victim and nothing else"
bash "$src/tests/tools/compare_results.sh" "$tmp/plain" "$sharded" || fail "the resumed results differ from the unsharded"
# A task cancelled while it runs (scancel; its --time does the same): Slurm's SIGTERM interrupts the
# shard, whose record says so, and the status the dashboard reads tells it from the others (found
# by a probe: a cancelled shard read as a queued one, "No news").
cancelled=$tmp/cancelled
out=$(ROGER_BIN=$roger ROGER_OUT=$cancelled bash "$submit" scripts/quick.lua 3) || fail "submit.sh: $out"
cancel_array=$(awk '$1 == "array" { print $2 }' <<< "$out")
jobs_ids+=($(held_ids "$out"))
deadline=$((SECONDS + 120))
until compgen -G "$cancelled/trials/*/*/001/result.json" >/dev/null; do
  [ $SECONDS -lt $deadline ] || fail "shard 1 of the array to cancel had no result in 120 s"
  sleep 0.1
done
scancel "${cancel_array}_1"
deadline=$((SECONDS + 120))
while [ -n "$(squeue -h -j "$(held_ids "$out" | tr ' ' ,)" 2>/dev/null)" ]; do
  [ $SECONDS -lt $deadline ] || fail "the cancelled array's jobs did not leave the queue in 120 s"
  sleep 1
done
grep -q "submit this shard again (scripts/slurm/submit.sh scripts/quick.lua 3 --array=1," \
  "$cancelled/slurm/shard-1-$cancel_array.out" || fail "the cancelled task does not say how to submit it again"
python3 - "$cancelled" <<'PY' || fail "the cancelled shard's record or the status does not say it was interrupted"
import json, sys
record = json.load(open(sys.argv[1] + "/shards/1-of-3.json"))
status = json.load(open(sys.argv[1] + "/status.json"))
states = [s["state"] for s in status["shards"]]
ok = (record["state"] == "interrupted" and record["slurm"] is True and record["pending"] > 0 and
      states == ["ended", "interrupted", "ended"] and status["slurm"] is True and status["waiting"] == "shards")
print("record:", record, "status:", status) if not ok else None
sys.exit(0 if ok else 1)
PY
log "a task cancelled while it runs records that it was interrupted, and says how to submit it again"

log "PASSED"
