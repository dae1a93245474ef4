-- A batch script whose evaluation asks for worlds that are neither each policy's own nor shared.
return {
  name = "bad",
  curriculum = "curricula/paper.lua",
  runs = { { name = "SG", stage = "SG", contexts = { "DC2" } } },
  evaluations = {
    { name = "gen", run = "SG",
      worlds = "same" },
  },
}
