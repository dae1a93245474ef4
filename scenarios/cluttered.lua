-- cluttered.lua: the paper's generalization world (Section IV): the unobstructed world plus
-- randomly placed static obstacles, with any of the four object shapes.
--
-- Roger, the object and the goal are placed exactly as in unobstructed.lua (same rules, same
-- draws: for a given seed they are in the same places), then `obstacles` grey boxes or disks of
-- 0.15 to 0.3 m are added. Each keeps `obstacle_clearance` (0.4 m) of free floor to Roger, the
-- object, the goal, the walls and the other obstacles: they obstruct paths and partly occlude the
-- object, but can never hide it from every viewpoint (see lib/place.lua for the argument) and
-- leave room for the hands around the object.
local shapes = require("lib.shapes")
local place = require("lib.place")
local body = require("lib.body")

return {
  name = "cluttered",
  description = "Section IV: the unobstructed world plus random obstacles; circle, triangle, pentagon or spade.",

  params = body.with_params{
    shape = { default = "circle", choices = shapes.names(),
              description = "the object: circle, triangle, pentagon or spade" },
    obstacles = { default = 3, min = 0, max = 8, description = "number of obstacles" },
    obstacle_min_size = { default = 0.15, min = 0.05, description = "smallest obstacle side or diameter (m)" },
    obstacle_max_size = { default = 0.3, min = 0.05, max = 1.0, description = "largest obstacle side or diameter (m)" },
    obstacle_clearance = { default = 0.4, min = 0.0,
                           description = "free floor between an obstacle and anything else (m)" },
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
    place.obstacles(world, rng, p)
  end,
}
