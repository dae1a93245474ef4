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
    { name = "SG_stop5", stage = "SG_stop5", contexts = { "DC2" } },
    { name = "T_stop5", stage = "T_stop5", contexts = { "DC4", "DC5", "DC6" },
      skills = { Phi_SG_stop5 = { run = "SG_stop5", context = "DC2" } } },
    { name = "SG_anypass", stage = "SG_anypass", contexts = { "DC2" } },
    { name = "T_anypass", stage = "T_anypass", contexts = { "DC4", "DC6" },
      skills = { Phi_SG_anypass = { run = "SG_anypass", context = "DC2" } } },
    { name = "SG_ref", stage = "SG_ref", contexts = { "B1", "DC1", "DC2" } },
    { name = "T_ref", stage = "T_ref", contexts = { "B2", "DC3", "DC4", "DC6" },
      skills = { Phi_SG_ref = { run = "SG_ref", context = "DC2" } } },
  },
  tables = {
    table_for("SG", "B1", "the paper's settings (initial_q = 0, SG trained to the end of its budget)", sg_usage()),
    table_for("T", "B2", "the paper's settings", t_usage("Phi_SG")),
    table_for("SG_q100", "B1", "initial_q = -100", sg_usage()),
    table_for("T_q100", "B2", "initial_q = -100", t_usage("Phi_SG_q100")),
    table_for("SG_stop5", "DC2", "SG stopped after 5 passing checkpoints of one greedy policy"),
    table_for("T_stop5", "DC4", "on the Phi_SG of SG_stop5"),
    table_for("SG_anypass", "DC2",
              "SG stopped after any 5 passing checkpoints, the policy changed between them or not"),
    table_for("T_anypass", "DC4", "on the Phi_SG of SG_anypass"),
    table_for("SG_ref", "B1", "only actions with a reference chosen (referenced_only)", sg_usage()),
    table_for("T_ref", "B2", "only actions with a reference chosen", t_usage("Phi_SG_ref")),
  },
}
