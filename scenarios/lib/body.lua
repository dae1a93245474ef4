-- lib/body.lua: Roger's body and eyes as scenario parameters, so that a stage, a developmental
-- context (a context's `params`) or `--set` can change them without editing the scenario
-- (docs/scenarios.md, Bodies). The defaults are the paper's Roger. The shipped scenarios take
-- these parameters through body.with_params and place Roger through lib/place.lua, which reads
-- the footprint of the body in force.
--
--   params = body.with_params{ shape = {...}, ... },
--   generate = function(world, rng, p)
--     local b = body.of(p)          -- { body = {...}, eyes = {...} } for world:robot
--     world:robot{ x = 1, y = 0, body = b.body, eyes = b.eyes, noise = body.noise_of(p) }
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
  -- Noise (docs/scenarios.md, Noise): sigmas, each multiplied by noise_scale. The defaults are none.
  noise_image = { default = 0.0, min = 0, max = 255, description = "sigma of each pixel's colour channels (levels)" },
  noise_joints = { default = 0.0, min = 0, max = 1, description = "sigma of each joint angle read (rad)" },
  noise_base = { default = 0.0, min = 0, max = 1, description = "sigma of the base pose read (m, rad)" },
  noise_touch = { default = 0.0, min = 0, max = 5, description = "sigma of each contact force (a fraction of it)" },
  noise_effort = { default = 0.0, min = 0, max = 5, description = "sigma of each command (a fraction of it)" },
  noise_scale = { default = 1.0, min = 0, max = 100, description = "a factor on every noise sigma" },
}

-- The moderate noise level M of docs/results.md (Noise), as scenario parameters (scale it with
-- noise_scale): roger eval ... --set noise_image=10 --set noise_joints=0.01 ... --set noise_scale=2
body.MODERATE_NOISE = { noise_image = 10, noise_joints = 0.01, noise_base = 0.01, noise_touch = 0.1,
                        noise_effort = 0.1 }

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

-- The world:robot field noise = {...} that parameters p (with body.PARAMS) ask for: each sigma
-- times noise_scale.
function body.noise_of(p)
  local k = p.noise_scale
  return { image = k * p.noise_image, joints = k * p.noise_joints, base = k * p.noise_base,
           touch = k * p.noise_touch, effort = k * p.noise_effort }
end

return body
