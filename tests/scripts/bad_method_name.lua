-- A misspelt method of the world and of rng (tests/test_scenario.cpp): each an error at its line
-- naming the methods, not "attempt to call a nil value".
return {
  generate = function(world, rng, params)
    world:robot{ x = 0, y = 0 }
    if params.which == "rng" then
      rng:integre(0, 3)
    end
    world:obstcle{ x = 1, y = 1 }
  end,
  params = { which = { default = "world", choices = { "world", "rng" } } },
}
