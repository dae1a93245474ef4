---@meta
-- docs/api/curriculum.lua: what a curriculum reaches beyond the control basis (docs/curricula.md):
-- roger.stage, roger.learned, and the arguments of its Lua callbacks.
-- tests/test_lua_sandbox.cpp keeps it equal to what the sandbox registers.

---Validates a stage where it is written (errors point at this line) and returns the table. The
---curriculum reads the table again when the script returns, so changes made to it later count
---(a wrapper that shortens a required curriculum's budgets) and are checked, their errors
---pointing at this line too.
---@param stage roger.Stage
---@return roger.Stage
function roger.stage(stage) end

---The stand-in controller for the skill an earlier stage yields (its `skill` field).
---@param name string
---@return roger.Controller
function roger.learned(name) end

---A task-space axis: the integers lo..hi of a scenario parameter (docs/curricula.md, Teachers).
---@param lo integer
---@param hi integer above lo (a single value is a fixed parameter: write it in params)
---@return roger.TaskAxis
function roger.int(lo, hi) end

---A task-space axis: the numbers in [lo, hi] of a scenario parameter.
---@param lo number
---@param hi number above lo
---@return roger.TaskAxis
function roger.real(lo, hi) end

---A task-space axis: these values of a scenario parameter (numbers, strings or booleans).
---@param values (number|string|boolean)[] two or more, distinct
---@return roger.TaskAxis
function roger.choice(values) end

---A value of a task space's axis (`tasks = { obstacles = roger.int(0, 6) }`).
---@class roger.TaskAxis

---A stage's teacher (`teacher = roger.teacher.alp_gmm{}`): it picks each training episode's task.
---@class roger.Teacher

---The teachers (docs/curricula.md, Teachers). Each draws from its own stream of the trial's seed.
roger.teacher = {}

---Domain randomization: every task of the space alike (the default when a stage gives `tasks`).
---@param options? {}
---@return roger.Teacher
function roger.teacher.random(options) end

---Fixed steps, each a part of the space (`{obstacles = 0}`, `{obstacles = roger.int(0, 3)}`, `{}` the
---whole); the next begins when the success rate over the step's last `window` episodes reaches
---`promote` (default 0.9, window 20), the previous comes back below `demote` (default: never).
---@param steps table[] {param = value|roger.TaskAxis, ..., promote?: number, demote?: number, window?: integer}
---@return roger.Teacher
function roger.teacher.sequence(steps) end

---Lift-Constraint-Act-Saturate: `lift = {eye_pixels = {32, 64, 128}}` holds one parameter at a level
---until the success rate of the last `window` episodes (default 50) beats the window before by less
---than `slope` (default 0.05) and is at least `floor` (default 0: a curve flat at zero counts as
---saturated), then lifts it to the next level.
---@param options {lift: table<string, (number|string|boolean)[]>, window?: integer, slope?: number, floor?: number}
---@return roger.Teacher
function roger.teacher.lcas(options) end

---ALP-GMM (Portelas et al. 2019): Gaussian mixtures of 2..k_max (6) components fitted every `fit_every`
---(50) episodes to the last `history` (250) pairs of task and absolute learning progress; tasks from a
---component in proportion to its progress, `random_share` (0.2) of them uniform.
---@param options? {fit_every?: integer, k_max?: integer, random_share?: number, history?: integer}
---@return roger.Teacher
function roger.teacher.alp_gmm(options) end

---Prioritized Level Replay (Jiang et al. 2021) over levels (task, world seed): replays a seen level with
---probability `replay` (0.5), rank-based priorities at `temperature` (0.1) mixed with `staleness` (0.1);
---`score` "td" (the episode's mean |TD error|, default) or "success" (1 - success); `buffer` (500) levels.
---@param options? {replay?: number, temperature?: number, staleness?: number, score?: "td"|"success", buffer?: integer}
---@return roger.Teacher
function roger.teacher.plr(options) end

---An earlier training episode as a teacher function's `history` shows it.
---@class roger.TeacherEpisode
---@field task table<string, number|string|boolean> the parameters the episode's task gave
---@field success boolean
---@field reward number
---@field time number simulated seconds it lasted

---A stage's test set: `tasks` drawn from the space with Rng(`seed`), or the tasks of `list`.
---@class roger.TestSet
---@field tasks? integer default 200
---@field seed? integer default: checkpoints.seeds
---@field list? table<string, number|string|boolean>[] every axis of the space in each

---A stage's state as a callback sees it: each action's name to its gamma.
---@alias roger.State table<string, roger.GammaName>

---Why a reward function is called.
---@alias roger.Event "decision"|"absorbing"|"timeout"

---An object as a callback's `world` shows it (the task's judge, not Roger's senses).
---@class roger.WorldObject
---@field name string
---@field shape string its shape's name
---@field colour string "#rrggbb"
---@field x number centre (m)
---@field y number
---@field held boolean Roger's body or a hand touches it
---@field region? string the goal region its centre lies in, nil when none

---A goal region as a callback's `world` shows it.
---@class roger.WorldGoal
---@field name string
---@field x number centre (m)
---@field y number
---@field radius number

---A static obstacle as a callback's `world` shows it.
---@class roger.WorldObstacle
---@field name string
---@field x number centre (m)
---@field y number
---@field shape string its shape's name

---The last argument of a curriculum's absorbing and reward functions.
---@class roger.CallbackWorld
---@field objects roger.WorldObject[] every object, in the scenario's order
---@field goals roger.WorldGoal[] the goal regions
---@field obstacles roger.WorldObstacle[] the static obstacles, in the scenario's order

---A developmental context: a name, its action set Psi, and optionally scenario parameters over
---the stage's (a context that restricts the body or the senses: docs/curricula.md).
---@class roger.Context
---@field name string
---@field actions roger.ControllerRef[] 1 to 12 actions with distinct names
---@field params? table<string, number|string|boolean> scenario parameters over the stage's
---@field init? roger.ContextInit the context whose Q-table this one starts from (default: none, every value initial_q)

---A context's warm start (docs/curricula.md, Warm starts): that context is trained first with the
---trial's seed, and this one starts from its Q-table.
---@class roger.ContextInit
---@field stage? string a stage written before, or this one (default: this one)
---@field context string a context of that stage written before this one

---A stage's reward: the defaults are absorbing 100, timeout -100, step 0.
---@class roger.Reward
---@field absorbing? number
---@field timeout? number
---@field step? number paid per tick

---Q-learning's settings.
---@class roger.Learner
---@field alpha? number default 0.1
---@field discount? number default 0.95
---@field epsilon_start? number default 1
---@field epsilon_end? number default 0.05
---@field initial_q? number default 0
---@field referenced_only? boolean never choose an action whose gamma is NOREF (default false)
---@field unconverged_first? boolean while some action is !CONV, choose only among those (default false)
---@field discount_seconds? number 0: discount once per decision (default, the paper); s > 0: discount^(elapsed / s)

---Greedy checkpoints and the final evaluation.
---@class roger.Checkpoints
---@field every? integer training episodes between checkpoints (default budget / 20, at least 1)
---@field episodes? integer episodes per checkpoint (default 20; not with a `test` set)
---@field threshold? number success rate to reach, in (0, 1] (default 0.9)
---@field seeds? integer first held-out seed (default 1000000)
---@field stop_after? integer stop after this many passing checkpoints (0: never)
---@field settle? boolean a changed policy starts the count again (default true)
---@field final? integer episodes of the final evaluation (default 50; not with a `test` set)

-- roger.TimePerObject (time_limit = {per_object = 3}) is described in control.lua, which a
-- curriculum's editor reads beside this file.

---A stage: a learning problem per developmental context (docs/curricula.md).
---@class roger.Stage
---@field name string unique
---@field description? string
---@field scenario? string scenario name or path (default "unobstructed")
---@field params? table<string, any> scenario parameters
---@field time_limit number|roger.TimePerObject simulated seconds per episode (> 0, at most 3600), or per object of its world
---@field absorbing roger.Predicate|fun(state: roger.State, time: number, world: roger.CallbackWorld, episode: table): boolean
---@field reward? roger.Reward|fun(state: roger.State, action: string, event: roger.Event, time: number, world: roger.CallbackWorld, episode: table): number
---@field learner? roger.Learner
---@field budget {episodes: integer}
---@field checkpoints? roger.Checkpoints
---@field contexts roger.Context[]|table<string, roger.ControllerRef[]|{actions: roger.ControllerRef[], params: table<string, number|string|boolean>?, init: roger.ContextInit?}>
---@field skill? {name: string, context: string} the context whose greedy policy becomes a skill (the stage's absorbing must then be a predicate, not a Lua function: a skill's gamma is evaluated every tick)
---@field tasks? table<string, roger.TaskAxis> scenario parameters each training episode draws (docs/curricula.md, Teachers)
---@field teacher? roger.Teacher|fun(history: roger.TeacherEpisode[], rng: roger.Rng): table<string, number|string|boolean> who draws them (default roger.teacher.random{})
---@field test? roger.TestSet the tasks the checkpoints and the final evaluation run

---What a curriculum returns.
---@class roger.Curriculum
---@field name? string default: the file name
---@field description? string
---@field stages roger.Stage[] in curriculum order
