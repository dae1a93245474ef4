-- Fixture: field mistakes in world:object; `mode` selects which (a misspelt 'mas' is on line 8).
local shapes = require("lib.shapes")
return {
  params = { mode = "unknown" },
  generate = function(world, rng, params)
    world:robot{ x = 0, y = 0 }
    if params.mode == "unknown" then
      world:object{ shape = shapes.get("circle"), x = 1, y = 1, mas = 0.5 }
    elseif params.mode == "type" then
      world:object{ shape = shapes.get("circle"), x = "one", y = 1 }
    elseif params.mode == "missing" then
      world:object{ shape = shapes.get("circle"), y = 1 }
    elseif params.mode == "overlap" then
      world:object{ shape = shapes.get("circle"), x = 0.2, y = 0 }
    elseif params.mode == "huge_mass" then
      world:object{ shape = shapes.get("circle"), x = 1, y = 1, mass = 1e39 }
    elseif params.mode == "huge_viscosity" then
      world:object{ shape = shapes.get("circle"), x = 1, y = 1, angular_viscosity = 1e300 }
    elseif params.mode == "heaviest" then  -- every field at its upper bound
      world:object{ shape = shapes.get("circle"), x = 1, y = 1, mass = 1e4, friction_force = 1e6,
                    friction_torque = 1e6, viscosity = 1e4, angular_viscosity = 1e4,
                    surface_friction = 10 }
    end
  end,
}
