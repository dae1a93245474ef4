-- Fixture: a stage whose time limit table misspells per_object, named at its roger.stage line (4).
local p3 = roger.primitive("phi3")
return { stages = {
  roger.stage{
    name = "Typo", scenario = "sorting", time_limit = { per_objects = 30 }, absorbing = roger.converged(p3),
    budget = { episodes = 3 }, contexts = { { name = "A", actions = { p3 } } },
  },
} }
