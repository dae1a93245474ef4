-- Fixture of test_propose: a curriculum of the user's own whose stage names its scenario by a path
-- relative to this file (propose_beside_world.lua, beside it, as docs/curricula.md recommends).
-- The test copies both into curricula/mine/ of a project tree of its own (ROGER_HOME), since a
-- proposal requires the curriculum it starts from, and proposes from context Eyes64, whose
-- scenario parameters (coarser eyes) every context of the proposal must keep.
local skills = require("lib.skills")
local p = skills.primitives()
local Phi6 = skills.Phi6(p)
local preshape = p.phi4:subject_to(p.phi2)

return {
  name = "propose_beside",
  stages = {
    roger.stage{
      name = "Grasp",
      scenario = "propose_beside_world.lua",
      time_limit = 5,
      absorbing = roger.converged(p.phi3),
      learner = { alpha = 0.1, discount = 0.95, epsilon_start = 1.0, epsilon_end = 0.05 },
      budget = { episodes = 400 },
      checkpoints = { every = 10, episodes = 20, threshold = 0.9 },
      contexts = {
        { name = "Eyes64", actions = { p.phi1, p.phi3, preshape, Phi6 }, params = { eye_pixels = 64 } },
        { name = "B1", actions = { p.phi1, p.phi3, preshape, Phi6 } },
      },
    },
  },
}
