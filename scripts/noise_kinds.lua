-- noise_kinds.lua: the kinds of noise other than white (bias, drift, delay, dropout, resolution),
-- each alone at a moderate level and all of them together (docs/results.md, Noise, "Kinds").
-- `scripts/noise_kinds.py` runs it with the scripted task's and the sort's evaluations; alone:
-- `roger run scripts/noise_kinds.lua`.
--
--   SG, T:      the paper's runs of SG/DC2 and T/DC6 without noise (trial i of T over trial i's
--               Phi_SG), whose T/DC6 policies are then evaluated, without retraining, in Table
--               III's worlds (cluttered, 3 obstacles, the four shapes) under each kind alone
--               (III_<kind>) and under all of them (III_all);
--   SG_K, T_K:  SG in B1 and DC2 (20 trials) and T in B2 and DC6 (4 trials) trained under all of
--               the kinds together (T_K's trial i over the Phi_SG of SG_K/DC2's trial i, learned
--               under them).
local KINDS = require("noise_kinds_levels")
local SHAPES = { "circle", "triangle", "pentagon", "spade" }

local evaluations, tables = {}, {
  { title = "SG trained under every kind", run = "SG_K", baseline = "B1" },
  { title = "T trained under every kind", run = "T_K", baseline = "B2" },
}
local function evaluate(name, params)
  local p = { obstacles = 3 }
  for k, v in pairs(params) do p[k] = v end
  evaluations[#evaluations + 1] = { name = "III_" .. name, run = "T", context = "DC6", scenario = "cluttered",
                                    params = p, shapes = SHAPES, episodes = 10 }
  tables[#tables + 1] = { title = "Table III's T/DC6 policies under " .. name, evaluation = "III_" .. name }
end
evaluate("none", {})
for _, kind in ipairs(KINDS.alone) do evaluate(kind.name, kind.params) end
evaluate("all", KINDS.all)

return {
  name = "noise_kinds",
  description = "Bias, drift, delay, dropout and resolution, each alone and all together: Table III's "
    .. "noise-free T/DC6 policies under them, and SG and T trained under all of them.",
  curriculum = "curricula/paper.lua",
  trials = 20,
  seed = 1,
  runs = {
    { name = "SG", stage = "SG", contexts = { "DC2" } },
    { name = "T", stage = "T", contexts = { "DC6" }, skills = { Phi_SG = { run = "SG", context = "DC2" } } },
    { name = "SG_K", stage = "SG", contexts = { "B1", "DC2" }, params = KINDS.all },
    -- 4 trials: under every kind SG/DC2 stops at its episode cap (400) and T/B2 at its own, so a
    -- trial takes several times a noise-free one.
    { name = "T_K", stage = "T", contexts = { "B2", "DC6" }, params = KINDS.all, trials = 4,
      skills = { Phi_SG = { run = "SG_K", context = "DC2" } } },
  },
  evaluations = evaluations,
  tables = tables,
}
