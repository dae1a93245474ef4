-- A misspelt method inside a helper the generator calls (tests/test_scenario.cpp): the error is at
-- the helper's line (5), where the mistake is, not at the generator's call of it (11).
local function place(world)
  -- Not a tail call: the generator's frame stays below this one.
  local x, y = world:sample_positon{ name = "Roger", radius = 0.2 }
  return x, y
end
return {
  generate = function(world, rng, params)
    world:arena{ xmin = -2, xmax = 2, ymin = -2, ymax = 2 }
    local x, y = place(world)
    world:robot{ x = x, y = y }
  end,
}
