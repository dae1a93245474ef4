-- lib/propose.lua: what the curricula written by `roger propose` are built with (docs/propose.md).
-- A proposal restates nothing of the task: it requires the original curriculum, takes the task
-- stage and its actions by name, and builds new stages of the same kind around them.
--
--   local propose = require("lib.propose")
--   local task = propose.task("paper", "SG")       -- stage SG of curricula/paper.lua
--   local A = propose.actions(task, "B1")          -- its context B1's actions, by name
--   local sub = propose.stage(task, { name = "SG_to_phi1", goal = A["phi1"],
--                 contexts = { { name = "P", actions = { A["Phi6"], A["phi1"] } } },
--                 skill = { name = "Phi_to_phi1", context = "P" } })
local M = {}

-- What propose.task learned of each task it returned: the module and whether its scenario came
-- resolved (for the error of a scenario path that leads elsewhere from this file).
local origin = {}

-- A scenario named by a relative path ("clutter_pick.lua", "worlds/mine.lua"), which roger.stage
-- looks for beside the file that calls it, rather than a shipped scenario's bare name.
local function relative_path(s)
  return type(s) == "string" and (s:find("/", 1, true) ~= nil or s:sub(-4) == ".lua") and s:sub(1, 1) ~= "/"
end

-- The stage named `name` of the curriculum module `module` (required, so built once). `resolved`
-- (optional) is {scenario = PATH}: the stage's scenario as the curriculum resolved it, a path from
-- the project (or absolute). A stage that names its scenario relative to its own file
-- (`scenario = "clutter_pick.lua"`, beside the curriculum) needs it: propose.stage calls
-- roger.stage from this file, which would look for that path beside curricula/lib/ instead.
-- roger propose writes it so. The task returned is a copy of the stage with the scenario replaced.
function M.task(module, name, resolved)
  -- Found by a probe: a missing argument was "attempt to concatenate a nil value" in this file.
  if type(module) ~= "string" or type(name) ~= "string" then
    error("lib.propose: propose.task takes the curriculum module's name and the stage's name, two strings " ..
          "(propose.task(\"paper\", \"SG\")), got " .. type(module) .. " and " .. type(name), 2)
  end
  -- Found by a probe: a module require could not find was said at this file's line, not the
  -- caller's, and a proposal made in a project of one's own (ROGER_HOME) did not say where to look.
  local found, cur = pcall(require, module)
  if not found then
    local why = tostring(cur)
    local missing = why:match("^(module .- not found.-);? ?searched:")
    error("lib.propose: propose.task could not require the curriculum '" .. module .. "': " ..
          (missing and missing .. " (a proposal written in a project of one's own is checked and run with that " ..
                       "project's ROGER_HOME, as its first lines say)" or why), 2)
  end
  if type(cur) ~= "table" or type(cur.stages) ~= "table" then
    error("lib.propose: the module '" .. module .. "' is not a curriculum (no stages)", 2)
  end
  if resolved ~= nil and type(resolved) ~= "table" then
    error("lib.propose: propose.task's third argument must be a table {scenario = PATH}, got " .. type(resolved), 2)
  end
  for key in pairs(resolved or {}) do
    if key ~= "scenario" then
      error("lib.propose: propose.task's third argument has an unknown field '" .. tostring(key) ..
            "'; it takes only 'scenario' (the stage's scenario as its curriculum resolved it)", 2)
    end
  end
  local names = {}
  for _, st in ipairs(cur.stages) do
    if st.name == name then
      local task = {}
      for k, v in pairs(st) do task[k] = v end
      if resolved and resolved.scenario ~= nil then task.scenario = resolved.scenario end
      origin[task] = { module = module, resolved = resolved ~= nil and resolved.scenario ~= nil }
      return task
    end
    names[#names + 1] = st.name
  end
  error("lib.propose: curriculum '" .. module .. "' has no stage '" .. name .. "'; stages: " ..
        table.concat(names, ", "), 2)
end

-- The task's context named `context` (an error lists the contexts).
local function context_of(task, context)
  if type(task) ~= "table" or type(task.contexts) ~= "table" then
    error("lib.propose: the first argument must be a task from propose.task, got " .. type(task), 3)
  end
  if type(context) ~= "string" then
    error("lib.propose: the second argument must be the name of one of the task's contexts, a string, got " ..
          type(context), 3)
  end
  local names = {}
  for key, ctx in pairs(task.contexts) do
    local cname = ctx.name or key
    if cname == context then return ctx end
    names[#names + 1] = tostring(cname)
  end
  table.sort(names)
  error("lib.propose: stage '" .. task.name .. "' has no context '" .. context .. "'; contexts: " ..
        table.concat(names, ", "), 3)
end

-- The actions of the task's context `context`, as a table name -> controller. A name it does not
-- hold is an error at the line that reads it, listing the names it holds (found by a probe:
-- A["Phi 6"] was nil, dropped from the end of an action list without a word).
function M.actions(task, context)
  local ctx = context_of(task, context)
  local A, names = {}, {}
  for _, a in ipairs(ctx.actions or ctx) do
    A[a.name] = a
    names[#names + 1] = a.name
  end
  table.sort(names)
  return setmetatable(A, { __index = function(_, name)
    error("lib.propose: context '" .. tostring(context) .. "' of stage '" .. tostring(task.name) ..
          "' has no action '" .. tostring(name) .. "'; its actions: " .. table.concat(names, ", "), 2)
  end })
end

-- The scenario parameters of the task's context `context` (a restricted body or senses), nil when
-- it sets none: the proposal's contexts keep them, so that they train the body the probe trained.
function M.params(task, context)
  local ctx = context_of(task, context)
  return ctx.actions and ctx.params or nil
end

-- A stage of the task's kind: its scenario, parameters, time limit, learner, budget, checkpoints
-- and teaching (task space, teacher, test set). With `goal` (a controller) it is a subgoal stage:
-- absorbing when the goal is CONV, with the task's fixed rewards (or +100/-100/0 when the task's
-- reward is a Lua function, which was written for the task's own actions); without, it is the task
-- itself with new contexts.
local stage_fields = { name = true, description = true, goal = true, contexts = true, skill = true }

function M.stage(task, fields)
  if type(fields) ~= "table" then
    error("lib.propose: propose.stage's second argument must be a table of fields, got " .. type(fields), 2)
  end
  -- Found by a probe: a misspelt field (gaol, skils) was dropped, and the stage became the task.
  for key in pairs(fields) do
    if not stage_fields[key] then
      error("lib.propose: propose.stage has no field '" .. tostring(key) .. "'; it takes name, contexts, goal, " ..
            "skill and description (the rest comes from the task)", 2)
    end
  end
  local reward = task.reward
  if fields.goal and type(reward) ~= "table" then reward = { absorbing = 100, timeout = -100, step = 0 } end
  -- Called from a function of this file, so that roger.stage places its errors and the stage here.
  local ok, result = pcall(function() return roger.stage{
    name = fields.name,
    description = fields.description or task.description,
    scenario = task.scenario,
    params = task.params,
    time_limit = task.time_limit,
    absorbing = fields.goal and roger.converged(fields.goal) or task.absorbing,
    reward = reward,
    learner = task.learner,
    budget = task.budget,
    checkpoints = task.checkpoints,
    tasks = task.tasks,
    teacher = task.teacher,
    test = task.test,
    contexts = fields.contexts,
    skill = fields.skill,
  } end)
  if ok then return result end
  local from = origin[task]
  local scenario_failed = tostring(result):find("field 'scenario'", 1, true)
  if from and not from.resolved and relative_path(task.scenario) and scenario_failed then
    error("lib.propose: stage '" .. tostring(task.name) .. "' of '" .. from.module .. "' names its scenario '" ..
          task.scenario .. "' by a path relative to the file that writes the stage, and propose.stage writes it " ..
          "again from curricula/lib/propose.lua, where that path leads elsewhere: give the scenario as the " ..
          "curriculum resolved it, propose.task(\"" .. from.module .. "\", \"" .. tostring(task.name) ..
          "\", { scenario = PATH }) with PATH from the project (roger propose writes it so). " .. tostring(result), 2)
  end
  -- roger.stage placed its error at a line of this file, where the stage is written again: the
  -- caller's line says whose stage it is (found by a probe: a missing name read propose.lua:95).
  local message = tostring(result)
  local here = message:match("^[^:]*lib/propose%.lua:%d+: (.*)$")
  error(here or message, here and 2 or 0)
end

return M
