-- .luacheckrc: luacheck over every shipped Lua file (`luacheck .` here; CTest runs it as
-- `lua_lint`, docs/authoring.md). No global is listed by hand: the roger.* API and what the
-- sandbox takes away are read from docs/api/*.lua and .luarc.json, the description editors read,
-- which tests/test_lua_sandbox.cpp keeps equal to what the engine registers.
std = "lua54"
-- Callbacks have fixed argument lists (state, time, world): naming the unused ones documents them.
unused_args = false
exclude_files = {
  "build*/**", "results/**", "out/**",  -- build trees (build-asan in CI), run outputs
  "docs/api/**",                   -- definitions for editors: empty function bodies by design
  "tests/scripts/bad_syntax.lua",  -- does not compile, on purpose (the error names its line)
  "tests/lint/**",                 -- mistakes on purpose: CTest lua_lint_finds checks they are found
}

-- The folder of this file (luacheck runs it from anywhere).
local here = (debug.getinfo(1, "S").source:match("^@(.*[/\\])") or "./")

-- Every roger.* member the API files define (`function roger.x`, `roger.x =`, `roger["x"] =`,
-- `roger.x.y =`), as luacheck's nested field table; and the top-level functions they mark
-- deprecated (not in the sandbox).
local function read_api()
  local roger, missing = {}, {}
  local lfs = require("lfs")
  local files = {}
  for name in lfs.dir(here .. "docs/api") do
    if name:match("%.lua$") then files[#files + 1] = here .. "docs/api/" .. name end
  end
  table.sort(files)
  for _, file in ipairs(files) do
    local deprecated = false
    for line in io.lines(file) do
      local path = line:match("^function roger%.([%w_.]+)%s*%(") or line:match("^roger%.([%w_.]+)%s*=")
                   or line:match('^roger%["([%w_]+)"%]%s*=')
      if path then
        local node = roger
        for part in path:gmatch("[^.]+") do
          node.fields = node.fields or {}
          node.fields[part] = node.fields[part] or {}
          node = node.fields[part]
        end
      end
      local global = deprecated and line:match("^function ([%w_]+)%s*%(")
      if global then missing[#missing + 1] = global end
      deprecated = line:match("^%-%-%-@deprecated") ~= nil or (deprecated and line:match("^%-%-%-") ~= nil)
    end
  end
  return roger, missing
end

-- The libraries .luarc.json disables for the editor are not in the sandbox either.
local function disabled_libraries()
  local out = {}
  local f = assert(io.open(here .. ".luarc.json"))
  local text = f:read("*a")
  f:close()
  local builtin = text:match('"runtime%.builtin"%s*:%s*(%b{})') or ""
  for lib in builtin:gmatch('"([%w_]+)"%s*:%s*"disable"') do out[#out + 1] = lib end
  return out
end

local roger_api, deprecated_globals = read_api()
read_globals = { roger = roger_api }
not_globals = deprecated_globals
for _, lib in ipairs(disabled_libraries()) do not_globals[#not_globals + 1] = lib end
