-- Fixture: a degenerate polygon (three collinear points) made on line 4.
return {
  generate = function(world, rng, params)
    local flat = roger.shape{ name = "flat", polygons = { { { 0, 0 }, { 0.1, 0 }, { 0.2, 0 } } } }
    world:robot{ x = 0, y = 0 }
    world:object{ shape = flat, x = 1, y = 1 }
  end,
}
