---@meta
-- api/curriculum.lua: what a curriculum reaches beyond the control basis (docs/curricula.md):
-- roger.stage, roger.learned, and the arguments of its Lua callbacks.
-- tests/test_lua_sandbox.cpp keeps it equal to what the sandbox registers.

---Validates a stage where it is written (errors point at this line) and returns the table.
---@param stage roger.Stage
---@return roger.Stage
function roger.stage(stage) end

---The stand-in controller for the skill an earlier stage yields (its `skill` field).
---@param name string
---@return roger.Controller
function roger.learned(name) end

---A stage's state as a callback sees it: each action's name to its gamma.
---@alias roger.State table<string, roger.GammaName>

---Why a reward function is called.
---@alias roger.Event "decision"|"absorbing"|"timeout"

---An object as a callback's `world` shows it (the task's judge, not Roger's senses).
---@class roger.WorldObject
---@field name string
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

---The last argument of a curriculum's absorbing and reward functions.
---@class roger.CallbackWorld
---@field objects roger.WorldObject[] every object, in the scenario's order
---@field goals roger.WorldGoal[] the goal regions

---A developmental context: a name, its action set Psi, and optionally scenario parameters over
---the stage's (a context that restricts the body or the senses: docs/curricula.md).
---@class roger.Context
---@field name string
---@field actions roger.ControllerRef[] 1 to 12 actions with distinct names
---@field params? table<string, number|string|boolean> scenario parameters over the stage's

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
---@field every? integer training episodes between checkpoints (default budget / 20)
---@field episodes? integer episodes per checkpoint (default 20)
---@field threshold? number success rate to reach (default 0.9)
---@field seeds? integer first held-out seed (default 1000000)
---@field stop_after? integer stop after this many passing checkpoints (0: never)
---@field settle? boolean a changed policy starts the count again (default true)
---@field final? integer episodes of the final evaluation (default 50)

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
---@field contexts roger.Context[]|table<string, roger.ControllerRef[]|{actions: roger.ControllerRef[], params: table<string, number|string|boolean>?}>
---@field skill? {name: string, context: string} the context whose greedy policy becomes a skill

---What a curriculum returns.
---@class roger.Curriculum
---@field name? string default: the file name
---@field description? string
---@field stages roger.Stage[] in curriculum order
