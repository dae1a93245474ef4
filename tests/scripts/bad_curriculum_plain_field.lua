-- Fixture: a plain-table stage (no roger.stage) with a bad budget, named at line 5.
local p3 = roger.primitive("phi3")
return { stages = {
  {
    name = "Plain", time_limit = 5, absorbing = roger.converged(p3), budget = { episodes = -3 },
    contexts = { { name = "A", actions = { p3 } } },
  },
} }
