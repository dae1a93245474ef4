-- Fixture: a stage whose learner's discount clock is negative, named at its roger.stage line (4).
local p3 = roger.primitive("phi3")
return { stages = {
  roger.stage{
    name = "Clock", time_limit = 5, absorbing = roger.converged(p3), budget = { episodes = 3 },
    learner = { discount_seconds = -2 },
    contexts = { { name = "A", actions = { p3 } } },
  },
} }
