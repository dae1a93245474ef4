-- A batch script that raises while it runs.
local t = nil
return { name = "bad", curriculum = "curricula/paper.lua", runs = t.runs }
