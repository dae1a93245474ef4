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

-- The stage named `name` of the curriculum module `module` (required, so built once).
function M.task(module, name)
  local cur = require(module)
  if type(cur) ~= "table" or type(cur.stages) ~= "table" then
    error("lib.propose: the module '" .. module .. "' is not a curriculum (no stages)", 2)
  end
  local names = {}
  for _, st in ipairs(cur.stages) do
    if st.name == name then return st end
    names[#names + 1] = st.name
  end
  error("lib.propose: curriculum '" .. module .. "' has no stage '" .. name .. "'; stages: " ..
        table.concat(names, ", "), 2)
end

-- The actions of the task's context `context`, as a table name -> controller.
function M.actions(task, context)
  local names = {}
  for key, ctx in pairs(task.contexts) do
    local cname = ctx.name or key
    if cname == context then
      local A = {}
      for _, a in ipairs(ctx.actions) do A[a.name] = a end
      return A
    end
    names[#names + 1] = tostring(cname)
  end
  table.sort(names)
  error("lib.propose: stage '" .. task.name .. "' has no context '" .. context .. "'; contexts: " ..
        table.concat(names, ", "), 2)
end

-- A stage of the task's kind: its scenario, parameters, time limit, learner, budget and
-- checkpoints. With `goal` (a controller) it is a subgoal stage: absorbing when the goal is CONV,
-- with the task's fixed rewards (or +100/-100/0 when the task's reward is a Lua function, which
-- was written for the task's own actions); without, it is the task itself with new contexts.
function M.stage(task, fields)
  local reward = task.reward
  if fields.goal and type(reward) ~= "table" then reward = { absorbing = 100, timeout = -100, step = 0 } end
  return roger.stage{
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
    contexts = fields.contexts,
    skill = fields.skill,
  }
end

return M
