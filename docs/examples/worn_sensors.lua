-- A ball seen by worn sensors: joint encoders with a calibration bias, a slow drift, two ticks of
-- latency, lost readings and a 0.005 rad resolution; eyes with colour noise and dropped frames.
local shapes = require("lib.shapes")

return {
  name = "worn_sensors",
  generate = function(world, rng, params)
    world:goal{ name = "goal", x = 1.2, y = 1.2, radius = 0.3 }
    world:robot{ x = -1, y = 0, heading = 0, noise = {
      joints = { sigma = 0.005, bias = 0.02, drift = { sigma = 0.01, tau = 10 }, delay = 2,
                 dropout = 0.05, quantum = 0.005 },
      image = { sigma = 10, bias = 5, dropout = 0.02 },
    } }
    local x, y = world:sample_position{ name = "ball", radius = 0.2, robot_distance = 1.4 }
    world:object{ name = "ball", shape = shapes.get("circle"), x = x, y = y }
  end,
}
