-- Fixture: an absorbing function that calls the state's __index itself on a number (line 5). It
-- crashed roger (the metamethod walked its first argument as a table); it is an error at the line.
local p3 = roger.primitive("phi3")
local function absorbing(state)
  return getmetatable(state).__index(5, "x") == "CONV"
end
return { stages = {
  roger.stage{ name = "S", time_limit = 0.5, absorbing = absorbing,
               budget = { episodes = 2 }, contexts = { { name = "A", actions = { p3 } } } },
} }
