-- Fixture of the [faults] tests: the unobstructed world, except that some seeds draw a world the
-- generator refuses (line 9), as a scenario with a rare bug would.
local base = require("unobstructed")

return {
  name = "faults_scenario",
  params = base.params,
  generate = function(world, rng, p)
    if rng:uniform() < 0.25 then error("an unlucky world") end
    base.generate(world, rng, p)
  end,
}
