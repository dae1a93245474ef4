-- Fixture: a Lua absorbing function that misspells a field of `world` (line 5), found by
-- roger check (world.objcts is nil) rather than at training's first episode.
local p3 = roger.primitive("phi3")
local function absorbing(state, time, world)
  local first = world.objcts[1]
  return first ~= nil and first.region ~= nil
end
return { stages = {
  roger.stage{ name = "S", time_limit = 0.5, absorbing = absorbing,
               budget = { episodes = 2 }, contexts = { { name = "A", actions = { p3 } } } },
} }
