-- Fixture: string.rep asked for 2^62 empty strings on line 3: a C loop that allocates nothing and
-- never reaches a VM instruction.
local s = string.rep("", 1 << 62)
return s
