-- An evaluation that takes a skill its policies' context does not use (test_batch_script).
return {
  curriculum = "curricula/paper.lua",
  runs = {
    { name = "SG", stage = "SG", contexts = { "DC2" } },
    { name = "T", stage = "T", contexts = { "B2" } },
  },
  evaluations = {
    { name = "e", run = "T", context = "B2", skills = { Phi_SG = { run = "SG", context = "DC2" } } },
  },
}
