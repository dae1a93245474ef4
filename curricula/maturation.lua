-- maturation.lua: maturational curricula. Development restricts the body or the senses early and
-- restores them later: Phi_SG is learned with coarse eyes (32 pixels over 60 degrees, stage
-- SG_coarse) or with both eyes frozen straight ahead (SG_frozen), then the transport (T_coarse,
-- T_frozen) is learned with the full body, reusing that Phi_SG. Each is the paper's curriculum
-- (lib/paper_stages.lua) in every other respect; docs/results.md ("Transfer across bodies", d)
-- compares their time-to-threshold with the paper's DC6.
--
-- A context restricts the body through its scenario `params` (docs/curricula.md, Contexts that
-- change the body): the SG contexts here carry eye_pixels, eye_fov or locked, and the T contexts
-- none, so T's worlds have the full Roger.
--
--   roger check curricula/maturation.lua
--   roger train curricula/maturation.lua --stage T_coarse --context DC6 --seed 1 --out out/T-coarse
local paper = require("lib.paper_stages")

-- The paper's stages (SG, T) with the full body, to compare against (scripts/transfer.lua).
local SG, T = paper.stages{}
local SG_coarse, T_coarse = paper.stages{ suffix = "_coarse", sg_params = { eye_pixels = 32, eye_fov = 1.0472 } }
local SG_frozen, T_frozen = paper.stages{ suffix = "_frozen", sg_params = { locked = "left_eye,right_eye" } }

return {
  name = "maturation",
  description = "The paper's stages, and Phi_SG learned with coarse or frozen eyes, "
    .. "then the transport with the full body.",
  stages = { SG, T, SG_coarse, T_coarse, SG_frozen, T_frozen },
}
