-- Fixture: a stage whose learner's unconverged_first is not a boolean, named at its roger.stage line (4).
local p3 = roger.primitive("phi3")
return { stages = {
  roger.stage{
    name = "Eager", time_limit = 5, absorbing = roger.converged(p3), budget = { episodes = 3 },
    learner = { unconverged_first = "yes" },
    contexts = { { name = "A", actions = { p3 } } },
  },
} }
