-- Fixture: an unknown primitive kind (line 3).
local search = roger.primitive("search")
local grab = roger.primitive("phi9", { epsilon = 0.1 })  -- luacheck: ignore (the script fails before it is used)
return { policies = { p = { action = search, goal = roger.converged(search), time_limit = 5 } } }
