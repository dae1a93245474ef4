---@meta
-- docs/api/sandbox.lua: the standard library as every roger script has it (docs/scenarios.md, The
-- sandbox): Lua 5.4's base, math, string, table, utf8 and coroutine libraries, with `require`
-- returning a standard library by its name and finding dotted module names in the script's
-- folder and the project's scenarios/, curricula/ and scripts/, and `print` writing to standard
-- error. The io, os and package libraries and debug's functions but `debug.traceback` are
-- stand-ins (.luarc.json disables them for the editor; touching one raises an error that says
-- the script is sandboxed), and neither is anything marked deprecated below: an editor strikes
-- it through, the linter (.luacheckrc) reports it, and tests/test_lua_sandbox.cpp checks that
-- the sandbox indeed refuses it. `setmetatable` refuses a metatable with a `__gc` field (a
-- finalizer would run outside the instruction budget), and the budget counts the work of the
-- library's C functions too (docs/scenarios.md).

---Visits the keys of `t` and their values. In roger's sandbox the order is the same in every run
---(Lua's follows string hashes seeded per run): numbers by value, strings byte by byte, false,
---true, then keys of other types in Lua's order. A table with __pairs gets its metamethod.
---@generic K, V
---@param t table<K, V>
---@return fun(table: table<K, V>, index?: K): K, V
---@return table<K, V>
---@return nil
function pairs(t) end

---@deprecated Not in roger's sandbox (it reads any file): use require("dotted.name").
function dofile(filename) end

---@deprecated Not in roger's sandbox (it reads any file): use require("dotted.name").
function loadfile(filename, mode, env) end

---@deprecated Not in roger's sandbox: bytecode is refused, in and out.
function string.dump(f, strip) end

---@deprecated Not in roger's sandbox: draw from the rng a scenario's generate or a teacher function
---receives (rng:uniform, rng:int, ...), so a run is reproducible from its seed; a reward or
---absorbing function gets none.
function math.random(m, n) end

---@deprecated Not in roger's sandbox: the rng your function receives is seeded from the world's
---seed.
function math.randomseed(x, y) end
