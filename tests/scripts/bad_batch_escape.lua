-- A batch script whose name is built with a backtracking gsub on line 3.
local name = string.rep("a", 30000)
name = name:gsub("a*a*a*a*a*a*a*b", "")
return { name = name, curriculum = "curricula/paper.lua", runs = {} }
