-- Fixture: a negative convergence threshold (line 4).
local phi0 = roger.primitive("phi0")  -- luacheck: ignore (the script fails before it is used)
local phi3 = roger.primitive("phi3",
                             { epsilon = -0.1 })
return { policies = { p = { action = phi3, goal = roger.converged(phi3), time_limit = 5 } } }
