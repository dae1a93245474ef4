-- Fixture: a skill script whose `policies` is misspelt (see bad_top_key_curriculum.lua).
local p = require("lib.skills").primitives()
return { policy = { t = { action = p.phi0, goal = roger.converged(p.phi0), time_limit = 5 } } }
