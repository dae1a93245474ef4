-- Fixture: subject_to with a number as the superior (line 4).
local phi4 = roger.primitive("phi4")
local phi5 = roger.primitive("phi5")  -- luacheck: ignore (the script fails before it is used)
local hold = phi4:subject_to(5)
return { policies = { p = { action = hold, goal = roger.converged(hold), time_limit = 5 } } }
