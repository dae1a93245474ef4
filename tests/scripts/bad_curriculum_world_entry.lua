-- Fixture: Lua callbacks that misspell a field of an entry of `world` (tests/test_curriculum.cpp).
-- Before, o.regoin read nil: roger check said ok and the stage never succeeded.
local p3 = roger.primitive("phi3")
local function in_goal(o)
  local inside = o.regoin == "goal"  -- line 5: the helper's line, not its caller's
  return inside
end
local function absorbing(state, time, world)
  local found = false
  for _, o in ipairs(world.objects) do
    if in_goal(o) then found = true end
  end
  return found
end
return { stages = {
  roger.stage{ name = "S", time_limit = 0.5, absorbing = absorbing,
               budget = { episodes = 2 }, contexts = { { name = "A", actions = { p3 } } } },
} }
