-- sorting.lua: the sorting task of the paper's Figure 1: objects of the four types (circle,
-- triangle, pentagon, spade), each type in its own colour, to be carried each into the goal region
-- of its type. The four regions sit at fixed places on the arena's edge, in the middle of each wall;
-- goal region k (0-based, as phi1's `region`) belongs to sorting.TYPES[k + 1].
--
--   roger check scenarios/sorting.lua --seeds 50
--   roger render sorting --seed 3 --set objects=4 --out sorting.png
--
-- Placement order: the regions, Roger, the objects (each type's colour), then the obstacles, all
-- from the generator's rng, so a world is a pure function of (parameters, seed).
local shapes = require("lib.shapes")

-- The types, their colours and their regions, in region order.
local TYPES = { "circle", "triangle", "pentagon", "spade" }
local COLOURS = {
  circle = { 220, 30, 30 },     -- the paper's red ball
  triangle = { 40, 80, 220 },   -- blue
  pentagon = { 230, 170, 20 },  -- amber
  spade = { 150, 40, 170 },     -- purple
}
local REGION_RADIUS = 0.4
local REGION_INSET = 0.8 -- region centre to its wall: the carried object fits in with Roger clear of the wall

-- Half the arena's side: 5 x 5 m for up to four objects, 6 x 6 m for more, so that every object
-- keeps room around it for the hands (eight in 5 x 5 m often leave no place for the last one).
local function half_side(objects)
  return objects <= 4 and 2.5 or 3.0
end

-- Region centres: the middle of the east, north, west and south walls.
local function region_centre(k, half)
  local d = half - REGION_INSET
  return ({ { d, 0 }, { 0, d }, { -d, 0 }, { 0, -d } })[k]
end

-- The order of the "cycle" mix. The triangle comes last: of the four it is the one the grasp
-- primitives hold least reliably while carrying (docs/results.md, Sorting), so the small worlds
-- test sorting rather than that grasp; 4 and 8 objects hold every type.
local CYCLE = { "circle", "spade", "pentagon", "triangle" }

-- The i-th object's type for a mix: "cycle" takes the types in turn (circle, spade, pentagon,
-- triangle, circle, ...), "random" draws each.
local function object_type(i, mix, rng)
  if mix == "cycle" then return CYCLE[(i - 1) % #CYCLE + 1] end
  return rng:choice(TYPES)
end

return {
  name = "sorting",
  description = "Figure 1: 2 to 8 objects of four types, each type to its own region on the arena's edge.",

  params = {
    objects = { default = 2, min = 1, max = 8, description = "number of objects" },
    mix = { default = "cycle", choices = { "cycle", "random" },
            description = "types in turn (circle, spade, pentagon, triangle, ...) or drawn at random" },
    obstacles = { default = 0, min = 0, max = 4, description = "number of static obstacles" },
    object_clearance = { default = 0.35, min = 0.1,
                         description = "free floor around each object (m): room for the hands" },
    object_wall_margin = { default = 1.0, min = 0.3,
                           description = "least distance from the walls to an object's centre (m)" },
    robot_distance = { default = 0.9, min = 0.0,
                       description = "least distance from Roger's base centre to an object's centre (m)" },
  },

  generate = function(world, rng, p)
    local half = half_side(p.objects)
    world:arena{ xmin = -half, xmax = half, ymin = -half, ymax = half, cell = 0.0625 }
    for k, t in ipairs(TYPES) do
      local c = region_centre(k, half)
      world:goal{ name = t, x = c[1], y = c[2], radius = REGION_RADIUS, colour = COLOURS[t] }
    end
    local rx, ry = world:sample_position{
      name = "Roger", radius = roger.robot.footprint_radius, wall_margin = 1.0, clearance = 0.2,
    }
    world:robot{ x = rx, y = ry, heading = rng:angle() }
    for i = 1, p.objects do
      local t = object_type(i, p.mix, rng)
      local shape = shapes.get(t)
      local x, y = world:sample_position{
        name = t .. " " .. i, shape = shape, clearance = p.object_clearance,
        wall_margin = p.object_wall_margin, robot_distance = p.robot_distance, tries = 5000,
      }
      world:object{ name = t .. " " .. i, shape = shape, colour = COLOURS[t], x = x, y = y, theta = rng:angle() }
    end
    for i = 1, p.obstacles do
      local name = "obstacle " .. i
      local shape = shapes.box(name, rng:uniform(0.15, 0.3), rng:uniform(0.15, 0.3))
      local x, y = world:sample_position{ name = name, shape = shape, clearance = 0.3, tries = 20000 }
      world:obstacle{ name = name, shape = shape, x = x, y = y, theta = rng:angle() }
    end
    -- Unbound controllers look for the circle's red, as in the paper's worlds.
    world:stimulus{ colour = COLOURS.circle }
  end,
}
