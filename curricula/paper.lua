-- paper.lua: the paper's two-stage developmental curriculum (Section III). Roger first learns
-- Phi_SG (search for the ball, approach it, grasp it), then Phi_T (transport it to the goal
-- region), each in several developmental contexts: action sets Psi that differ in how much
-- control knowledge they hand over as skills.
--
--   roger check curricula/paper.lua
--   roger train curricula/paper.lua --stage SG --context DC2 --seed 1 --out out/SG-DC2
--   roger train curricula/paper.lua --stage T --context DC6 --seed 1 --out out/T-DC6
--
-- The stages and the settings they are learned with live in lib/paper_stages.lua, shared with
-- curricula/ablation.lua, which learns the same stages under the settings the paper's replaced.
local SG, T = require("lib.paper_stages").stages{}

return {
  name = "paper",
  description = "Search-grasp (Table I: B1, DC1, DC2), then transport reusing the learned Phi_SG "
    .. "(Table II: B2, DC3, DC4, DC5, DC6).",
  stages = { SG, T },
}
