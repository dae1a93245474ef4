-- lib/body.lua: Roger's body and eyes as scenario parameters, so that a stage, a developmental
-- context (a context's `params`) or `--set` can change them without editing the scenario
-- (docs/scenarios.md, Bodies). The defaults are the paper's Roger. The shipped scenarios take
-- these parameters through body.with_params and place Roger through lib/place.lua, which reads
-- the footprint of the body in force.
--
--   params = body.with_params{ shape = {...}, ... },
--   generate = function(world, rng, p)
--     local b = body.of(p)          -- { body = {...}, eyes = {...} } for world:robot
--     world:robot{ x = 1, y = 0, body = b.body, eyes = b.eyes }
--   end
local body = {}

-- The body's scenario parameters: the links, the base, the hands, the eyes and locked joints.
body.PARAMS = {
  upper_arm = { default = 0.5, min = 0.1, max = 2.0, description = "Roger's upper arm length (m)" },
  forearm = { default = 0.5, min = 0.1, max = 2.0, description = "Roger's forearm length (m)" },
  base_radius = { default = 0.16, min = 0.05, max = 1.0, description = "Roger's base radius (m)" },
  hand_radius = { default = 0.08, min = 0.01, max = 0.3, description = "Roger's hand radius (m)" },
  eye_pixels = { default = 128, min = 16, max = 512, description = "pixels of each eye" },
  eye_fov = { default = math.pi / 2, min = 0.1, max = 2.8, description = "each eye's full field of view (rad)" },
  locked = { default = "",
             description = "joints held at their start angle, comma-separated (e.g. left_elbow,right_elbow)" },
}

-- Adds body.PARAMS to a scenario's params table and returns it.
function body.with_params(params)
  for name, spec in pairs(body.PARAMS) do params[name] = spec end
  return params
end

-- The world:robot fields { body = {...}, eyes = {...} } that parameters p (with body.PARAMS) ask for.
function body.of(p)
  local locked = {}
  for name in string.gmatch(p.locked, "[^,%s]+") do locked[#locked + 1] = name end
  return {
    body = { upper_arm = p.upper_arm, forearm = p.forearm, base_radius = p.base_radius,
             hand_radius = p.hand_radius, locked = locked },
    eyes = { pixels = p.eye_pixels, fov = p.eye_fov },
  }
end

return body
