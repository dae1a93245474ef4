-- Fixture: a runaway loop at load time, on line 3.
local n = 0
while true do n = n + 1 end
