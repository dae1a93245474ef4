-- Fixture: a misspelt field of `world` itself (tests/test_curriculum.cpp): world.goalz read nil,
-- so this absorbing function never held.
local p3 = roger.primitive("phi3")
local function absorbing(state, time, world)
  return world.goalz ~= nil and #world.goalz > 0
end
return { stages = {
  roger.stage{ name = "S", time_limit = 0.5, absorbing = absorbing,
               budget = { episodes = 2 }, contexts = { { name = "A", actions = { p3 } } } },
} }
