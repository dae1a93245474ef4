-- A batch script whose T contexts use Phi_SG without saying which run trains it.
return {
  name = "bad",
  curriculum = "curricula/paper.lua",
  runs = {
    { name = "SG", stage = "SG", contexts = { "DC2" } },
    { name = "T", stage = "T", contexts = { "DC6" } },
  },
}
