-- Fixture: tries to read a file (line 2).
local f = io.open("/etc/passwd")  -- luacheck: ignore (the sandbox refusing io is the point)
return f
