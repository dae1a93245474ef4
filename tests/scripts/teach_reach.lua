-- teach_reach.lua: a world whose difficulty one parameter sets, for the teachers' tests
-- (tests/test_teach.cpp), with a trivial part, a learnable band and an unlearnable part of known
-- extent. Roger faces the red ball straight ahead; `level` in [0, 1] sets how far it is from the
-- approach ring around the ball:
--   level < 0.4:        on the ring: phi1 has converged before anything moves (always a success);
--   0.4 <= level <= 0.6: 1.5 to 2.5 m, which phi1 covers within the stage's 3 s only when chosen
--                       first (phi4 first costs 1.8 s: a learner must learn to commit to phi1);
--   level > 0.6:        4 m, beyond reach in 3 s whatever is chosen.
-- `distance` (when >= 0) sets the distance itself instead.
local shapes = require("lib.shapes")

local function distance_of(p)
  if p.distance >= 0 then return p.distance end
  if p.level < 0.4 then return 0 end
  if p.level <= 0.6 then return 1.5 + 5 * (p.level - 0.4) end
  return 4
end

return {
  name = "teach_reach",
  description = "Roger faces the ball straight ahead: trivial, learnable or beyond reach by one parameter.",
  params = {
    level = { default = 0.5, min = 0.0, max = 1.0,
              description = "difficulty: < 0.4 trivial, to 0.6 learnable, above beyond reach" },
    distance = { default = -1.0, min = -1.0, max = 4.5,
                 description = "distance from the approach ring to Roger (m); -1: from level" },
  },
  generate = function(world, rng, p)
    world:arena{ xmin = -3, xmax = 3, ymin = -1.5, ymax = 1.5, cell = 0.1 }
    world:robot{ x = -2.4, y = rng:uniform(-0.05, 0.05), heading = 0 }
    world:object{ name = "ball", shape = shapes.get("circle"), colour = { 220, 30, 30 },
                  x = -2.4 + 0.58 + distance_of(p), y = 0 }
  end,
}
