-- Fixture: the skill names a context the stage does not have (the stage is written at line 4).
local p3 = roger.primitive("phi3")
return { stages = {
  roger.stage{ name = "S", time_limit = 5, absorbing = roger.converged(p3), budget = { episodes = 10 },
               contexts = { { name = "A", actions = { p3 } } }, skill = { name = "K", context = "DC9" } },
} }
