-- Fixture of the linter (CTest lua_lint_sandbox): what the sandbox removes from the standard
-- libraries (docs/api/sandbox.lua's deprecated members) is reported, as loadfile is.
local a = math.random(3)
local d = string.dump(print)
local f = loadfile("x.lua")
local g = math.floor(2.5)
return a, d, f, g
