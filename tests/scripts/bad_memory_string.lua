-- Fixture: asks for a 1 GiB string (under Lua's own 2 GiB string limit, over the memory cap).
local s = string.rep("x", 2^30)
return #s
