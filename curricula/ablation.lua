-- ablation.lua: the paper's stages (lib/paper_stages.lua) learned again under the settings the
-- paper's curriculum replaced, one setting at a time, so that docs/results.md can say what each
-- choice does. scripts/ablation.lua runs it.
--
--   SG, T               the paper's settings (as curricula/paper.lua)
--   SG_q100, T_q100     initial_q = -100: an untried action looks as bad as a failed one
--   SG_stop5, T_stop5   SG stops after 5 passing checkpoints of one greedy policy (stop_after =
--                       5), as T does, instead of training to the end of its budget
--   SG_anypass, T_anypass  SG stops after any 5 consecutive passing checkpoints, the greedy policy
--                       changed between them or not (stop_after = 5, settle = false)
--   SG_ref, T_ref       referenced_only: an action whose gamma is NOREF is never chosen
--
--   roger check curricula/ablation.lua
local stages = require("lib.paper_stages").stages

local SG, T = stages{}
local SG_q100, T_q100 = stages{ suffix = "_q100", initial_q = -100 }
local SG_stop5, T_stop5 = stages{ suffix = "_stop5", sg_stop_after = 5 }
local SG_anypass, T_anypass = stages{ suffix = "_anypass", sg_stop_after = 5, settle = false }
local SG_ref, T_ref = stages{ suffix = "_ref", referenced_only = true }

return {
  name = "ablation",
  description = "The paper's stages under the learner settings its curriculum replaced, one at a time.",
  stages = { SG, T, SG_q100, T_q100, SG_stop5, T_stop5, SG_anypass, T_anypass, SG_ref, T_ref },
}
