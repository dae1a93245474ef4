-- scripted.lua: the whole task written by hand, no learning: search for the object, track it,
-- approach it while preshaping, grasp it, and transport it to the goal region. It is the
-- reference point for the learned policies (the control knowledge a curriculum has to find) and a
-- smoke test of the primitives:
--
--   roger check curricula/scripted.lua
--   roger eval curricula/scripted.lua --policy task
--
-- Each step of a sequence runs until it converges; a step that loses its reference hands control
-- back to the one before it (tracking lost the ball: search again).
local skills = require("lib.skills")

local p = skills.primitives()
local Phi6 = skills.Phi6(p)            -- search, then track with phi0
local Phi7 = skills.Phi7(p)            -- phi1, then phi4 <| phi2
local transport = skills.transport(p)  -- phi1{goal = "region"} <| phi4 <| phi5

-- Search-grasp: find the object, approach and preshape, then close the grasp (phi3).
local Phi_SG = roger.sequence("Phi_SG", { Phi6, Phi7, p.phi3 })

-- The task: search-grasp, then carry the object to the goal while holding it.
local Phi_T = roger.sequence("Phi_T", { Phi_SG, transport })

return {
  name = "scripted",
  description = "The hand-written task: search, track, approach and preshape, grasp, transport.",
  policies = {
    task = {
      action = Phi_T,
      -- The paper's absorbing state of Phi_T: phi1, phi4 and phi5 all CONV (the object in the
      -- goal region, the grasp held).
      goal = skills.transported(transport),
      time_limit = 10,
      description = "search, grasp and transport the object to the goal region",
    },
    search_grasp = {
      action = Phi_SG,
      goal = roger.converged(p.phi3),  -- the absorbing state of Phi_SG: gamma(phi3) = CONV
      time_limit = 5,
      description = "search for the object, approach it and form a three-contact grasp",
    },
    phi6 = {
      action = Phi6,
      goal = roger.converged(p.phi0),  -- the stimulus centred in both eyes
      time_limit = 5,
      description = "search for the stimulus and track it",
    },
  },
}
