-- Fixture: a skill that contains itself by name (defined on line 4).
local search = roger.primitive("search")
local phi0 = roger.primitive("phi0")
local looping = roger.sequence("Looping", { search, phi0, "Looping" })
return { policies = { p = { action = looping, goal = roger.converged(phi0), time_limit = 5 } } }
