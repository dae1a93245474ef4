-- ablation.lua: what each learner setting of the paper's curriculum does, measured. The paper's
-- stages are learned under the paper's settings and under the settings they replaced, one at a
-- time (curricula/ablation.lua); docs/results.md ("Ablations") reads the tables this writes.
--   roger run scripts/ablation.lua                 # 50 trials per context, as the paper's
--   roger run scripts/ablation.lua --trials 10     # a look in a few minutes
-- A table of one run; with `skill`, also the share of the decisions its policies give the skill
-- among the actions it subsumes (the paper's usage analysis).
local function table_for(run, baseline, what, usage)
  return { title = run .. ": " .. what, run = run, baseline = baseline, usage = usage }
end
local function sg_usage() return { { context = "DC1", skill = "Phi7", subsumes = { "phi1", "phi4 <| phi2" } } } end
local function t_usage(skill) return { { context = "DC3", skill = skill, subsumes = { "phi3", "Phi6", "Phi7" } } } end

return {
  name = "ablation",
  description = "The paper's stages under the learner settings its curriculum replaced, one at a time.",
  curriculum = "curricula/ablation.lua",
  trials = 50,
  seed = 1,
  runs = {
    { name = "SG", stage = "SG", contexts = { "B1", "DC1", "DC2" } },
    { name = "T", stage = "T", contexts = { "B2", "DC3", "DC4", "DC5", "DC6" },
      skills = { Phi_SG = { run = "SG", context = "DC2" } } },
    { name = "SG_q100", stage = "SG_q100", contexts = { "B1", "DC1", "DC2" } },
    { name = "T_q100", stage = "T_q100", contexts = { "B2", "DC3", "DC4", "DC5", "DC6" },
      skills = { Phi_SG_q100 = { run = "SG_q100", context = "DC2" } } },
    { name = "SG_runout", stage = "SG_runout", contexts = { "DC1", "DC2" } },
    { name = "T_runout", stage = "T_runout", contexts = { "DC6" },
      skills = { Phi_SG_runout = { run = "SG_runout", context = "DC2" } } },
  },
  tables = {
    table_for("SG", "B1", "the paper's settings (initial_q = 0, stop after 5 passing checkpoints)", sg_usage()),
    table_for("T", "B2", "the paper's settings", t_usage("Phi_SG")),
    table_for("SG_q100", "B1", "initial_q = -100", sg_usage()),
    table_for("T_q100", "B2", "initial_q = -100", t_usage("Phi_SG_q100")),
    table_for("SG_runout", "DC1", "SG trained to the end of its budget", sg_usage()),
    table_for("T_runout", "DC6", "on the Phi_SG of SG trained to the end of its budget"),
  },
}
