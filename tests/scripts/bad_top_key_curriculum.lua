-- Fixture: a curriculum whose `stages` is misspelt. roger check once took a file without any
-- kind's key for a scenario, and blamed curricula/lib/skills.lua for the missing roger.primitive.
local p = require("lib.skills").primitives()
return { stagez = { roger.stage{ name = "S", time_limit = 2, scenario = "unobstructed", budget = { episodes = 5 },
  absorbing = roger.converged(p.phi0), contexts = { A = { actions = { p.phi0 } } } } } }
