-- Fixture: a Lua reward that returns a reward and a done flag, as a Gymnasium step would (the
-- function is defined at line 5).
local p3 = roger.primitive("phi3")
local p0 = roger.primitive("phi0")
local function reward(state, action, event)
  return 1.0, event == "absorbing"
end
return { stages = {
  roger.stage{ name = "S", time_limit = 0.5, absorbing = roger.converged(p3), reward = reward,
               budget = { episodes = 2 }, contexts = { { name = "A", actions = { p3, p0 } } } },
} }
