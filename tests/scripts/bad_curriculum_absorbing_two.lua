-- Fixture: a Lua absorbing function that returns two values (defined at line 4).
local p3 = roger.primitive("phi3")
local p0 = roger.primitive("phi0")
local function absorbing(state)
  return state.phi3 == "CONV", "converged"
end
return { stages = {
  roger.stage{ name = "S", time_limit = 0.5, absorbing = absorbing,
               budget = { episodes = 2 }, contexts = { { name = "A", actions = { p3, p0 } } } },
} }
