-- Fixture: a misspelt primitive at the end of an action list (p.phi33 for p.phi3). Lua drops a
-- trailing nil from a table, so without lib/skills' strict table the stage would train on one
-- action fewer, silently.
local p = require("lib.skills").primitives()
return { stages = { roger.stage{ name = "S", time_limit = 2, scenario = "unobstructed",
  absorbing = roger.converged(p.phi0),
  contexts = { A = { actions = { p.phi0, p.phi2, p.phi33 } } } } } }
