-- Fixture: grows a table until memory runs out.
local t = {}  -- luacheck: ignore (filled, never read: only memory matters)
local i = 0
while true do
  i = i + 1
  t[i] = { i, tostring(i) }
end
