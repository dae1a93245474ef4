-- noise_kinds_levels.lua: the moderate levels of the kinds of noise other than white, for
-- scripts/noise_kinds.lua and scripts/noise_kinds.py (scenario parameters of scenarios/lib/body.lua).
local alone = {
  { name = "joints_bias", params = { noise_joints_bias = 0.02 } },                       -- rad
  { name = "joints_drift", params = { noise_joints_drift = 0.01, noise_joints_tau = 10 } }, -- rad, s
  { name = "joints_delay", params = { noise_joints_delay = 2 } },                         -- ticks
  { name = "joints_dropout", params = { noise_joints_dropout = 0.05 } },
  { name = "joints_quantum", params = { noise_joints_quantum = 0.005 } },                 -- rad
  { name = "base_bias", params = { noise_base_bias = 0.02 } },                            -- m and rad
  { name = "base_drift", params = { noise_base_drift = 0.01, noise_base_tau = 10 } },
  { name = "image_bias", params = { noise_image_bias = 10 } },                            -- colour levels
  { name = "image_drift", params = { noise_image_drift = 10, noise_image_tau = 10 } },
  { name = "image_delay", params = { noise_image_delay = 2 } },
  { name = "image_dropout", params = { noise_image_dropout = 0.05 } },
  { name = "image_quantum", params = { noise_image_quantum = 16 } },                      -- levels
  { name = "touch_dropout", params = { noise_touch_dropout = 0.05 } },
  { name = "effort_delay", params = { noise_effort_delay = 2 } },
  { name = "effort_dropout", params = { noise_effort_dropout = 0.05 } },
}
local all = {}
for _, kind in ipairs(alone) do
  for k, v in pairs(kind.params) do all[k] = v end
end
return { alone = alone, all = all }
