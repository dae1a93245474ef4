-- curriculum_example.lua: a new developmental context written in Lua and trained without
-- rebuilding the engine (docs/curricula.md, "Tutorial"). Roger learns to find the ball and centre
-- it in both eyes, choosing among turning on the spot (search) and centring (phi0) in context Gaze;
-- context Skilled has the Phi6 skill alone, to compare with.
--
--   roger check docs/examples/curriculum_example.lua
--   roger train docs/examples/curriculum_example.lua --stage Look --context Gaze --seed 3 --out out/look
local skills = require("lib.skills")

local p = skills.primitives()
local Phi6 = skills.Phi6(p)

-- A reward written in Lua, called only when the state changes (decision points), never per tick
-- (but in the Python module's tick mode, where every tick is a decision: docs/python.md):
-- a small cost per decision so that short policies are preferred, +100 at the goal, -100 at the
-- time-out. `state` maps each action's name to "NOREF", "!CONV" or "CONV".
local function reward(state, action, event)
  if event == "absorbing" then return 100 end
  if event == "timeout" then return -100 end
  return -1
end

return {
  name = "look",
  description = "Learn to find the ball and hold it centred in view.",
  stages = {
    roger.stage{
      name = "Look",
      scenario = "unobstructed",
      time_limit = 4,
      absorbing = roger.converged(p.phi0),   -- the ball centred in both eyes
      reward = reward,
      learner = { alpha = 0.2, discount = 0.95, epsilon_start = 1.0, epsilon_end = 0.05, initial_q = -100 },
      budget = { episodes = 60 },
      checkpoints = { every = 10, episodes = 10, threshold = 0.9, stop_after = 2, final = 20 },
      contexts = {
        { name = "Gaze", actions = { p.search, p.phi0 } },
        { name = "Skilled", actions = { Phi6 } },
      },
      skill = { name = "Phi_Look", context = "Gaze" },
    },
  },
}
