-- sort_by_hand.lua: one hand-written policy that sorts whatever a sorting world holds, 1 to 12
-- objects of any mix, with or without obstacles (the paper's Figure 1, written by hand):
--
--   roger eval curricula/sort_by_hand.lua --policy sort --set objects=8 --episodes 20
--   roger eval curricula/sort_by_hand.lua --policy sort --set objects=8 --set obstacles=2
--   roger render curricula/sort_by_hand.lua --policy sort --set objects=8 --seed 3 --out out/sort8
--
-- It is built from the same bound transport as the learned sorting stage (lib/sorting.lua): the
-- hand-written Phi_T of curricula/scripted.lua bound to each of the four types, run type by type,
-- each again and again until its search has looked everywhere and seen none of its type left.
-- Success is the world's judgement (roger.sorted): every object lies in the region of its colour
-- and is not held, however many there are.
local skills = require("lib.skills")
local sorting = require("lib.sorting")

-- The carrying navigator of sorting (lib/sorting.lua): the object ends inside its region.
local p = skills.primitives({ carry = sorting.CARRY })
local transport = skills.transport(p)
local carry = roger.sequence("carry", {
  roger.sequence("search-grasp", { skills.Phi6(p), skills.Phi7(p), p.phi3 }), transport })
-- Transport converges only once the object is delivered (phi1 itself CONV, the grasp held).
local Phi_T = roger.policy("Phi_T", {
  actions = { carry }, table = { ["*"] = carry }, done = skills.transported(transport) })

local sort = sorting.by_hand(sorting.moves(Phi_T))

return {
  name = "sort_by_hand",
  description = "Sort every object of a sorting world into the region of its type, by hand.",
  policies = {
    sort = {
      action = sort,
      goal = roger.sorted(),
      time_limit = { per_object = 30 },
      scenario = "sorting",
      description = "carry every object into the region of its colour, type by type",
    },
  },
}
