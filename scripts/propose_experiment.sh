#!/bin/sh
# propose_experiment.sh: the experiment of docs/propose.md. From stage T of the paper's curriculum
# with only the primitives and hand-written compositions of context B2, roger propose proposes a
# curriculum; then the proposal (context P) and the paper's B2, DC3 and DC6 are trained for N
# seeded trials each (seeds 1..N, as scripts/paper.lua's trials), and the table compares their
# time-to-threshold: the final stage alone (the paper's measure), with the learned skills' own
# training added (SG/DC2 for DC3 and DC6, the proposal's subgoal stages for P), and for P with the
# search's simulated seconds added as well. Re-running resumes: the search from its records, the
# trials from their summaries.
#
#   scripts/propose_experiment.sh [OUT] [TRIALS] [BUDGET]    (defaults: results/propose 50 60000)
#   ROGER=build/engine/roger JOBS=2 SEED=1 scripts/propose_experiment.sh   (SEED: the search's)
set -eu
OUT=${1:-results/propose}
TRIALS=${2:-50}
BUDGET=${3:-60000}
ROGER=${ROGER:-build/engine/roger}
JOBS=${JOBS:-2}
SEED=${SEED:-1}

"$ROGER" propose paper --stage T --context B2 --budget "$BUDGET" --probe-share 0.3 --seed "$SEED" --out "$OUT/search"

mkdir -p "$OUT/trials"
# One line per trial to run: curriculum, context, seed; trials with a summary are kept.
for ctx in P B2 DC3 DC6; do
  cur=paper
  [ "$ctx" = P ] && cur="$OUT/search/proposal.lua"
  seed=1
  while [ "$seed" -le "$TRIALS" ]; do
    [ -s "$OUT/trials/$ctx-$seed.json" ] || echo "$cur $ctx $seed"
    seed=$((seed + 1))
  done
done | xargs -P "$JOBS" -L 1 sh -c '
  "$0" train "$1" --stage T --context "$2" --seed "$3" --out "'"$OUT"'/runs/$2-$3" --json | tail -n 1 \
    > "'"$OUT"'/trials/$2-$3.json.tmp" && mv "'"$OUT"'/trials/$2-$3.json.tmp" "'"$OUT"'/trials/$2-$3.json"
' "$ROGER"

python3 - "$OUT" "$TRIALS" <<'PY'
import json, statistics, sys
out, trials = sys.argv[1], int(sys.argv[2])
report = open(f"{out}/search/propose.md").read()
spent = float(report.split("; spent ")[1].split(" ")[0])
def mmss(s):
    if s is None:
        return "-"
    t = int(s + 0.5)  # whole seconds first, as the engine's tables round (59.7 s is 1:00, not 0:60)
    return f"{t // 60}:{t % 60:02d}"
rows = []
for ctx in ["B2", "DC3", "DC6", "P"]:
    alone, developed, reached = [], [], 0
    for seed in range(1, trials + 1):
        j = json.load(open(f"{out}/trials/{ctx}-{seed}.json"))
        t = j["time_to_threshold_s"] if j["reached"] else j["train_sim_s"]
        skills = sum(k["totals"]["sim_s"] for k in j.get("skills", {}).values() if k.get("trained"))
        reached += bool(j["reached"])
        alone.append(t)
        developed.append(t + skills)
    with_search = statistics.median(developed) + spent if ctx == "P" else None
    rows.append((ctx, reached, statistics.median(alone), statistics.mean(alone), statistics.median(developed), with_search))
print(f"| context | reached | median, final stage | mean, final stage | median, + learned skills' training | + the search ({spent:.0f} s) |")
print("|---|---|---|---|---|---|")
for ctx, r, med, mean, dev, ws in rows:
    print(f"| {ctx} | {r}/{trials} | {mmss(med)} | {mmss(mean)} | {mmss(dev)} | {mmss(ws)} |")
PY
