-- Fixture: an absorbing state held for 250 "seconds" (ticks meant) in episodes of 5 s, which can
-- never hold; named at its roger.stage line (4).
local p3 = roger.primitive("phi3")
return { stages = {
  roger.stage{
    name = "Patient", time_limit = 5, absorbing = roger.held(roger.converged(p3), 250),
    budget = { episodes = 3 }, contexts = { { name = "A", actions = { p3 } } },
  },
} }
