-- Fixture: a number parameter given as a string (line 3).
local phi1 = roger.primitive("phi1")  -- luacheck: ignore (the script fails before it is used)
local carry = roger.primitive("phi1", { goal = "region", speed = "fast" })
return { policies = { p = { action = carry, goal = roger.converged(carry), time_limit = 5 } } }
