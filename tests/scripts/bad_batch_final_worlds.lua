-- A batch script whose run asks for final worlds that are neither each trial's own nor shared.
return {
  name = "bad",
  curriculum = "curricula/paper.lua",
  runs = {
    { name = "SG", stage = "SG", contexts = { "DC2" },
      final_worlds = "mine" },
  },
}
