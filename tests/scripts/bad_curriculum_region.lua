-- Fixture: a context whose navigator goes to goal region 7, in worlds of one region (the
-- unobstructed scenario's); the other context's binding names region 0, and its navigator follows.
local to_seven = roger.primitive("phi1", { goal = "region", region = 7 })
local p3 = roger.primitive("phi3")
local bound = roger.bind("to the goal", roger.primitive("phi1", { goal = "region", region = 9 }), { region = 0 })
return { stages = {
  roger.stage{ name = "S", time_limit = 0.5, absorbing = roger.converged(p3),
               budget = { episodes = 2 },
               contexts = { { name = "Bound", actions = { p3, bound } }, { name = "A", actions = { p3, to_seven } } } },
} }
