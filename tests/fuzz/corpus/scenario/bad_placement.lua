-- Fixture: placements that cannot be satisfied. `mode` selects which.
return {
  params = { mode = { default = "walls", choices = { "walls", "robot" } } },
  generate = function(world, rng, params)
    world:robot{ x = 0, y = 0 }
    if params.mode == "walls" then
      -- A 2.5 m wall margin leaves nothing of a 4 x 4 m arena (line 8).
      world:sample_position{ name = "ball", radius = 0.2, wall_margin = 2.5 }
    else
      -- Nothing in the arena is 10 m from Roger (line 11).
      world:sample_position{ name = "ball", radius = 0.2, robot_distance = 10, tries = 500 }
    end
  end,
}
