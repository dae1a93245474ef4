#!/usr/bin/env bash
# check_tutorial.sh ROGER SOURCE WORK: docs/tutorial-new-context.md as a user follows it. Its Lua
# files (each ```lua block, named by its first comment line) are written to WORK/mywork/, every
# `$roger ...` line of its sh blocks runs as written from WORK (roger=ROGER), each must succeed,
# and every figure section 3 quotes must be what the commands print: each context's episodes and
# simulated seconds to the threshold, its final evaluation's successes, the saved policy's
# successes on other seeds, the ratios the text puts in words, and section 1's seeded worlds.
# Prints each difference; exits 0 when there is none, 1 otherwise (CTest tutorial_new_context).
set -euo pipefail
if [ $# -ne 3 ]; then
  echo "usage: $0 ROGER SOURCE_DIR WORK_DIR" >&2
  exit 2
fi
roger=$1 source=$2 work=$3
doc=$source/docs/tutorial-new-context.md
rm -rf "$work"
mkdir -p "$work/mywork" "$work/out"
status=0
fail() { echo "FAILED: $*"; status=1; }

# The Lua files, as the tutorial shows them.
awk -v dir="$work/mywork" '
  /^```lua$/ { inside = 1; file = ""; next }
  /^```$/    { inside = 0; next }
  inside && file == "" { if (match($0, /^-- [A-Za-z0-9_]+\.lua:/)) file = dir "/" substr($0, 4, RLENGTH - 4); else inside = 0 }
  inside && file != "" { print > file }' "$doc"
for f in blue_ball.lua fetch_blue.lua; do
  [ -s "$work/mywork/$f" ] || fail "no \`\`\`lua block of $doc starts with '-- $f:'"
done

# Every $roger command of the sh blocks, in order, as written.
mapfile -t commands < <(awk '/^```sh$/ { inside = 1; next } /^```$/ { inside = 0 } inside && /^\$roger / { print }' "$doc")
[ ${#commands[@]} -ge 6 ] || fail "expected at least 6 \$roger commands in $doc, found ${#commands[@]}"
declare -A train_out
eval_out="" eval_cmd="" check_out=""
cd "$work"
for i in "${!commands[@]}"; do
  cmd=${commands[$i]}
  echo "\$ $cmd"
  if ! out=$(eval "$cmd" 2>&1); then
    echo "$out"
    fail "the command exits non-zero: $cmd"
    continue
  fi
  echo "$out"
  case "$cmd" in
    *" train "*) ctx=$(sed -n 's/.*--context \([^ ]*\).*/\1/p' <<<"$cmd"); train_out[$ctx]=$out ;;
    *" eval "*) eval_out=$out eval_cmd=$cmd ;;
    *" check "*blue_ball*) check_out=$out ;;
  esac
done
[ $status -eq 0 ] || exit 1

# Section 3's paragraph, on one line.
para=$(tr '\n' ' ' < "$doc" | tr -s ' ')
para=${para#*What they give (seed 1): }
para=${para%%To change the task*}
has() {  # has TEXT WHAT: the paragraph (or TEXT) says WHAT
  grep -qF -- "$2" <<<"$1" || fail "docs/tutorial-new-context.md does not say '$2' (the commands print it; above)"
}
number_word() {
  local words=(zero one two three four five six seven eight nine ten eleven twelve)
  if [ "$1" -le 12 ]; then echo "${words[$1]}"; else echo "$1"; fi
}

declare -A episodes seconds
for ctx in Skilled Primitives; do
  out=${train_out[$ctx]:-}
  [ -n "$out" ] || { fail "no \$roger train ... --context $ctx command in $doc"; continue; }
  line=$(grep -E '^ *threshold ' <<<"$out" || true)
  threshold=$(sed -n 's/^ *threshold *\([0-9.]*%\) reached after.*/\1/p' <<<"$line")
  episodes[$ctx]=$(sed -n 's/.* reached after \([0-9]*\) episodes, .*/\1/p' <<<"$line")
  seconds[$ctx]=$(sed -n 's/.* episodes, \([0-9.]*\) simulated s,.*/\1/p' <<<"$line")
  if [ -z "${episodes[$ctx]}" ] || [ -z "${seconds[$ctx]}" ]; then
    fail "$ctx does not reach its threshold: '$line'"; continue
  fi
  final=$(grep -E '^ *final policy ' <<<"$out" || true)
  pct=$(sed -n 's/^ *final policy *\([0-9.]*\)% success over.*/\1/p' <<<"$final")
  held=$(sed -n 's/.* success over \([0-9]*\) held-out episodes.*/\1/p' <<<"$final")
  [ -n "$pct" ] && [ -n "$held" ] || { fail "no final policy line for $ctx: '$final'"; continue; }
  successes=$(awk -v p="$pct" -v n="$held" 'BEGIN { printf "%d", p * n / 100 + 0.5 }')
  # The context's sentence: from its name to the next context's.
  segment=${para#*\`$ctx\` }
  segment=${segment%%. \`*}
  [ "$segment" != "$para" ] || { fail "section 3 does not name \`$ctx\`"; continue; }
  has "$segment" "${episodes[$ctx]} episodes (${seconds[$ctx]} simulated seconds"
  has "$segment" "final evaluation succeeds in $successes of $held episodes"
  [ "$ctx" = Skilled ] && has "$segment" "reaches the $threshold threshold"
done

if [ -n "${episodes[Skilled]:-}" ] && [ -n "${episodes[Primitives]:-}" ]; then
  time_ratio=$(awk -v a="${seconds[Primitives]}" -v b="${seconds[Skilled]}" 'BEGIN { printf "%d", a / b + 0.5 }')
  episode_ratio=$(awk -v a="${episodes[Primitives]}" -v b="${episodes[Skilled]}" 'BEGIN { printf "%d", a / b + 0.5 }')
  has "$para" "about $(number_word "$time_ratio") times as long"
  has "$para" "costs $(number_word "$episode_ratio") times the episodes"
fi

# The saved policy on other worlds.
first=$(sed -n 's/.*--seed \([0-9]*\).*/\1/p' <<<"$eval_cmd")
count=$(sed -n 's/.*--episodes \([0-9]*\).*/\1/p' <<<"$eval_cmd")
rate=$(sed -n 's/^ *success rate .*(\([0-9]* of [0-9]*\)).*/\1/p' <<<"$eval_out")
if [ -n "$first" ] && [ -n "$count" ] && [ -n "$rate" ]; then
  has "$para" "on $count other worlds (seeds $first to $((first + count - 1))) the saved policy succeeds in $rate"
else
  fail "the \$roger eval command or its success rate line not found: '$eval_cmd'"
fi

# Section 1: the scenario check builds as many worlds as the text says.
worlds=$(sed -n 's/.*(scenario .blue_ball., \([0-9]*\) seeds generated and built.*/\1/p' <<<"$check_out")
if [ -n "$worlds" ]; then
  has "$(tr '\n' ' ' < "$doc" | tr -s ' ')" "it generates and builds $worlds seeded worlds"
else
  fail "\$roger check mywork/blue_ball.lua does not say how many seeds it built: '$check_out'"
fi

[ $status -eq 0 ] && echo "docs/tutorial-new-context.md: every command runs, every figure of section 3 is what they print"
exit $status
