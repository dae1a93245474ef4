-- Preshaping with the body's distance left to phi4: phi2 with body = "clear" fixes only the hands
-- (the body just keeps clear of the object), so phi4 <| phi2 can back the base off, the arms
-- compensating, until the elbows near 90 degrees. See "Which body to use" in docs/control.md.
local skills = require("lib.skills")

-- phi4 steps slowly: its nullspace motion runs through the base, which follows a step several
-- times slower than the arms, and a fast step would reach the hands before the base has moved.
local p = skills.primitives{ phi2 = { body = "clear" }, phi4 = { rate = 0.04 } }

local condition = p.phi4:subject_to(p.phi2)  -- phi4 <| phi2

return {
  name = "conditioning",
  description = "Approach the ball, then preshape with phi4 conditioning the arms in phi2's nullspace.",
  policies = {
    preshape = {
      action = roger.sequence("approach_and_condition", { skills.Phi6(p), p.phi1, condition }),
      -- The preshape reached and the posture settled: both sides of the composite converged.
      goal = roger.held(roger.converged(condition), 0.2),
      time_limit = 15,
      description = "search, approach, then preshape while conditioning the arms",
    },
  },
}
