-- A batch script naming a context the stage does not have.
return {
  name = "bad",
  curriculum = "curricula/paper.lua",
  runs = {
    { name = "SG", stage = "SG",
      contexts = { "B1", "DC9" } },
  },
}
