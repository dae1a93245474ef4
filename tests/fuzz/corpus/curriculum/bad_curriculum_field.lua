-- Fixture: a misspelt field (time_limt) in the stage written at line 4.
local p3 = roger.primitive("phi3")
return { stages = {
  roger.stage{ name = "S", time_limt = 5, absorbing = roger.converged(p3), budget = { episodes = 10 },
               contexts = { { name = "A", actions = { p3 } } } },
} }
