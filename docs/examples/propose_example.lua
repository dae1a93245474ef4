-- propose_example.lua: a curriculum written by hand with lib.propose, the way roger propose
-- writes its proposals: learn to reach phi1's CONV (the approach) first, then search-grasp with
-- that skill and phi3. roger check docs/examples/propose_example.lua
local propose = require("lib.propose")
local task = propose.task("paper", "SG")   -- stage SG of curricula/paper.lua
local A = propose.actions(task, "B1")      -- context B1's actions by name

local approach = propose.stage(task, {
  name = "SG_to_phi1",
  goal = A["phi1"],                        -- absorbing when phi1 is CONV
  contexts = { { name = "P", actions = { A["Phi6"], A["phi1"] } } },
  skill = { name = "Phi_approach", context = "P" },
})

return {
  name = "propose_example",
  stages = {
    approach,
    propose.stage(task, {                  -- the task itself, with new contexts
      name = "SG",
      contexts = { { name = "P", actions = { roger.learned("Phi_approach"), A["phi3"] } } },
    }),
  },
}
