-- lib/body.lua: Roger's body and eyes as scenario parameters, so that a stage, a developmental
-- context (a context's `params`) or `--set` can change them without editing the scenario
-- (docs/scenarios.md, Bodies). The defaults are the paper's Roger. The shipped scenarios take
-- these parameters through body.with_params and place Roger through lib/place.lua, which reads
-- the footprint of the body in force.
--
--   params = body.with_params{ shape = {...}, ... },     -- the paper's Roger by default, or
--   params = body.with_params({ shape = {...} }, { upper_arm = 0.6, eye_pixels = 48 }),
--   generate = function(world, rng, p)
--     local b = body.of(p)          -- { body = {...}, eyes = {...} } for world:robot
--     world:robot{ x = 1, y = 0, body = b.body, eyes = b.eyes, noise = body.noise_of(p) }
--   end
local param_defaults = require("lib.param_defaults")
local body = {}

-- The body's scenario parameters: the links, the base, the hands, the eyes and locked joints.
body.PARAMS = {
  upper_arm = { default = 0.5, min = 0.1, max = 2.0, description = "Roger's upper arm length (m)" },
  forearm = { default = 0.5, min = 0.1, max = 2.0, description = "Roger's forearm length (m)" },
  -- Above 0.08: the eyes sit at (0, +-0.08) in the base frame and must lie inside it, and eye_y
  -- is not a parameter here (world:robot takes it, for a scenario of its own).
  base_radius = { default = 0.16, min = 0.09, max = 1.0, description = "Roger's base radius (m)" },
  hand_radius = { default = 0.08, min = 0.01, max = 0.3, description = "Roger's hand radius (m)" },
  eye_pixels = { default = 128, min = 16, max = 512, description = "pixels of each eye" },
  eye_fov = { default = math.pi / 2, min = 0.1, max = 2.8, description = "each eye's full field of view (rad)" },
  locked = { default = "", list = true,
             choices = { "left_eye", "right_eye", "left_shoulder", "left_elbow", "right_shoulder", "right_elbow" },
             description = "joints held at their start angle, comma-separated (e.g. left_elbow,right_elbow)" },
  -- Noise (docs/scenarios.md, Noise): per channel, the white noise's sigma (noise_<channel>) and the
  -- other kinds (noise_<channel>_<kind>), each but the drift's tau multiplied by noise_scale. The
  -- defaults are none.
  noise_scale = { default = 1.0, min = 0, max = 100, description = "a factor on every noise level (not on tau)" },
}

-- The longest delay world:robot takes (ticks: 1 s).
local MAX_DELAY_TICKS = 50

-- Each channel's unit and largest values: sigma, bias and drift; resolution (quantum).
local CHANNELS = {
  { name = "image", max = 255, unit = "colour levels", quantum = 255, quantum_unit = "colour levels" },
  { name = "joints", max = 1, unit = "rad", quantum = 1, quantum_unit = "rad" },
  { name = "base", max = 1, unit = "m and rad", quantum = 1, quantum_unit = "m and rad" },
  { name = "touch", max = 5, unit = "a fraction of each contact force", quantum = 1000, quantum_unit = "N" },
  { name = "effort", max = 5, unit = "a fraction of each command", quantum = 1,
    quantum_unit = "m or rad of a commanded error" },
}
-- "an" before a vowel ("an image reading"), else "a".
local function article(word)
  return word:match("^[aeiou]") and "an" or "a"
end

for _, c in ipairs(CHANNELS) do
  local n = "noise_" .. c.name
  local readings = c.name == "effort" and "command" or "reading"
  body.PARAMS[n] = { default = 0.0, min = 0, max = c.max,
                     description = "white noise sigma of " .. c.name .. " (" .. c.unit .. ")" }
  body.PARAMS[n .. "_bias"] = { default = 0.0, min = 0, max = c.max,
                                description = "sigma of the " .. c.name .. " channel's bias, drawn per episode ("
                                  .. c.unit .. ")" }
  body.PARAMS[n .. "_drift"] = { default = 0.0, min = 0, max = c.max,
                                 description = "stationary sigma of the " .. c.name .. " channel's drift ("
                                   .. c.unit .. ")" }
  body.PARAMS[n .. "_tau"] = { default = 10.0, min = 0.001, max = 3600,
                               description = "correlation time of the " .. c.name .. " channel's drift (s)" }
  body.PARAMS[n .. "_delay"] = { default = 0, min = 0, max = MAX_DELAY_TICKS,
                                 description = c.name .. " " .. readings .. "s late by this many ticks" }
  body.PARAMS[n .. "_dropout"] = { default = 0.0, min = 0, max = 1,
                                   description = "probability per tick that " .. article(c.name) .. " " .. c.name
                                     .. " " .. readings .. " is lost" }
  body.PARAMS[n .. "_quantum"] = { default = 0.0, min = 0, max = c.quantum,
                                   description = c.name .. " rounded to multiples of this (" .. c.quantum_unit .. ")" }
end

-- The parameters body.noise_of reads, noise_scale first, for its check that a scenario declares
-- them (made once, not at every world).
local NOISE_NAMES = {}
for name in pairs(body.PARAMS) do
  if name:sub(1, 6) == "noise_" and name ~= "noise_scale" then NOISE_NAMES[#NOISE_NAMES + 1] = name end
end
table.sort(NOISE_NAMES)
table.insert(NOISE_NAMES, 1, "noise_scale")

-- The moderate noise level M of docs/results.md (Noise), as scenario parameters (scale it with
-- noise_scale): roger eval ... --set noise_image=10 --set noise_joints=0.01 ... --set noise_scale=2
body.MODERATE_NOISE = { noise_image = 10, noise_joints = 0.01, noise_base = 0.01, noise_touch = 0.1,
                        noise_effort = 0.1 }

-- Adds body.PARAMS to a scenario's params table and returns it. `defaults`, if given, are the
-- scenario's own defaults for some of them (a scenario of another body), which --set, a stage's
-- and a context's params still override:
--   params = body.with_params({ shape = ... }, { upper_arm = 0.6, eye_pixels = 48 }),
-- A name the scenario's params already define is refused (it would be lost without a word), as
-- are an unknown name and a bad default, at the scenario's line (lib/param_defaults.lua).
function body.with_params(params, defaults)
  local p = param_defaults.with_params(body.PARAMS, params, defaults, "body.with_params", "lib/body.lua", 2)
  return p  -- not a tail call: the errors point at the scenario, two frames up
end

-- Refuses parameters p that lack one of body.PARAMS (a scenario that calls body.of or
-- body.noise_of without declaring them through body.with_params), at the scenario's line `level`
-- frames up, saying so. Found by a probe: it failed at this file's line that read the first one.
local function require_declared(p, who, names, level)
  local missing = {}
  for _, name in ipairs(names) do
    if rawget(p, name) == nil then missing[#missing + 1] = name end
  end
  if #missing == 0 then return end
  error(string.format("%s reads the scenario parameters of lib/body.lua, and the scenario does not declare %s%s: "
                      .. "declare them with params = body.with_params({ ...its own... }) (docs/scenarios.md, "
                      .. "Bodies)", who, "'" .. missing[1] .. "'",
                      #missing > 1 and (" and " .. (#missing - 1) .. " more") or ""), level + 1)
end

local BODY_NAMES = { "upper_arm", "forearm", "base_radius", "hand_radius", "eye_pixels", "eye_fov", "locked" }

-- The world:robot fields { body = {...}, eyes = {...} } that parameters p (with body.PARAMS) ask for.
-- `above`, as for noise_of: the frames between the scenario and the caller (a library step's 1).
function body.of(p, above)
  require_declared(p, "body.of", BODY_NAMES, 2 + (above or 0))
  local locked = {}
  for name in string.gmatch(p.locked, "[^,%s]+") do locked[#locked + 1] = name end
  return {
    body = { upper_arm = p.upper_arm, forearm = p.forearm, base_radius = p.base_radius,
             hand_radius = p.hand_radius, locked = locked },
    eyes = { pixels = p.eye_pixels, fov = p.eye_fov },
  }
end

-- The world:robot field noise = {...} that parameters p (with body.PARAMS) ask for: each channel's
-- kinds, every level times noise_scale (a delay rounded to whole ticks, a dropout at most 1).
-- Each level is within its parameter's range, but noise_scale may carry it past the channel's:
-- refused here, where the two parameters that made it are known (world:robot would name only the
-- product), at the line that asked for the noise: noise_of's caller, or `above` frames above it when
-- a library step calls noise_of for the scenario (place.robot passes 1, so the error names the
-- scenario's line, not lib/place.lua's).
local function number_text(v)
  if v == math.floor(v) and math.abs(v) < 1e15 then return string.format("%d", v) end
  return string.format("%.14g", v)
end

local function scaled(p, c, param, field, hi, unit, rounded, level)
  local v = p.noise_scale * p[param]
  if rounded then v = math.floor(v + 0.5) end
  if v > hi then
    error(string.format("body.noise_of: noise.%s: field '%s' must be within [0, %s] %s, got %s (the scenario "
                        .. "parameters %s = %s times noise_scale = %s: lower either)", c.name, field,
                        number_text(hi), unit, number_text(v), param, number_text(p[param]),
                        number_text(p.noise_scale)), level)
  end
  return v
end

function body.noise_of(p, above)
  local level = 3 + (above or 0)  -- scaled, noise_of, then the line that asked
  require_declared(p, "body.noise_of", NOISE_NAMES, level - 1)
  local noise = {}
  for _, c in ipairs(CHANNELS) do
    local n = "noise_" .. c.name
    noise[c.name] = {
      sigma = scaled(p, c, n, "sigma", c.max, c.unit, false, level),
      bias = scaled(p, c, n .. "_bias", "bias", c.max, c.unit, false, level),
      drift = { sigma = scaled(p, c, n .. "_drift", "drift.sigma", c.max, c.unit, false, level), tau = p[n .. "_tau"] },
      delay = scaled(p, c, n .. "_delay", "delay", MAX_DELAY_TICKS, "ticks", true, level),
      dropout = math.min(1, p.noise_scale * p[n .. "_dropout"]),
      quantum = scaled(p, c, n .. "_quantum", "quantum", c.quantum, c.quantum_unit, false, level),
    }
  end
  return noise
end

return body
