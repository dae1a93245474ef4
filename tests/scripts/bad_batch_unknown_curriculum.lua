-- A batch script naming a curriculum that does not exist.
return {
  name = "bad",
  curriculum = "curricula/no_such_curriculum.lua",
  runs = { { name = "SG", stage = "SG", contexts = { "B1" } } },
}
