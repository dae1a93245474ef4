-- sorting.lua: the sorting task of the paper's Figure 1 (curricula/sorting.lua) for 2, 4 and 8
-- objects: stages SG and T as in the paper (one context each, DC2 and DC6), then the learned
-- sorting stage Sort<n>, whose actions are the learned Phi_T of trial i of T bound to each of the
-- four types (loaded, not trained again), against the hand-written sorting policy Hand<n>.
--   roger run scripts/sorting.lua --out results/sorting
-- docs/results.md (Sorting) reports its figures.
local runs = {
  { name = "SG", stage = "SG", contexts = { "DC2" } },
  { name = "T", stage = "T", contexts = { "DC6" }, skills = { Phi_SG = { run = "SG", context = "DC2" } } },
}
-- The sorting table (one row per number of objects, hand-written and learned side by side) comes
-- first; the paper-style tables follow for the learned stages only (a hand-written policy has no
-- training time).
local rows = {}
local tables = { { title = "Sorting: success against the number of objects", sorting = rows } }
-- Each trial's final evaluation in worlds of its own (final_worlds = "own": trial i's 50 from the
-- held-out seeds + 50 i), so the table's rates pool distinct worlds, and its intervals resample the
-- learned policies (or the hand-written policy's worlds) as they were drawn.
for _, n in ipairs({ 2, 4, 8 }) do
  runs[#runs + 1] = { name = "Sort" .. n, stage = "Sort" .. n, contexts = { "Learned" },
                      skills = { Phi_T = { run = "T", context = "DC6" } }, final_worlds = "own" }
  runs[#runs + 1] = { name = "Hand" .. n, stage = "Hand" .. n, contexts = { "Scripted" }, final_worlds = "own" }
  rows[#rows + 1] = { objects = n, learned = "Sort" .. n, hand = "Hand" .. n }
  tables[#tables + 1] = { title = "Sorting " .. n .. " objects: learned", run = "Sort" .. n }
end

return {
  name = "sorting",
  description = "Figure 1: sorting 2, 4 and 8 objects by type with the learned Phi_T, against a hand-written policy.",
  curriculum = "curricula/sorting.lua",
  trials = 3,
  seed = 1,
  runs = runs,
  tables = tables,
  figures = {
    { file = "sorting_curves", title = "Sorting: learning curves (8 objects)", run = "Sort8" },
  },
}
