-- Fixture of test_propose: the scenario tests/scripts/propose_beside.lua names by a path relative
-- to itself. The paper's unobstructed world under another name.
local base = require("unobstructed")

return {
  name = "propose_beside_world",
  params = base.params,
  generate = base.generate,
}
