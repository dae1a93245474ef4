-- Fixture: a context with no actions (the stage is written at line 4).
local p3 = roger.primitive("phi3")
return { stages = {
  roger.stage{ name = "S", time_limit = 5, absorbing = roger.converged(p3), budget = { episodes = 10 },
               contexts = { { name = "Empty", actions = {} } } },
} }
