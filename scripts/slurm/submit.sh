#!/usr/bin/env bash
# submit.sh SCRIPT N [sbatch options...]: runs a batch script of roger on a Slurm cluster as a job
# array of N shards (array.sbatch, tasks 0 .. N-1, each `roger run SCRIPT --shard slurm`) and a
# report job (report.sbatch, `roger report`) that starts once every task has succeeded. Prints the
# two job ids, one line each:
#   array 12
#   report 13
#
#   scripts/slurm/submit.sh scripts/paper.lua 50 --partition=short --time=02:00:00 --cpus-per-task=2
#
# The sbatch options (--partition, --time, --cpus-per-task, --mem, --account, ...) go to both jobs,
# after the scripts' own, so they win; --dependency=LIST holds the array alone (the report follows
# the array); --output, --error and --job-name are refused; --array=LIST goes to the array alone and replaces 0-(N-1):
# `submit.sh SCRIPT N --array=7` runs shard 7 of N again (what it finds finished it keeps) and a
# new report after it. Each task runs as many trials at once as it has CPUs (--cpus-per-task).
#
# Environment:
#   ROGER_OUT   the results folder, on a filesystem every node sees   results/<the script's name> here
#   ROGER_BIN   the roger program, likewise                           build/engine/roger (installed: bin/roger)
#   ROGER_ARGS  more arguments of roger run (e.g. "--set mass=0.7"), split at whitespace
#   ROGER_LOGS  the jobs' output files                                ROGER_OUT/slurm
# Relative paths are taken from the current folder, and the jobs run in it (on a filesystem every
# node sees), as roger run would here: a batch script's `curriculum = "curricula/mine.lua"` is
# looked for from it first, on the cluster as on this machine.
set -euo pipefail

usage="usage: $0 SCRIPT N [sbatch options...] (SCRIPT: a batch script such as scripts/paper.lua; N: the number of shards)"
die() { echo "submit.sh: $*" >&2; exit 2; }

[ $# -ge 2 ] || die "$usage"
script=$1 shards=$2
shift 2
[[ $shards =~ ^[1-9][0-9]*$ ]] || die "N must be a positive integer (the number of shards), not '$shards'; $usage"

# Refuses an --array LIST (Slurm's forms: 7, 3,7,12-14, 0-49:2, with a %throttle) that names a task
# outside 0..N-1: task K runs shard K of N, and roger refuses K >= N only once the job has waited
# in the queue.
check_array() {
  local list=${1%\%*} item first last items
  local form="the tasks are the shards 0 to $((shards - 1)) of N=$shards (e.g. --array=$((shards - 1)) or --array=0-$((shards - 1))%10)"
  IFS=, read -r -a items <<< "$list"
  [ ${#items[@]} -gt 0 ] || die "--array=$1 names no task: $form"
  for item in "${items[@]}"; do
    [[ $item =~ ^([0-9]+)(-([0-9]+)(:[1-9][0-9]*)?)?$ ]] || die "--array=$1: '$item' is neither a task nor a range: $form"
    first=$((10#${BASH_REMATCH[1]})) last=$((10#${BASH_REMATCH[3]:-${BASH_REMATCH[1]}}))
    [ "$first" -le "$last" ] || die "--array=$1: the range '$item' runs backwards: $form"
    [ "$last" -lt "$shards" ] || die "--array=$1: task $last is past the last shard: $form"
  done
}

# --array=LIST and --dependency=... go to the array only; every other option to both jobs. A
# --dependency given to the report too would replace its afterok on the array: it would start
# before the shards end. The jobs' names and output files are submit.sh's (ROGER_LOGS moves them):
# one --output for both would mix the shards' logs and the report's.
array="0-$((shards - 1))"
dependency=()
common=()
for option in "$@"; do
  case $option in
    --array=*) array=${option#--array=}; check_array "$array" ;;
    -a | -a* | --array) die "give the array as --array=LIST (got '$option')" ;;
    --dependency=*) dependency=("$option" --kill-on-invalid-dep=yes) ;;  # a failed one cancels the array
    -d | -d* | --dependency) die "give a dependency as --dependency=LIST (got '$option'); it holds the array, and the report follows the array" ;;
    -o | -o* | --output | --output=* | -e | -e* | --error | --error=*)
      die "the jobs' output files are submit.sh's (ROGER_LOGS chooses their folder), got '$option'" ;;
    -J | -J* | --job-name | --job-name=*) die "the jobs' names are submit.sh's (roger-<script>, roger-report-<script>), got '$option'" ;;
    --comment | --comment=*) die "the array's comment is submit.sh's (it names the results folder, for a shard submitted again), got '$option'" ;;
    --export | --export=*)
      die "the jobs' environment is submit.sh's (--export=ALL: the jobs read ROGER_SCRIPT, ROGER_OUT, ... from it; without them they would run scripts/paper.lua), got '$option': set what the jobs need in the environment of submit.sh" ;;
    *) common+=("$option") ;;
  esac
done

command -v sbatch >/dev/null 2>&1 ||
  die "sbatch not found: run this on a Slurm submit host (or put Slurm's commands on PATH)"
# A job array's indices stop below the cluster's MaxArraySize (found by a probe: N = 5000 got
# sbatch's bare "Invalid job array specification").
max_array=$(scontrol show config 2>/dev/null | awk -F= '/^MaxArraySize/ { gsub(/ /, "", $2); print $2 }' || true)
if [[ $max_array =~ ^[0-9]+$ ]] && [ "$shards" -gt "$max_array" ]; then
  die "N = $shards shards: this cluster's MaxArraySize is $max_array, so a job array's tasks are 0 to $((max_array - 1)); give N at most $max_array (each shard then runs more trials)"
fi

here=$(dirname "$(readlink -f "${BASH_SOURCE[0]}")")
repo=$(cd "$here/../.." && pwd)

# An absolute path of a file named relative to the current folder (which need not exist yet).
absolute() { case $1 in /*) echo "$1" ;; *) echo "$PWD/$1" ;; esac; }

# The script, as roger run takes it: a file, a path relative to the project (scripts/paper.lua from
# any folder), or a bare name of one in scripts/ (named by its path here: roger check takes a bare
# `paper` for the curriculum of that name, found by a probe).
if [ -f "$script" ]; then
  script=$(absolute "$script")
elif [[ $script != /* && -f $repo/$script ]]; then
  script=$repo/$script
elif [[ $script != */* && -f $repo/scripts/$script.lua ]]; then
  script=$repo/scripts/$script.lua
elif [[ $script != */* && -f $repo/scripts/$script ]]; then
  script=$repo/scripts/$script
else
  die "no batch script '$script' (neither a file here, nor a file of the project $repo, nor a script in $repo/scripts)"
fi
name=$(basename "$script" .lua)

# The program: the repository's build, else (installed: <prefix>/share/roger/scripts/slurm) <prefix>/bin/roger.
default_bin=$repo/build/engine/roger
[ -x "$default_bin" ] || [ ! -x "$repo/../../bin/roger" ] || default_bin=$(cd "$repo/../../bin" && pwd)/roger
bin=$(absolute "${ROGER_BIN:-$default_bin}")
[ -x "$bin" ] || die "no roger program at '$bin' (build it: cmake -S . -B build && cmake --build build --target roger; or set ROGER_BIN)"
# The script checked before anything waits in the queue; roger check says where roger run writes
# without --out: results/<the script's name> here (its name field, not its file's; the project may
# be an installed tree, not writable).
# With the options of ROGER_ARGS that roger check takes (found by a probe: a misspelt --set failed
# every task once it had waited in the queue).
read -r -a run_args <<< "${ROGER_ARGS:-}"
check_args=()
for ((i = 0; i < ${#run_args[@]}; i++)); do
  case ${run_args[i]} in
    --set | --lua-instructions | --lua-memory) check_args+=("${run_args[i]}" "${run_args[i + 1]:-}"); i=$((i + 1)) ;;
    --set=* | --lua-instructions=* | --lua-memory=*) check_args+=("${run_args[i]}") ;;
    # Every task would run nothing, and the report job fail (found by a probe).
    --dry-run) die "ROGER_ARGS has --dry-run: every task would run nothing, and the report job find no results; to see what a shard would do, run: $bin run $script --shard 0/$shards --dry-run" ;;
  esac
done
checked=$("$bin" check "$script" ${check_args[@]+"${check_args[@]}"}) ||
  die "roger check refused $script${check_args[*]:+ with ${check_args[*]}} (above): nothing was submitted"
default_out=$(printf '%s\n' "$checked" | sed -n "s/^  results folder: \(.*\) (roger run's default --out)\$/\1/p")
[ -n "$default_out" ] || die "roger check $script did not say where roger run writes (is $bin an older roger?)"
out=$(absolute "${ROGER_OUT:-$default_out}")
# Each task's command as array.sbatch runs it, as shard 0 and with --dry-run, before anything waits
# in the queue: a misspelt option of ROGER_ARGS, an --only naming nothing, a results folder made by
# another build of roger or another configuration, or holding shards of another N, would fail
# every task once it starts (found by a probe).
"$bin" run "$script" --shard "0/$shards" --jobs 1 --out "$out" ${run_args[@]+"${run_args[@]}"} --dry-run >/dev/null ||
  die "roger run refuses the tasks' command (above: roger run $script --out $out ${ROGER_ARGS:-}): nothing was submitted"
logs=$(absolute "${ROGER_LOGS:-$out/slurm}")
# Slurm opens the jobs' output files but creates no folder for them. Those made here are removed
# again, while empty, when sbatch refuses the jobs (found by a probe: a misspelt partition left an
# empty folder behind).
# The folders mkdir -p makes, deepest first: the two and each parent of theirs not there yet
# (found by a probe: ROGER_OUT=a/b/c left a/ and a/b/ behind).
made=()
for folder in "$out" "$logs"; do
  while [ ! -d "$folder" ]; do
    made=("$folder" ${made[@]+"${made[@]}"})
    folder=$(dirname "$folder")
  done
done
# Deepest first, each once: logs inside out is removed before out.
if [ ${#made[@]} -gt 0 ]; then
  mapfile -t made < <(printf '%s\n' "${made[@]}" | sort -u | awk '{ print length($0) "\t" $0 }' | sort -k1,1rn | cut -f2-)
fi
mkdir -p "$out" "$logs"
unmake() { for folder in ${made[@]+"${made[@]}"}; do rmdir "$folder" 2>/dev/null || true; done; }

# The jobs read these (sbatch passes the environment on: --export=ALL below).
export ROGER_BIN=$bin ROGER_SCRIPT=$script ROGER_OUT=$out ROGER_SHARDS=$shards
export ROGER_ARGS=${ROGER_ARGS:-}

# sbatch --parsable prints "ID" or "ID;CLUSTER". The jobs start in this folder (array.sbatch and
# report.sbatch go to Slurm's SLURM_SUBMIT_DIR).
submit() {
  local id
  id=$(sbatch --parsable --export=ALL "$@") || { unmake; die "sbatch failed: sbatch $*"; }
  echo "${id%%;*}"
}

# A shard submitted again (--array=LIST) while tasks of an earlier array of this script still wait
# or run: the new report waits for them too (found by a probe: it ran before them, failed on their
# trials, and no report followed them). Their ids, colon-separated (afterany:A:B), from squeue.
# Only this user's arrays of this folder, told by the comment each array carries (found by a
# probe: another folder's array of the same script, a point of a sweep, held the report too).
comment="roger-out:$out"
earlier_arrays() {
  [ "$array" != "0-$((shards - 1))" ] || return 0
  squeue -h -u "$(id -un)" -n "roger-$name" -t PENDING,RUNNING,CONFIGURING,SUSPENDED -o '%F|%k' 2>/dev/null |
    awk -F'|' -v want="$comment" '$2 == want { print $1 }' | sort -u | paste -sd: -
}
earlier=$(earlier_arrays || true)

array_id=$(submit --job-name="roger-$name" --comment="$comment" --array="$array" --output="$logs/shard-%a-%A.out" \
  ${dependency[@]+"${dependency[@]}"} ${common[@]+"${common[@]}"} "$repo/scripts/slurm/array.sbatch")
made=()  # the array is queued: its folders stay
# afterok: the report only after every task succeeded; a failed task cancels it (instead of
# leaving it pending forever): redo the shard with --array=K, which submits a new report.
report_id=$(submit --job-name="roger-report-$name" --dependency="afterok:$array_id${earlier:+,afterany:$earlier}" --kill-on-invalid-dep=yes \
  --output="$logs/report-%j.out" ${common[@]+"${common[@]}"} "$repo/scripts/slurm/report.sbatch") ||
  die "the array $array_id is queued, and its report could not be submitted (above): cancel the array (scancel $array_id) and submit again, or run roger report $out once the array is done"
echo "array $array_id"
echo "report $report_id"
