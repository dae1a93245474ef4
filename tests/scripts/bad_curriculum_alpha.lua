-- Fixture: a stage whose learner's alpha is out of range, named at its roger.stage line (4) once.
local p3 = roger.primitive("phi3")
return { stages = {
  roger.stage{
    name = "Alpha", time_limit = 5, absorbing = roger.converged(p3), budget = { episodes = 3 },
    learner = { alpha = -1 },
    contexts = { { name = "A", actions = { p3 } } },
  },
} }
