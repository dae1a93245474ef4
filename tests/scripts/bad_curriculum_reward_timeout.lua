-- Fixture: a Lua reward whose slip is on the time-out's branch only (the slip is at line 6).
local p3 = roger.primitive("phi3")
local p0 = roger.primitive("phi0")
local function reward(state, action, event, time, world)
  if event == "timeout" then
    return -100 * world.objects[1].massa
  end
  return 0
end
return { stages = {
  roger.stage{ name = "S", time_limit = 0.5, absorbing = roger.converged(p3), reward = reward,
               budget = { episodes = 2 }, contexts = { { name = "A", actions = { p3, p0 } } } },
} }
