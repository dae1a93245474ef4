-- Fixture: a stage uses the skill it yields itself (the stage is written at line 5, the context at 6).
local p3 = roger.primitive("phi3")
local K = roger.learned("K")
return { stages = {
  roger.stage{ name = "S", time_limit = 5, absorbing = roger.converged(p3), budget = { episodes = 10 },
               contexts = { { name = "A", actions = { p3 } }, { name = "B", actions = { p3, K } } },
               skill = { name = "K", context = "A" } },
} }
