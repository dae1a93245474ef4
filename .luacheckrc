-- .luacheckrc: luacheck over every shipped Lua file (`luacheck .` here; CTest runs it as
-- `lua_lint`, docs/authoring.md). No global is listed by hand: the roger.* API and what the
-- sandbox takes away are read from docs/api/*.lua and .luarc.json, the description editors read,
-- which tests/test_lua_sandbox.cpp keeps equal to what the engine registers.
--
-- It runs from any folder (`luacheck --config /home/me/roger/.luacheckrc my_folder`), also as
-- share/roger/.luacheckrc of an installed roger: it reads the docs/api/ and .luarc.json beside
-- itself. Its options are returned as a table, not set as globals, so that a one-line .luacheckrc
-- in a folder of one's own, `return dofile("/home/me/roger/.luacheckrc")`, uses them too.
local lfs = require("lfs")

-- The folder of this file, with a trailing separator. luacheck loads a config as a chunk named
-- "chunk", not by its path, so the path is looked for in turn: in the chunk's name (`dofile`),
-- in the `path` or `config_path` luacheck's loader holds, in `--config FILE` on the command line,
-- and where luacheck itself finds a .luacheckrc (the current folder and its parents). The first
-- whose folder holds docs/api/ wins; else the current folder.
local function config_folder()
  local cwd = lfs.currentdir() or "."
  local candidates = {}
  local function add(file)
    if type(file) == "string" and file ~= "" then candidates[#candidates + 1] = file end
  end
  local source = debug.getinfo(1, "S").source
  if source:sub(1, 1) == "@" then add(source:sub(2)) end
  for level = 2, 30 do
    if not debug.getinfo(level, "f") then break end
    for i = 1, 200 do
      local name, value = debug.getlocal(level, i)
      if not name then break end
      if name == "path" or name == "config_path" then add(value) end
    end
  end
  local args = arg or {}
  for i = 1, #args do
    if args[i] == "--config" then add(args[i + 1]) else add(args[i]:match("^%-%-config=(.+)$")) end
  end
  local dir = cwd
  while dir and dir ~= "" do
    add(dir .. "/.luacheckrc")
    dir = dir:match("^(.*)/[^/]*$")
  end
  for _, file in ipairs(candidates) do
    local folder = file:match("^(.*[/\\])") or "./"
    if not (folder:match("^[/\\]") or folder:match("^%a:[/\\]")) then folder = cwd .. "/" .. folder end
    if lfs.attributes(file, "mode") == "file" and lfs.attributes(folder .. "docs/api", "mode") == "directory" then
      return folder
    end
  end
  return cwd .. "/"
end

local here = config_folder()
if lfs.attributes(here .. "docs/api", "mode") ~= "directory" then
  error("no docs/api/ beside this .luacheckrc (nor in " .. here .. "): run luacheck --config ROGER/.luacheckrc, "
        .. "ROGER a roger checkout or the share/roger of an installed roger")
end

-- Every roger.* member the API files define (`function roger.x`, `roger.x =`, `roger["x"] =`,
-- `roger.x.y =`), as luacheck's nested field table; the top-level functions they mark deprecated
-- (not in the sandbox); and the library members they mark so (`string.dump`, `math.random`), as
-- {library, member} pairs.
local function read_api()
  local roger, missing, members = {}, {}, {}
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
      local library, member = line:match("^function ([%w_]+)%.([%w_]+)%s*%(")
      if deprecated and library ~= "roger" and member then members[#members + 1] = { library, member } end
      deprecated = line:match("^%-%-%-@deprecated") ~= nil or (deprecated and line:match("^%-%-%-") ~= nil)
    end
  end
  return roger, missing, members
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

local roger_api, not_globals, removed_members = read_api()
for _, lib in ipairs(disabled_libraries()) do not_globals[#not_globals + 1] = lib end

-- Lua 5.4's standard as luacheck defines it, less the library members the sandbox removes: then
-- `math.random(3)` is reported ("accessing undefined field random of global math") as `loadfile`
-- is. A deep copy: luacheck's own table is shared with its other standards.
local function copy(t)
  if type(t) ~= "table" then return t end
  local out = {}
  for k, v in pairs(t) do out[k] = copy(v) end
  return out
end
local sandbox_std = copy(require("luacheck.builtin_standards").lua54)
for _, pair in ipairs(removed_members) do
  local library = sandbox_std.read_globals[pair[1]]
  if library and library.fields then library.fields[pair[2]] = nil end
end

return {
  stds = { roger_sandbox = sandbox_std },
  std = "roger_sandbox",
  -- Callbacks have fixed argument lists (state, time, world): naming the unused ones documents them.
  unused_args = false,
  -- Anchored at this file's folder, so that they hold from whichever folder luacheck runs.
  exclude_files = {
    here .. "build*/**", here .. "results/**", here .. "out/**",  -- build trees (build-asan in CI), run outputs
    here .. "docs/api/**",                   -- definitions for editors: empty function bodies by design
    here .. "tests/scripts/bad_syntax.lua",  -- does not compile, on purpose (the error names its line)
    here .. "tests/lint/**",                 -- mistakes on purpose: CTest lua_lint_finds checks they are found
  },
  read_globals = { roger = roger_api },
  not_globals = not_globals,
}
