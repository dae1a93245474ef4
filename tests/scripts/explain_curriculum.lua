-- Fixture of the [explain] tests (tests/test_trainer.cpp): stages built to fail in the ways a
-- training explains (engine/batch/explain.h), on two goal regions and navigators (phi1) to them.
--   livelock: each arrival pays +10 and nothing absorbs, so going back and forth between the two
--     regions beats anything else: the greedy policy alternates go0 and go1 until every episode
--     times out (a greedy cycle). A third navigator heads for a region the world does not have
--     (NOREF throughout).
--   unused: the absorbing state needs that navigator to converge, and a learner that chooses only
--     actions with a reference never runs it: go0 arrives, and the state is never left.
--   reach: go0 alone, absorbed on arrival: reaches its threshold (explained only when asked).
local go0 = roger.primitive("phi1", { goal = "region", region = 0, name = "go0" })
local go1 = roger.primitive("phi1", { goal = "region", region = 1, name = "go1" })
local nowhere = roger.primitive("phi1", { goal = "region", region = 9, name = "nowhere" })

local function never() return false end

local function per_arrival(state, action, event)
  if event == "decision" then return 10 end
  if event == "timeout" then return -100 end
  return 0
end

local function stage(fields)
  fields.scenario = "tests/scripts/explain_scenario.lua"
  fields.contexts = { { name = "A", actions = fields.actions } }
  fields.actions = nil
  return roger.stage(fields)
end

return {
  name = "explain",
  stages = {
    stage{ name = "livelock", actions = { go0, go1, nowhere }, absorbing = never, reward = per_arrival,
           time_limit = 12, budget = { episodes = 30 },
           checkpoints = { every = 10, episodes = 2, final = 4 } },
    stage{ name = "unused", actions = { go0, nowhere }, absorbing = roger.converged(nowhere),
           learner = { referenced_only = true }, time_limit = 6, budget = { episodes = 6 },
           checkpoints = { every = 3, episodes = 2, final = 2 } },
    stage{ name = "reach", actions = { go0 }, absorbing = roger.converged(go0), time_limit = 6,
           budget = { episodes = 2 }, checkpoints = { every = 2, episodes = 2, final = 2 } },
  },
}
