---@meta
-- docs/api/batch.lua: what a batch script returns (docs/batch.md). A batch script reaches no roger.*
-- function: it runs in the plain sandbox and returns a table, described here for editors. Every
-- field the engine reads is here (engine/script/batch/batch_script.cpp); any other field is an
-- error naming its line and the known fields.

---Where a learned skill comes from: trial i uses the final policy of trial i of `run`/`context`.
---@class roger.BatchSkillSource
---@field run string an earlier run, of the stage that yields the skill
---@field context? string default: the context the yielding stage names in its `skill` field

---A training run: one stage's contexts, `trials` seeded trials each.
---@class roger.BatchRun
---@field name string unique: letters, digits, `.`, `_`, `-`, at most 200 (not "eval"); the first segment of its trial ids (`T/DC3/007`)
---@field stage string a stage of the curriculum
---@field contexts? string[] some of its contexts, in the tables' order (default: all of them; not empty)
---@field trials? integer overrides the script's `trials` (1 to 100000; default: the script's)
---@field params? table<string, number|string|boolean> scenario parameters over the script's (default: none)
---@field skills? table<string, roger.BatchSkillSource> for every learned skill its contexts use, the run and context that train it (required for each such skill)
---@field final_worlds? "own"|"shared" default "shared": every trial's final evaluation on the stage's held-out seeds; "own": trial i's from the held-out seeds + i * its final episodes

---Greedy runs of the final policies of a run's trials elsewhere, without retraining.
---@class roger.BatchEvaluation
---@field name string unique: letters, digits, `.`, `_`, `-`, at most 200; trial ids are eval/<name>/<shape>/<trial>
---@field run string the run whose trials' final policies are evaluated
---@field context? string a context of that run (default: the run's last context)
---@field scenario? string a scenario name or path, looked for beside the batch script first (default: the stage's)
---@field params? table<string, number|string|boolean> scenario parameters (default: none)
---@field shapes? string[] one group per shape (shape=<name>; not with a `shape` in `params`); default: one group called "all"
---@field episodes? integer episodes per shape and policy (1 to 1000000; default 50)
---@field first_seed? integer first world seed (default -1: the stage's held-out seeds); its last world's seed at most 2^53
---@field worlds? "own"|"shared" default "own": shape k's trial i from first_seed + (k * trials + i) * episodes; "shared": every policy on shape k's worlds from first_seed + k * episodes (common random numbers)
---@field trials? integer the first `trials` trials of the run (1 to the run's trials; default: all)
---@field skills? table<string, roger.BatchSkillSource> learned skills of the context from these runs instead of the ones the policies embed (trial i's; default: the embedded ones)

---A row of a table's `usage`: the share of `skill` among itself and the actions it subsumes.
---@class roger.BatchUsage
---@field context string a context of the table's run
---@field skill string an action of that context
---@field subsumes string[] actions of that context (not empty)

---A row of a sorting table: the runs of one number of objects (the first context of each).
---@class roger.BatchSortingRow
---@field objects integer the number of objects (1 to 1000)
---@field learned? string the learned run (default: none; give `learned`, `hand` or both)
---@field hand? string the hand-written run (default: none)

---A table of the report: give one of `run`, `evaluation`, `sorting` or `compare`.
---@class roger.BatchTable
---@field title? string its heading (default: one made from what it shows: "Stage T (run T)", "Evaluation generalization", "Comparison of T_seq/DC3, T_lcas/DC3", "Stage T (run T): final success by shape")
---@field run? string a run's table: a row per context
---@field baseline? string what the others are compared with: a context of `run`, or a "run/context" row of `compare` (default: the first)
---@field evaluation? string an evaluation's table: a row per shape and a Total (no `baseline`, `usage` or `by`)
---@field usage? roger.BatchUsage[] with `run`: the usage of each skill below the table (default: none)
---@field sorting? roger.BatchSortingRow[] a sorting table, one row per number of objects (no `run`, `evaluation`, `baseline`, `usage` or `by`)
---@field compare? string[] a comparison across runs: a row per "run/context" (no `run`, `evaluation` or `usage`)
---@field by? string with `run` or `compare`: the final evaluations' success rate split by this feature (obstacles, objects, shape, or a task parameter of the runs' stages) instead (default: none)

---A figure of the report, written as <file>.png and <file>.svg.
---@class roger.BatchFigure
---@field file string a plain name (no folder, no extension), unique, not iqm_<run>
---@field title? string default: one made from what it draws ("Cumulative training time", ...)
---@field kind? "curves"|"cumulative"|"tasks" default "curves": learning curves; "cumulative": time-to-threshold stacked over the skills' source trials (a run with skills); "tasks": where the run's teacher sampled `param`
---@field run? string the run it draws (required unless `compare` is given)
---@field compare? string[] instead of `run`, for kind "curves": one curve per "run/context" row
---@field y? "reward"|"success" default "reward": the curves' greedy checkpoint reward; "success": their success rate in % (with a test set, the share of its tasks mastered)
---@field log_x? boolean a log-spaced time axis (default false)
---@field context? string for kind "tasks" only: a context of `run` (default: the run's first)
---@field param? string for kind "tasks" only, required there: a parameter the run's teacher chooses, or the one LCAS lifts

---The sandbox's budgets for the curriculum, its scenarios and every trial (docs/batch.md).
---@class roger.BatchLimits
---@field instructions? integer Lua instructions per call from the engine (1000 to 2^53; default 50000000)
---@field memory? integer MiB for each Lua state (16 to 2^20; default 256)

---What a batch script returns (roger run SCRIPT.lua).
---@class roger.BatchScript
---@field name? string the default results folder results/<name> (a folder's name; default: the file name)
---@field description? string one line for the report (default: none)
---@field curriculum string a curriculum path (from the current folder, the script's folder or the project folder) or a bare name in curricula/
---@field trials? integer trials per context of every run (1 to 100000; default 1; --trials overrides it)
---@field seed? integer trial i (0, 1, ...) trains with seed `seed + i` (every such seed 0 to 2^53; default 1)
---@field params? table<string, number|string|boolean> scenario parameters of every training run (default: none; --set over them)
---@field limits? roger.BatchLimits the sandbox's budgets for the curriculum, its scenarios and every trial, not this script (--lua-instructions and --lua-memory override them)
---@field runs roger.BatchRun[] the training runs, in order (at least one)
---@field evaluations? roger.BatchEvaluation[] default: none
---@field tables? roger.BatchTable[] default: one per run (its first context the baseline) and one per evaluation
---@field figures? roger.BatchFigure[] default: curves_<run> of every run and cumulative_<run> of every run with skills
