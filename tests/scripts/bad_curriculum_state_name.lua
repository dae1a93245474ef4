-- Fixture: an absorbing function that reads the state by a name that is no action's (Phi3 for
-- phi3, line 5). A nil there made the test false for good: the stage never learned, silently.
local p3 = roger.primitive("phi3")
local function absorbing(state)
  return state.Phi3 == "CONV"
end
return { stages = {
  roger.stage{ name = "S", time_limit = 0.5, absorbing = absorbing,
               budget = { episodes = 2 }, contexts = { { name = "A", actions = { p3 } } } },
} }
