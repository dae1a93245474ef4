-- Fixture: asks the shape library for a shape it does not have (line 6).
local shapes = require("lib.shapes")
return {
  generate = function(world, rng, params)
    world:robot{ x = 0, y = 0 }
    local s = shapes.get("hexagon")
    world:object{ shape = s, x = 1, y = 1 }
  end,
}
