-- Fixture: a misspelt top-level key of a scenario (parms), placed at its line (5).
return {
  name = "top",
  description = "a scenario whose params are misspelt",
  parms = { n = 2 },
  generate = function(world, rng, p) world:robot{ x = 0, y = 0 } end,
}
