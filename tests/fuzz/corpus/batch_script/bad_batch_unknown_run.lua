-- A batch script whose stage T takes Phi_SG from a run that does not exist.
return {
  name = "bad",
  curriculum = "curricula/paper.lua",
  runs = {
    { name = "SG", stage = "SG", contexts = { "DC2" } },
    { name = "T", stage = "T", contexts = { "DC6" },
      skills = { Phi_SG = { run = "SGX", context = "DC2" } } },
  },
}
