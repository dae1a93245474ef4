-- ablation.lua: the paper's stages (lib/paper_stages.lua) learned again under the settings the
-- paper's curriculum replaced, one setting at a time, so that docs/results.md can say what each
-- choice does. scripts/ablation.lua runs it.
--
--   SG, T               the paper's settings (as curricula/paper.lua)
--   SG_q100, T_q100     initial_q = -100: an untried action looks as bad as a failed one
--   SG_runout, T_runout SG trains to the end of its budget (stop_after = 0) and yields the policy
--                       it ends with, not one that has just passed five checkpoints
--
--   roger check curricula/ablation.lua
local stages = require("lib.paper_stages").stages

local SG, T = stages{}
local SG_q100, T_q100 = stages{ suffix = "_q100", initial_q = -100 }
local SG_runout, T_runout = stages{ suffix = "_runout", sg_stop_after = 0 }

return {
  name = "ablation",
  description = "The paper's stages under the learner settings its curriculum replaced, one at a time.",
  stages = { SG, T, SG_q100, T_q100, SG_runout, T_runout },
}
