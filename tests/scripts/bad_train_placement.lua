-- Fixture: a context whose body no world of its scenario can place (a base of 1 m in the 4 x 4 m
-- arena), found at training's first episode inside scenarios/lib/place.lua.
local p = require("lib.skills").primitives()
return { stages = { roger.stage{ name = "S", scenario = "unobstructed", time_limit = 5,
  absorbing = roger.converged(p.phi0), budget = { episodes = 4 },
  contexts = { { name = "Wide", actions = { p.search, p.phi0 }, params = { base_radius = 1 } } } } } }
