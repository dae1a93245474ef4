-- Fixture of the static checks (tests/test_cli.cpp, CTest lua_lint_finds): a misspelt roger member
-- on line 5 and an undefined global on line 6, which both `roger check` and luacheck report.
local phi3 = roger.primitive("phi3")
local grab = roger.sequence("grab", { "phi0", phi3 })
local slow = roger.sequnce("slow grab", { grab })
local goal = roger.converged(phi)
return { policies = { grab = { action = slow, goal = goal, time_limit = 5 } } }
