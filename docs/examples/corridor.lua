-- docs/examples/corridor.lua: an example scenario for docs/scenarios.md.
--
-- A 6 x 3 m arena split by a wall with a door at a random height. Roger and a blue capsule start
-- in the left room; the goal is in the right room, so transporting the capsule means going
-- through the door. Try it:
--   roger check docs/examples/corridor.lua
--   roger render docs/examples/corridor.lua --seed 3 --set door=1.2 --out corridor.png
local shapes = require("lib.shapes")   -- found in <project>/scenarios/lib/shapes.lua

-- A custom object: a capsule, one box and two disks (a shape may mix both).
local capsule = roger.shape{
  name = "capsule",
  polygons = { { { -0.1, -0.08 }, { 0.1, -0.08 }, { 0.1, 0.08 }, { -0.1, 0.08 } } },
  disks = { { x = -0.1, r = 0.08 }, { x = 0.1, r = 0.08 } },
}

return {
  name = "corridor",
  description = "Two rooms joined by a door; carry the capsule from the left room to the goal in the right one.",

  params = {
    door = { default = 0.9, min = 0.5, max = 2.0, description = "door width (m)" },
    wall_thickness = { default = 0.1, min = 0.02, description = "thickness of the dividing wall (m)" },
    object_distance = { default = 1.0, min = 0.0, description = "least distance from Roger to the capsule (m)" },
    capsule = { default = true, description = "false uses the library's ball instead of the capsule" },
  },

  generate = function(world, rng, p)
    world:arena{ xmin = -3, xmax = 3, ymin = -1.5, ymax = 1.5, cell = 0.0625 }

    -- The dividing wall at x = 0: two grey boxes around a door centred at door_y.
    local door_y = rng:uniform(-1.5 + p.door / 2 + 0.2, 1.5 - p.door / 2 - 0.2)
    local below = door_y - p.door / 2 + 1.5   -- length of the lower wall piece
    local above = 1.5 - (door_y + p.door / 2)  -- and of the upper one
    world:obstacle{ name = "wall below", shape = shapes.box("wall below", p.wall_thickness, below),
                    x = 0, y = -1.5 + below / 2 }
    world:obstacle{ name = "wall above", shape = shapes.box("wall above", p.wall_thickness, above),
                    x = 0, y = 1.5 - above / 2 }

    world:goal{ name = "goal", x = 2.2, y = 0, radius = 0.3 }

    -- Roger anywhere in the left room, any heading.
    local rx, ry = world:sample_position{
      name = "Roger", radius = roger.robot.footprint_radius, region = { xmax = 0 },
    }
    world:robot{ x = rx, y = ry, heading = rng:angle() }

    -- The object in the left room too, away from Roger.
    local shape = p.capsule and capsule or shapes.get("circle")
    local ox, oy = world:sample_position{
      name = shape.name, shape = shape, region = { xmax = 0 }, robot_distance = p.object_distance,
    }
    world:object{ name = shape.name, shape = shape, colour = { 40, 80, 220 },
                  x = ox, y = oy, theta = rng:angle() }
    -- The eyes look for the first object's colour unless world:stimulus{colour=...} says otherwise.
  end,
}
