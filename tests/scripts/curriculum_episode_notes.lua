-- Fixture: a Lua reward that counts its calls in `episode`, the table that lasts one episode, and
-- an absorbing function that reads the count (tests/test_curriculum.cpp).
local p3 = roger.primitive("phi3")
local p0 = roger.primitive("phi0")
local function reward(state, action, event, time, world, episode)
  episode.calls = (episode.calls or 0) + 1
  return episode.calls
end
local function absorbing(state, time, world, episode)
  return (episode.calls or 0) >= 3
end
return { stages = {
  roger.stage{ name = "S", time_limit = 0.5, absorbing = absorbing, reward = reward,
               budget = { episodes = 2 }, contexts = { { name = "A", actions = { p3, p0 } } } },
} }
