-- A batch script with a misspelt field in a run.
return {
  name = "bad",
  curriculum = "curricula/paper.lua",
  runs = {
    { name = "SG", stage = "SG",
      contxts = { "B1" } },
  },
}
