-- Fixture: thirteen actions in one context (the stage is written at line 7).
local actions = {}
for i = 1, 13 do
  actions[i] = roger.primitive("phi0", { name = "look" .. i })
end
return { stages = {
  roger.stage{ name = "S", time_limit = 5, absorbing = roger.converged(actions[1]), budget = { episodes = 10 },
               contexts = { { name = "Wide", actions = actions } } },
} }
