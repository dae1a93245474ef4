-- lib/place.lua: the placement steps of the paper's transport task, shared by unobstructed.lua
-- and cluttered.lua. Each step draws from the generator's rng through world:sample_position, so a
-- world stays a pure function of (scenario, parameters, seed).
--
-- Order matters and is the same in both scenarios: goal, Roger, object, then obstacles. With the
-- same seed and parameters, cluttered.lua therefore puts Roger and the object exactly where
-- unobstructed.lua does, and only adds obstacles around them.
local shapes = require("lib.shapes")
local body = require("lib.body")

local place = {}

-- The scenario parameters each step reads beyond the body's (lib/body.lua). A scenario of one's own
-- that lacks one is told so at its own line, the one that called the step, rather than at this
-- file's line that reads it. Found by a probe: place.robot failed at lib/place.lua:31 on
-- robot_wall_margin.
local NEEDS = {
  goal = { "goal_x", "goal_y", "goal_radius" },
  robot = { "robot_wall_margin" },
  object = { "shape", "mass", "object_wall_margin", "robot_distance" },
  obstacles = { "obstacles", "obstacle_min_size", "obstacle_max_size", "obstacle_clearance" },
}
local SIGNATURE = { goal = "(world, p)", robot = "(world, rng, p)", object = "(world, rng, p)",
                    obstacles = "(world, rng, p)" }
local function check_params(step, p)
  -- Found by a probe: place.goal(world, rng, p) failed inside this file, "bad argument #1 to
  -- 'rawget' (table expected, got roger.Rng)", naming no line of the scenario.
  if type(p) ~= "table" then
    -- tostring names the engine's userdata by kind ("roger.Rng: 0x..."), where type says "userdata".
    local got = type(p) == "userdata" and tostring(p):match("^[%w%.]+") or type(p)
    error(string.format("place.%s%s: p must be the generator's parameters (its third argument), got %s",
                        step, SIGNATURE[step], got), 3)
  end
  local missing = {}
  for _, name in ipairs(NEEDS[step]) do
    if rawget(p, name) == nil then missing[#missing + 1] = name end
  end
  if #missing > 0 then
    error(string.format("place.%s reads the scenario parameter%s %s, which the scenario does not declare: "
                        .. "add %s to its params (scenarios/unobstructed.lua and scenarios/cluttered.lua show "
                        .. "each with its default and range)", step, #missing > 1 and "s" or "",
                        "'" .. table.concat(missing, "', '") .. "'", #missing > 1 and "them" or "it"), 3)
  end
end

-- The paper's red: the eyes track this colour.
place.RED = { 220, 30, 30 }

-- The transport goal: a floor region (the paper carries the ball to the origin).
function place.goal(world, p)
  check_params("goal", p)
  world:goal{ name = "goal", x = p.goal_x, y = p.goal_y, radius = p.goal_radius }
end

-- Roger, with the body and eyes of p (lib/body.lua), at a random position and heading. The sampled
-- disk is Roger's whole footprint (base and both hands folded as that body folds them:
-- roger.body_metrics(...).footprint_radius), so no heading puts a hand in a wall or on the goal;
-- p.robot_wall_margin is the least distance from the walls to the base centre (the footprint may
-- make it larger). Returns the base position.
-- "Roger", and the sizes of its body that are not the paper's (found by a probe: a body too large
-- for the arena was refused as "no placement for 'Roger'", naming no parameter); sorting.lua's too.
local SIZES = { "upper_arm", "forearm", "base_radius", "hand_radius" }
function place.robot_name(p)
  local changed = {}
  for _, name in ipairs(SIZES) do
    if p[name] ~= body.PARAMS[name].default then
      changed[#changed + 1] = name .. " = " .. string.format("%.14g", p[name])
    end
  end
  return #changed == 0 and "Roger" or ("Roger (" .. table.concat(changed, ", ") .. ")")
end

function place.robot(world, rng, p)
  check_params("robot", p)
  local b = body.of(p, 1)  -- its errors at the scenario's line, as noise_of's
  local x, y = world:sample_position{
    name = place.robot_name(p),
    radius = roger.body_metrics(b).footprint_radius,
    wall_margin = p.robot_wall_margin,
  }
  world:robot{ x = x, y = y, heading = rng:angle(), body = b.body, eyes = b.eyes, noise = body.noise_of(p, 1) }
  return x, y
end

-- The object (shape p.shape, red, mass p.mass) at a random orientation, its centre at least
-- p.object_wall_margin from the walls and p.robot_distance from Roger's base centre, clear of
-- Roger's hands and of the goal region. Returns the object's position.
function place.object(world, rng, p)
  check_params("object", p)
  local shape = shapes.get(p.shape, "place.object")
  local x, y = world:sample_position{
    name = p.shape,
    shape = shape,
    wall_margin = p.object_wall_margin,
    robot_distance = p.robot_distance,
  }
  world:object{
    name = p.shape, shape = shape, colour = place.RED,
    x = x, y = y, theta = rng:angle(), mass = p.mass,
  }
  return x, y
end

-- p.obstacles grey static obstacles, each a box (sides drawn in [min, max]) or a disk (diameter
-- drawn in [min, max]) at a random orientation, with at least p.obstacle_clearance of free floor
-- between it and Roger, the object, the goal region, the walls and the other obstacles.
--
-- Why the object can never be hidden from every viewpoint: an obstacle's bounding radius is at
-- most max/sqrt(2) (0.21 m by default) and its centre keeps clearance + that radius (0.61 m) from
-- the object's surface, so seen from the object each obstacle spans less than
-- 2 asin(0.21 / 0.61) = 40 degrees; three obstacles block at most 120 of the 360 degrees of lines
-- of sight, and with the object 0.95 m from the walls there are free viewpoints in the open
-- directions. tests/test_scenario.cpp checks it with the eyes' own painter over 1000 seeds.
function place.obstacles(world, rng, p)
  check_params("obstacles", p)
  if p.obstacle_min_size > p.obstacle_max_size then
    error(string.format("obstacle_min_size (%g) exceeds obstacle_max_size (%g)",
                        p.obstacle_min_size, p.obstacle_max_size), 2)
  end
  -- Found by a probe: obstacles declared with a default of 2.0 (a real) took --set obstacles=2.5
  -- and built 2, unsaid.
  if math.type(p.obstacles) ~= "integer" and p.obstacles ~= math.floor(p.obstacles) then
    error(string.format("place.obstacles: the parameter obstacles is a count, got %g (declare it with a whole " ..
                        "default, { default = 3, min = 0 }, and it takes whole numbers only)", p.obstacles), 2)
  end
  for i = 1, p.obstacles do
    local name = "obstacle " .. i
    local shape
    if rng:choice{ "box", "disk" } == "box" then
      shape = shapes.box(name, rng:uniform(p.obstacle_min_size, p.obstacle_max_size),
                         rng:uniform(p.obstacle_min_size, p.obstacle_max_size))
    else
      shape = shapes.disk(name, rng:uniform(p.obstacle_min_size, p.obstacle_max_size) / 2)
    end
    local x, y = world:sample_position{
      name = name, shape = shape, clearance = p.obstacle_clearance,
    }
    world:obstacle{ name = name, shape = shape, x = x, y = y, theta = rng:angle() }
  end
end

return place
