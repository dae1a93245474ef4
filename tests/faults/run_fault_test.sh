#!/usr/bin/env bash
# run_fault_test.sh CASE ROGER SOURCE_DIR WORK: faults a user meets on a bad day, each met by
# `roger run tests/scripts/kill_batch.lua`, which must stop at the first write or read that fails
# with one line naming the file and what to do, record no trial as failed, and end, when the same
# command is run again after the fault is mended, with the results of an uninterrupted run
# (tests/tools/compare_results.sh) and the trials finished before the fault kept, not run again.
#
#   reference       the uninterrupted run, in WORK/reference (the other cases compare with it)
#   disk_full       the results folder on a tmpfs too small for the run (mount, as root), then
#                   grown (mount -o remount,size=...)
#   not_writable    the results folder, holding the SG trials of an earlier --only SG run, made
#                   read-only (a read-only remount as root, chmod otherwise), then writable again
#   script_removed  the curriculum of a copy of the script (outside the project) deleted while the
#                   run goes, then put back
#   script_changed  the same curriculum edited while the run goes, then put back as it was
#
# Exit status: 0 passed, 1 failed, 77 skipped (disk_full and, as root, not_writable need to mount a
# tmpfs: root with CAP_SYS_ADMIN, as CI has; under CI=true a test that cannot mount one fails).
set -euo pipefail

if [ $# -ne 4 ]; then
  echo "usage: $0 reference|disk_full|not_writable|script_removed|script_changed ROGER SOURCE_DIR WORK" >&2
  exit 1
fi
case=$1 roger=$(readlink -f "$2") source=$(readlink -f "$3") work=$(mkdir -p "$4" && cd "$4" && pwd)
script=tests/scripts/kill_batch.lua
reference=$work/reference
fail() { echo "FAILED ($case): $*"; [ -f "${log:-}" ] && sed 's/^/  | /' "$log"; exit 1; }
# shellcheck source=tests/tools/skip.sh
. "$source/tests/tools/skip.sh"  # skip: exit 77, or a failure under CI=true
cd "$source"

if [ "$case" = reference ]; then
  rm -rf "$reference"
  mkdir -p "$work"
  log=$work/reference.log
  "$roger" run "$script" --jobs 2 --out "$reference" >"$log" 2>&1 || fail "the uninterrupted run"
  echo "reference run in $reference"
  exit 0
fi
[ -f "$reference/tables.md" ] || fail "no reference run in $reference (run the case 'reference' first)"

dir=$(mktemp -d "$work/$case.XXXXXX")
mounted=
child=
cleanup() {
  if [ -n "$child" ]; then kill -9 "$child" 2>/dev/null || true; fi
  if [ -n "$mounted" ]; then umount "$mounted" 2>/dev/null || umount -l "$mounted" 2>/dev/null || true; fi
  chmod -R u+w "$dir" 2>/dev/null || true
  rm -rf "$dir"
}
trap cleanup EXIT

# Mounts a tmpfs of `size` on folder $1 (skips the test when the machine does not let us).
mount_tmpfs() {
  mkdir -p "$1"
  [ "$(id -u)" = 0 ] || skip "($case) mounting a tmpfs needs root"
  mount -t tmpfs -o "size=$2" tmpfs "$1" 2>/dev/null || skip "($case) cannot mount a tmpfs here (no CAP_SYS_ADMIN?)"
  mounted=$1
}

# The faulty run must end with exactly one line saying what happened ($1, an extended regular
# expression), exit 1, and record no trial as failed.
check_stop() {
  local status=$1 pattern=$2
  [ "$status" -eq 1 ] || fail "exit status $status, not 1"
  [ "$(grep -c -v '^trials: ' "$log" | tr -d ' ')" -ge 1 ] || fail "no message"
  local last
  last=$(tail -n 1 "$log")
  echo "$last" | grep -Eq "$pattern" || fail "the last line does not match /$pattern/: $last"
  [ "$(grep -Ec 'the disk is full|was removed|changed while|writable' "$log")" -eq 1 ] || fail "the fault is said more than once"
  ! grep -q 'roger run: roger run:' "$log" || fail "a doubled prefix"
  ! grep -q 'trials failed\|trial failed' "$log" || fail "a trial is recorded as failed"
  [ -z "$(find "$out" -name error.json 2>/dev/null)" ] || fail "an error.json was written"
}

# The same command again (from the current folder) must resume, keeping every trial finished
# before the fault as it was (at least $1 of them; not run again), and end as the uninterrupted run.
check_resumed() {
  local before=$dir/finished_before
  find "$out/trials" -name result.json -printf '%p %T@\n' 2>/dev/null | sort >"$before"
  [ "$(wc -l <"$before")" -ge "$1" ] || fail "$(wc -l <"$before") trials finished before the fault, expected $1"
  "$roger" run "$script" --jobs 2 --out "$out" >"$log" 2>&1 || fail "the resumed run failed"
  grep -q "roger run: resuming $out" "$log" || fail "the second run did not resume"
  while read -r file stamp; do
    [ "$(find "$file" -printf '%T@')" = "$stamp" ] || fail "$file, finished before the fault, was written again"
  done <"$before"
  bash "$source/tests/tools/compare_results.sh" "$reference" "$out" >"$dir/compare.txt" 2>&1 ||
    { cat "$dir/compare.txt"; fail "the resumed results differ from the uninterrupted run's"; }
  echo "PASSED ($case): $(cat "$dir/compare.txt")"
}

# Runs a copy of the script and its curriculum in a folder of its own (not the project), under the
# same relative path so that the tables name the same script as the reference's; once the first
# trial has finished (about 20 s of trials are left on one job), keeps the curriculum in
# $dir/kept.lua and runs "$@" on it. Sets `status` to the run's exit status.
run_copy_altering_curriculum() {
  mkdir -p "$dir/copy/tests/scripts"
  cp tests/scripts/kill_batch.lua tests/scripts/kill_curriculum.lua "$dir/copy/tests/scripts/"
  out=$dir/results
  cd "$dir/copy"
  "$roger" run "$script" --jobs 1 --out "$out" >"$log" 2>&1 &
  child=$!
  for _ in $(seq 600); do
    [ -z "$(find "$out/trials" -name result.json 2>/dev/null)" ] || break
    kill -0 "$child" 2>/dev/null || break
    sleep 0.1
  done
  cp tests/scripts/kill_curriculum.lua "$dir/kept.lua"
  "$@"
  set +e
  wait "$child"
  status=$?
  set -e
  child=
}

edit_curriculum() { echo "-- an edit" >>tests/scripts/kill_curriculum.lua; }

log=$dir/run.log
case $case in
  disk_full)
    # 500 KiB holds the manifest and a few trials, not the run (1.2 MiB).
    mount_tmpfs "$dir/disk" 500k
    out=$dir/disk/results
    set +e
    "$roger" run "$script" --jobs 2 --out "$out" >"$log" 2>&1
    status=$?
    set -e
    check_stop $status "^roger run: error: the disk is full: cannot write .*'$out/[^']+': No space left on device\. Free some space, then run the same command again: it resumes where this one stopped$"
    mount -o remount,size=20m "$dir/disk"
    check_resumed 1
    ;;
  not_writable)
    out=$dir/ro/results
    if [ "$(id -u)" = 0 ]; then mount_tmpfs "$dir/ro" 20m; else mkdir -p "$dir/ro"; fi
    "$roger" run "$script" --jobs 2 --out "$out" --only SG >"$log" 2>&1 || fail "the run of SG"
    if [ -n "$mounted" ]; then mount -o remount,ro "$mounted"; else chmod -R a-w "$out"; fi
    set +e
    "$roger" run "$script" --jobs 2 --out "$out" >"$log" 2>&1
    status=$?
    set -e
    check_stop $status "^roger run: error: cannot [a-z ]+'$out/[^']*': (Read-only file system|Permission denied)\. Make the folder writable \(or give another with --out\), then run the same command again: it resumes where this one stopped$"
    if [ -n "$mounted" ]; then mount -o remount,rw "$mounted"; else chmod -R u+w "$out"; fi
    check_resumed 4
    ;;
  script_removed)
    run_copy_altering_curriculum rm tests/scripts/kill_curriculum.lua
    check_stop $status "^roger run: error: cannot read '$dir/copy/tests/scripts/kill_curriculum.lua': it was removed while the run was using it\. Put it back as it was, then run the same command again: it resumes where this one stopped$"
    cp "$dir/kept.lua" tests/scripts/kill_curriculum.lua
    check_resumed 1
    ;;
  script_changed)
    # The advice is to put it back (resumed) or to run the new version in another folder, not
    # that a folder does not exist.
    run_copy_altering_curriculum edit_curriculum
    check_stop $status "^roger run: error: '$dir/copy/tests/scripts/kill_curriculum.lua' changed while the run was using it\. Put it back as it was, then run the same command again: it resumes where this one stopped; or, to run the new version, give another --out$"
    cp "$dir/kept.lua" tests/scripts/kill_curriculum.lua
    check_resumed 1
    ;;
  *)
    echo "unknown case '$case'" >&2
    exit 1
    ;;
esac
