-- sorting.lua: the sorting task of the paper's Figure 1: objects of the four types (circle,
-- triangle, pentagon, spade), each type in its own colour, to be carried each into the goal region
-- of its type. The four regions sit at fixed places on the arena's edge, in the middle of each wall;
-- goal region k (0-based, as phi1's `region`) belongs to sorting.TYPES[k + 1].
--
--   roger check scenarios/sorting.lua --seeds 50
--   roger render sorting --seed 3 --set objects=4 --out sorting.png
--
-- Placement order: the objects' types (drawn first for the "random" mix, since a region's size
-- follows the number of objects of its type), the regions, Roger, the objects (each type's colour),
-- then the obstacles, all from the generator's rng, so a world is a pure function of (parameters,
-- seed).
local shapes = require("lib.shapes")
local body = require("lib.body")
local place = require("lib.place")

-- The types, their colours and their regions, in region order.
local TYPES = { "circle", "triangle", "pentagon", "spade" }
local COLOURS = {
  circle = { 220, 30, 30 },     -- the paper's red ball
  triangle = { 40, 80, 220 },   -- blue
  pentagon = { 230, 170, 20 },  -- amber
  spade = { 150, 40, 170 },     -- purple
}
-- Half the arena's side: 5 x 5 m for up to four objects, 6 x 6 m up to eight, 7 x 7 m beyond, so
-- that every object keeps room around it for the hands; wider by as much as the regions have grown
-- beyond 0.4 m (a random mix may put many objects of one type in one region).
local function half_side(objects, radius)
  local half = (objects <= 4 and 2.5 or objects <= 8 and 3.0 or 3.5) + (radius - 0.4)
  return math.ceil(half * 4 - 1e-9) / 4  -- a whole number of grid cells across
end

-- A region holds every object of its type, each an obstacle to the next one carried in (the planner
-- grows it by the carried object's reach): 0.4 m of radius for one object, 0.2 m more for each
-- further one. Its centre sits 0.4 m further from its wall than its radius, so the carried object
-- fits in with Roger clear of the wall.
local function region_radius(per_type)
  return 0.4 + 0.2 * (math.max(per_type, 1) - 1)
end

-- Region centres: the middle of the east, north, west and south walls.
local function region_centre(k, half, radius)
  local d = half - radius - 0.4
  return ({ { d, 0 }, { 0, d }, { -d, 0 }, { 0, -d } })[k]
end

-- The order of the "cycle" mix. The triangle comes last: of the four it is the one the grasp
-- primitives hold least reliably while carrying (docs/results.md, Sorting), so the small worlds
-- test sorting rather than that grasp; 4 and 8 objects hold every type.
local CYCLE = { "circle", "spade", "pentagon", "triangle" }

-- The objects' types for a mix: "cycle" takes the types in turn (circle, spade, pentagon,
-- triangle, circle, ...), "random" draws each. Returns the list and the largest count of one type.
local function object_types(n, mix, rng)
  local types, count, most = {}, {}, 0
  for i = 1, n do
    local t = mix == "cycle" and CYCLE[(i - 1) % #CYCLE + 1] or rng:choice(TYPES)
    types[i] = t
    count[t] = (count[t] or 0) + 1
    most = math.max(most, count[t])
  end
  return types, most
end

return {
  name = "sorting",
  description = "Figure 1: 1 to 12 objects of four types, each type to its own region on the arena's edge.",

  params = body.with_params{
    objects = { default = 2, min = 1, max = 12, description = "number of objects" },
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
    local types, most = object_types(p.objects, p.mix, rng)
    local radius = region_radius(most)
    local half = half_side(p.objects, radius)
    world:arena{ xmin = -half, xmax = half, ymin = -half, ymax = half, cell = 0.0625 }
    for k, t in ipairs(TYPES) do
      local c = region_centre(k, half, radius)
      world:goal{ name = t, x = c[1], y = c[2], radius = radius, colour = COLOURS[t] }
    end
    local b = body.of(p)
    local rx, ry = world:sample_position{
      name = place.robot_name(p), radius = roger.body_metrics(b).footprint_radius, wall_margin = 1.0, clearance = 0.2,
    }
    world:robot{ x = rx, y = ry, heading = rng:angle(), body = b.body, eyes = b.eyes, noise = body.noise_of(p) }
    for i = 1, p.objects do
      local t = types[i]
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
