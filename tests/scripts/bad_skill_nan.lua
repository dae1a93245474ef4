-- Fixture: a gain computed as 0/0, which is NaN (line 4).
local zero = 0
local phi0 = roger.primitive("phi0")  -- luacheck: ignore (the script fails before it is used)
local phi2 = roger.primitive("phi2", { gain = zero / zero })
return { policies = { p = { action = phi2, goal = roger.converged(phi2), time_limit = 5 } } }
