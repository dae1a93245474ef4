-- Fixture: a misspelt parameter of phi1 (line 4).
local phi1 = roger.primitive("phi1", { goal = "region" })
local phi4 = roger.primitive("phi4")  -- luacheck: ignore (the script fails before it is used)
local fast = phi1:with{ sped = 1.5 }
return { policies = { p = { action = fast, goal = roger.converged(fast), time_limit = 5 } } }
