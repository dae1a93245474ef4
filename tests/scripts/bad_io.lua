-- Fixture: tries to read a file (line 2).
local f = io.open("/etc/passwd")
return f
