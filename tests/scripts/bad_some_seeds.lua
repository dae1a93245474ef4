-- Fixture: a generator that fails for some seeds only (a nil indexed on line 7); seed 2 is the first.
local shapes = require("lib.shapes")
return {
  generate = function(world, rng, p)
    world:arena{ xmin = -2, xmax = 2, ymin = -2, ymax = 2 }
    world:robot{ x = 0, y = 0 }
    if rng:uniform() < 0.3 then local q = nil; world:object{ shape = q.shape } end
    world:object{ shape = shapes.get("circle"), x = 1, y = 1 }
  end,
}
