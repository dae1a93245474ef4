-- skills_example.lua: a skill script from docs/control.md. It builds the paper's skills from the
-- shared library, tunes a primitive, writes the transport stage as a hand-made state-to-action
-- policy over the paper's smallest action set (DC6: Phi_STG and phi1 <| phi4 <| phi5), and
-- returns two policies to evaluate:
--
--   roger check docs/examples/skills_example.lua
--   roger eval docs/examples/skills_example.lua --policy transport
local skills = require("lib.skills")   -- curricula/lib/skills.lua

-- The primitives, with a grasp that must hold for a tenth of a second before it counts.
local p = skills.primitives{ phi3 = { hold = 0.1 } }

-- Search-grasp as a sequence of the assumed skills: each step runs until it converges.
local Phi_SG = roger.sequence("Phi_SG", {
  skills.Phi6(p),   -- search, then track (Phi6)
  skills.Phi7(p),   -- approach while preshaping (Phi7)
  p.phi3,           -- close the grasp
})

-- Phi_STG: search-grasp, then keep the grasp with phi4 <| phi5.
local Phi_STG = skills.Phi_STG(Phi_SG, p)

-- The transport composite, in the paper's notation (phi1 here is the carrying navigator).
local carry = roger.compose("phi1 <| phi4 <| phi5", { phi1 = p.carry, phi4 = p.phi4, phi5 = p.phi5 })

-- A state-to-action policy: the state is the gamma of each action, in order; "*" matches any
-- state, and the most specific key wins.
local Phi_T = roger.policy("Phi_T", {
  actions = { "Phi_STG", carry },    -- a skill may be named by a string
  table = {
    ["* *"]    = "Phi_STG",          -- until the grasp is formed and held: search and grasp
    ["CONV *"] = carry,              -- holding it: carry it to the goal region
  },
  done = skills.transported(carry),  -- Phi_T converges in the paper's absorbing state
})

return {
  name = "example",
  description = "The transport stage as a hand-written policy over Phi_STG and phi1 <| phi4 <| phi5.",
  policies = {
    transport = {
      action = Phi_T,
      goal = skills.transported(carry),            -- phi1, phi4 and phi5 all CONV
      time_limit = 10,
      description = "search, grasp and carry the object to the goal region",
    },
    grasp = {
      action = Phi_STG,
      goal = roger.held(roger.converged(p.phi5), 0.5),  -- the grasp kept for half a second
      time_limit = 6,
      scenario = "unobstructed",
    },
  },
}
