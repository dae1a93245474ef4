-- The smallest transfer experiment (test_batch): T/DC6 of trial 0 over the Phi_SG it embeds, and
-- over a Phi_SG learned on a wider base (scripts/transfer.lua, docs/batch.md).
return {
  curriculum = "curricula/paper.lua",
  trials = 1,
  runs = {
    { name = "SG", stage = "SG", contexts = { "DC2" } },
    { name = "T", stage = "T", contexts = { "DC6" }, skills = { Phi_SG = { run = "SG", context = "DC2" } } },
    { name = "SG_wide", stage = "SG", contexts = { "DC2" }, params = { base_radius = 0.24 } },
  },
  evaluations = {
    { name = "as_learned", run = "T", context = "DC6", params = { base_radius = 0.24 }, episodes = 10 },
    { name = "retrained", run = "T", context = "DC6", params = { base_radius = 0.24 }, episodes = 10,
      skills = { Phi_SG = { run = "SG_wide", context = "DC2" } } },
  },
}
