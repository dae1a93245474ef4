-- Fixture: a missing 'then' after line 4, reported on line 5 where Lua meets the next token.
return {
  generate = function(world, rng, params)
    if params.x == 1
      world:robot{ x = 0, y = 0 }
    end
  end,
}
