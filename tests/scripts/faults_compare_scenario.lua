-- Fixture of the [faults] tests: the unobstructed world, except that some seeds' generator
-- compares two equal 4 MB strings for ever (line 11): each comparison one VM instruction of
-- 4 MB of C work, stopped by the processor-time budget.
local base = require("unobstructed")

return {
  name = "faults_compare_scenario",
  params = base.params,
  generate = function(world, rng, p)
    if rng:uniform() < 0.25 then
      local a, b = string.rep("a", 4000000), string.rep("a", 3999999) .. "a" while true do local _ = a == b end
    end
    base.generate(world, rng, p)
  end,
}
