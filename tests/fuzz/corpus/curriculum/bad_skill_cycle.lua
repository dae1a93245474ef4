-- Fixture: two skills that contain each other (A on line 5 names B, defined on line 6).
local search = roger.primitive("search")
local phi0 = roger.primitive("phi0")
local phi3 = roger.primitive("phi3")
local a = roger.sequence("A", { search, "B" })
local b = roger.sequence("B", { phi0, a, phi3 })
return { policies = { p = { action = b, goal = roger.converged(phi3), time_limit = 5 } } }
