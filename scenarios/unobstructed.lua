-- unobstructed.lua: the paper's training world (Section III): Roger, one red ball and the
-- transport goal in an empty 4 x 4 m arena.
--
-- The paper fixes the arena, the ball (radius 0.2 m, red) and the goal (the origin) but not the
-- start poses. Here:
--   * Roger starts at a random position and heading, its base centre at least 0.5 m from the walls
--     and its whole footprint (base and hands in the start posture) inside the arena at any heading;
--   * the object's centre is at least 0.95 m from the walls and 1.4 m from Roger's base centre, so
--     Roger must search, approach and grasp it, and there is room all around it for the hands;
--   * the goal is a disk of radius 0.25 m at the origin; neither Roger nor the object starts on it
--     (both keep 0.05 m of clearance from it), so every episode needs a real transport.
-- The `shape` parameter runs the same world with the other shapes of Section IV.
local shapes = require("lib.shapes")
local place = require("lib.place")
local body = require("lib.body")

return {
  name = "unobstructed",
  description = "Section III: Roger, a red object and the goal at the origin in an empty 4 x 4 m arena.",

  params = body.with_params{
    shape = { default = "circle", choices = shapes.names(),
              description = "the object: circle (the paper's ball), triangle, pentagon or spade" },
    mass = { default = 0.5, min = 0.01, max = 10000, description = "object mass (kg)" },
    object_wall_margin = { default = 0.95, min = 0.0,
                           description = "least distance from the walls to the object's centre (m)" },
    robot_distance = { default = 1.4, min = 0.0,
                       description = "least distance from Roger's base centre to the object's centre (m)" },
    robot_wall_margin = { default = 0.5, min = 0.0,
                          description = "least distance from the walls to Roger's base centre (m)" },
    goal_x = { default = 0.0, description = "goal centre x (m)" },
    goal_y = { default = 0.0, description = "goal centre y (m)" },
    goal_radius = { default = 0.25, min = 0.01, description = "goal radius (m)" },
  },

  generate = function(world, rng, p)
    world:arena{ xmin = -2, xmax = 2, ymin = -2, ymax = 2, cell = 0.0625 }
    place.goal(world, p)
    place.robot(world, rng, p)
    place.object(world, rng, p)
  end,
}
