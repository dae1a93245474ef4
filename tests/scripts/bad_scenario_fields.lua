-- Fixture: a parameter's field misspelt (defualt) in a scenario's returned table, which carries
-- no lines: the error is placed where the parameter is written (line 6), not at the file alone.
return {
  name = "fields",
  params = {
    n = { defualt = 2, min = 0, max = 4, description = "objects" },
  },
  generate = function(world, rng, p) world:robot{ x = 0, y = 0 } end,
}
