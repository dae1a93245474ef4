-- Fixture of the [faults] tests: the unobstructed world, except that some seeds' generator asks
-- string.rep for 2^62 empty strings (line 10), a C loop that allocates nothing and once ran for
-- ever between two VM instructions.
local base = require("unobstructed")

return {
  name = "faults_escape_scenario",
  params = base.params,
  generate = function(world, rng, p)
    if rng:uniform() < 0.25 then return string.rep("", 1 << 62) end
    base.generate(world, rng, p)
  end,
}
