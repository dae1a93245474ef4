-- Fixture: a Lua absorbing function that raises (line 5).
local p3 = roger.primitive("phi3")
local p0 = roger.primitive("phi0")
local function absorbing(state)
  error("no such sensor: " .. tostring(state.phi3 and "nose"))
end
return { stages = {
  roger.stage{ name = "S", time_limit = 0.5, absorbing = absorbing,
               budget = { episodes = 2 }, contexts = { { name = "A", actions = { p3, p0 } } } },
} }
