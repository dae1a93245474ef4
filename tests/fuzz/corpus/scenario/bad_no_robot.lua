-- Fixture: the generator (line 4) forgets to place Roger.
return {
  name = "no robot",
  generate = function(world, rng, params)
    world:goal{ x = 0, y = 0 }
  end,
}
