-- A batch script whose name waits on an __index chain that loops (line 4): each read follows 2000
-- links in C, one VM instruction, stopped by the processor-time budget.
local mt = {} mt.__index = mt setmetatable(mt, mt)
while true do pcall(function() return mt.name end) end
return { name = "never", curriculum = "curricula/paper.lua", runs = {} }
