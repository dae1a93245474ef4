-- Fixture: a pattern that backtracks for hours inside Lua's C matcher, at load time on line 4,
-- called as a method (the strings' metatable reaches the string table).
local subject = string.rep("a", 30000)
local found = subject:find(".-.-.-.-.-.-.-.-b")
return found
