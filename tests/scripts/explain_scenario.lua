-- Fixture of the [explain] tests (tests/test_trainer.cpp): the unobstructed world with a second
-- goal region (region 1) 1.3 m from the first (region 0, at the origin).
local base = require("unobstructed")

return {
  name = "explain_scenario",
  params = base.params,
  generate = function(world, rng, p)
    base.generate(world, rng, p)
    world:goal{ name = "second", x = -1.3, y = 0, radius = 0.3 }
  end,
}
