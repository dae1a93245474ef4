-- A batch script whose name waits on an __index chain that loops (line 4): each read follows 2000
-- links in C, one VM instruction, stopped by the processor-time budget.
local mt, name = {}, nil mt.__index = mt setmetatable(mt, mt)
while not name do pcall(function() return mt.name end) end
return { name = name, curriculum = "curricula/paper.lua", runs = {} }
