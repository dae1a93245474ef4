-- A batch script whose evaluation asks for a shape its scenario does not have (line 7).
return {
  name = "bad",
  curriculum = "curricula/paper.lua",
  runs = { { name = "T", stage = "T", contexts = { "B2" } } },
  evaluations = {
    { name = "gen", run = "T", scenario = "cluttered", shapes = { "circle", "hexagon" } },
  },
}
