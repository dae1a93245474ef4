-- noise.lua: the paper's results under seeded sensor and actuator noise (docs/results.md, "Noise").
-- `roger run scripts/noise.lua`.
--
--   SG, T:        the paper's runs without noise (the same trials as scripts/paper.lua: same
--                 curriculum, same seeds), whose T/DC6 policies Table III evaluates;
--   SG_M, T_M:    every context of Tables I and II trained under the moderate noise M, T_M over
--                 the Phi_SG of SG_M/DC2 (the paper's footnote 3, under the same noise);
--   III_x<scale>: Table III's noise-free T/DC6 policies, without retraining, under M scaled by
--                 0, 0.5, 1, 2, 4 and 8 (scale 0 is the paper's Table III);
--   III_M_x1:     the T/DC6 policies trained under M, run under M.
--
-- M = { image = 10 colour levels, joints = 0.01 rad, base = 0.01 m and rad, touch = 0.1, effort =
-- 0.1 } through the scenario parameters of scenarios/lib/body.lua (noise_scale multiplies them).
-- Success is judged on the true world (docs/control.md, Noise).
local M = { noise_image = 10, noise_joints = 0.01, noise_base = 0.01, noise_touch = 0.1, noise_effort = 0.1 }
local SHAPES = { "circle", "triangle", "pentagon", "spade" }

-- M scaled by `scale`, with `extra` parameters.
local function noise(scale, extra)
  local params = { noise_scale = scale }
  for k, v in pairs(M) do params[k] = v end
  for k, v in pairs(extra or {}) do params[k] = v end
  return params
end

-- "0", "0.5", "1", ... as a name part ("0_5" for 0.5).
local function scale_name(scale)
  return (tostring(scale):gsub("%.0$", ""):gsub("%.", "_"))
end

local SG_USAGE = { { context = "DC1", skill = "Phi7", subsumes = { "phi1", "phi4 <| phi2" } } }
local T_USAGE = { { context = "DC3", skill = "Phi_SG", subsumes = { "phi3", "Phi6", "Phi7" } } }

local evaluations, tables = {}, {
  { title = "Table I: Phi_SG learning, no noise", run = "SG", baseline = "B1", usage = SG_USAGE },
  { title = "Table I under M: Phi_SG learning", run = "SG_M", baseline = "B1", usage = SG_USAGE },
  { title = "Table II: Phi_T learning, no noise", run = "T", baseline = "B2", usage = T_USAGE },
  { title = "Table II under M: Phi_T learning", run = "T_M", baseline = "B2", usage = T_USAGE },
}
for _, scale in ipairs({ 0, 0.5, 1, 2, 4, 8 }) do
  local name = "III_x" .. scale_name(scale)
  evaluations[#evaluations + 1] = { name = name, run = "T", context = "DC6", scenario = "cluttered",
                                    params = noise(scale, { obstacles = 3 }), shapes = SHAPES, episodes = 50 }
  tables[#tables + 1] = { title = "Table III under " .. scale .. " M: the noise-free T/DC6 policies",
                          evaluation = name }
end
evaluations[#evaluations + 1] = { name = "III_M_x1", run = "T_M", context = "DC6", scenario = "cluttered",
                                  params = noise(1, { obstacles = 3 }), shapes = SHAPES, episodes = 50 }
tables[#tables + 1] = { title = "Table III under M: the T/DC6 policies trained under M", evaluation = "III_M_x1" }

return {
  name = "noise",
  description = "Tables I-III under seeded sensor and actuator noise: training under M, and the "
    .. "noise-free policies under M scaled by 0 to 8.",
  curriculum = "curricula/paper.lua",
  trials = 50,
  seed = 1,
  runs = {
    { name = "SG", stage = "SG", contexts = { "B1", "DC1", "DC2" } },
    { name = "T", stage = "T", contexts = { "B2", "DC3", "DC4", "DC5", "DC6" },
      skills = { Phi_SG = { run = "SG", context = "DC2" } } },
    { name = "SG_M", stage = "SG", contexts = { "B1", "DC1", "DC2" }, params = noise(1) },
    { name = "T_M", stage = "T", contexts = { "B2", "DC3", "DC4", "DC5", "DC6" }, params = noise(1),
      skills = { Phi_SG = { run = "SG_M", context = "DC2" } } },
  },
  evaluations = evaluations,
  tables = tables,
  figures = {
    { file = "curves_SG_M", title = "Phi_SG learning curves under M", run = "SG_M" },
    { file = "curves_T_M", title = "Phi_T learning curves under M", run = "T_M", log_x = true },
  },
}
