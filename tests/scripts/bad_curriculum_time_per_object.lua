-- Fixture: a stage whose time limit per object is not positive, named at its roger.stage line (4).
local p3 = roger.primitive("phi3")
return { stages = {
  roger.stage{
    name = "Slow", scenario = "sorting", time_limit = { per_object = 0 }, absorbing = roger.converged(p3),
    budget = { episodes = 3 }, contexts = { { name = "A", actions = { p3 } } },
  },
} }
