-- A batch script naming a stage the curriculum does not have.
return {
  name = "bad",
  curriculum = "curricula/paper.lua",
  runs = { { name = "X", stage = "Transport" } },
}
