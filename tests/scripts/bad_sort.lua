-- Fixture: table.sort over objects whose __lt is a C function, so no comparison runs a VM
-- instruction, again and again on line 6.
local mt = { __lt = rawequal }
local t = {}
for i = 1, 100000 do t[i] = setmetatable({}, mt) end
while true do table.sort(t) end
