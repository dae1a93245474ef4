-- teach_curriculum.lua: one stage per teacher over the world of teach_reach.lua, whose task space
-- (level in [0, 1]) has a trivial part, a learnable band [0.4, 0.6] and an unlearnable part, for
-- the teachers' tests (tests/test_teach.cpp). Psi: phi1 (approach the ball) and phi4 (condition the
-- arms: converges in 1.8 s and then leaves the state as it is, so chosen again it runs until the
-- time-out). Each stage is built by reach{...} with its own teacher.
local skills = require("lib.skills")
local p = skills.primitives()

local function reach(name, teacher, extra)
  local stage = {
    name = name, scenario = "tests/scripts/teach_reach.lua", time_limit = 3,
    absorbing = roger.converged(p.phi1),
    learner = { alpha = 0.2, discount = 0.95, epsilon_start = 1, epsilon_end = 0.05 },
    budget = { episodes = 300 },
    checkpoints = { every = 50, threshold = 0.9 },
    contexts = { { name = "A", actions = { p.phi1, p.phi4 } } },
    tasks = { level = roger.real(0, 1) },
    teacher = teacher,
    test = { tasks = 20, seed = 7 },
  }
  for k, v in pairs(extra or {}) do
    if v == false then stage[k] = nil else stage[k] = v end
  end
  return roger.stage(stage)
end

return {
  name = "teach",
  stages = {
    reach("Random", roger.teacher.random{}),
    reach("Alp", roger.teacher.alp_gmm{ fit_every = 25 }),
    reach("Plr", roger.teacher.plr{ replay = 0.5 }),
    reach("PlrFail", roger.teacher.plr{ score = "success" }),
    reach("Sequence", roger.teacher.sequence{
      { level = 0.1, promote = 0.9, window = 10 },
      { level = roger.real(0.4, 0.6), promote = 0.8, demote = 0.2, window = 20 },
      {},
    }),
    reach("Lcas", roger.teacher.lcas{ lift = { level = { 0.1, 0.5, 0.9 } }, window = 20, slope = 0.05 }),
    -- The band while the last 10 episodes succeeded at most 8 times, then anywhere.
    reach("Function", function(history, rng)
      local n, wins = #history, 0
      for i = math.max(1, n - 9), n do
        if history[i].success then wins = wins + 1 end
      end
      if n < 10 or wins <= 8 then return { level = 0.4 + 0.2 * rng:uniform() } end
      return {}
    end),
    -- No task space: LCAS lifts a parameter of the scenario alone.
    reach("LiftOnly", roger.teacher.lcas{ lift = { distance = { 0, 1, 2 } }, window = 20 },
          { tasks = false, test = { tasks = 10 } }),
  },
}
