-- Fixture: the generator calls a helper that fails on line 5 (indexing a nil field).
local helper = {}

function helper.size(spec)
  return spec.dimensions.width
end

return {
  name = "bad_runtime",
  generate = function(world, rng, params)
    world:robot{ x = 0, y = 0 }
    helper.size({})
  end,
}
