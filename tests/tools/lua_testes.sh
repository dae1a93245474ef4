#!/bin/bash
# lua_testes.sh: Lua's own test suite as the judge of the sandbox's Lua. Each file of Lua 5.4.4's
# tests (testes/*.lua: lua-5.4.4-tests.tar.gz from lua.org, or the v5.4.4 tag of github.com/lua/lua)
# runs twice with the same harness: as a scenario's top-level code under `roger check`, and under
# plain `lua5.4`. The harness counts the asserts that pass; a file passes when both runs reach its
# end with the same count. The tests are not kept in this repository: point the script at them.
#
#   bash tests/tools/lua_testes.sh TESTES_DIR [ROGER]      (ROGER defaults to build/engine/roger)
#
# What the harness changes, the same in both runs, and only where the sandbox refuses on purpose
# what a test uses (docs/reliability.md: no debug library but traceback, no io or os, no bytecode,
# no finalizers, no math.random, pairs in a fixed order) or where the harness itself shows
# through (its counting assert is a Lua function, so an assert's own error position moves):
#   - every file: `_port` and `_soft` set (no locale tests, the shorter loops; big.lua and
#     verybig.lua run whole), `package.loaded` answered from a table of the standard names, and
#     each edit listed below; an edit that changes nothing (another version of the tests) stops
#     the run; where a file writes a file or yields at its top level (as all.lua lets it), a
#     string buffer or a coroutine stands in;
#   - the globals Lua's tests read but never set (`undef`, `T`, `Message`, `Y`) declared as locals,
#     since the sandbox refuses a script that reads an undefined global at load.
# A file's asserts are counted in the harness's order, so the counts of both runs compare the same
# checks. Exit status 0 when every file agrees, 1 otherwise.
set -u
testes=${1:?usage: lua_testes.sh TESTES_DIR [ROGER]}
roger=${2:-build/engine/roger}
[ -f "$testes/strings.lua" ] || { echo "lua_testes: $testes holds no strings.lua: expected Lua 5.4.4's testes folder" >&2; exit 2; }
[ -x "$roger" ] || { echo "lua_testes: $roger is not an executable roger" >&2; exit 2; }
command -v lua5.4 > /dev/null || { echo "lua_testes: lua5.4 not found (apt-get install lua5.4)" >&2; exit 2; }
roger=$(cd "$(dirname "$roger")" && pwd)/$(basename "$roger")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$testes"/*.lua "$work"/
cd "$work" || exit 2

# A deterministic math.random (an LCG), for the files that draw numbers only to vary their data.
seeded_random='local __seed = 1 local math = setmetatable({random = function(m, n) __seed = (__seed * 1103515245 + 12345) % 2147483648 local u = __seed / 2147483648 if not m then return u end if not n then m, n = 1, m end return m + math.floor(u * (n - m + 1)) end}, {__index = math})'
# os as the tests read it: a clock that stands still, and only the "C" locale.
still_os='local os = {clock = function() return 0 end, time = function() return 0 end, setlocale = function(l) if l == nil or l == "C" then return "C" end end}'
undeclared='local undef, T, Message, Y = nil'
# tracegc.lua marks collections by printing from a finalizer (refused): its start and stop do nothing.
tracegc_idle='s/require"tracegc"/{start = function() end, stop = function() end}/'

failures=0
# prepare NAME HEADER [SED_EDIT...]: writes run_NAME.lua, the harness around NAME.lua.
prepare() {
  local name=$1 header=$2 edit
  shift 2
  cp "$name.lua" "body_$name.lua"
  for edit in "$@"; do
    cp "body_$name.lua" before.lua
    sed -i "$edit" "body_$name.lua"
    if cmp -s before.lua "body_$name.lua"; then
      echo "lua_testes: $name.lua: the edit '$edit' changed nothing: are these Lua 5.4.4's tests?" >&2
      exit 2
    fi
  done
  {
    echo 'local __count = 0 local __assert = assert'
    echo 'assert = function(...) __count = __count + 1 return __assert(...) end'
    echo "_port = true _soft = true local package = {loaded = setmetatable({}, {__index = function(_, k) return ({_G = 1, string = 1, table = 1, coroutine = 1, math = 1, io = 1, os = 1, debug = 1, utf8 = 1, package = 1})[k] end})} $header"
    echo 'local function __body(...)'
    cat "body_$name.lua"
    echo ''
    echo "end ${runner:-__body()} print(\"asserts passed\", __count)"
    echo 'return { name = "lua_testes", generate = function(world) world:robot{x = 0, y = 0, heading = 0} end }'
  } > "run_$name.lua"
}

# run NAME: both runs, one line of the table.
run() {
  local name=$1 plain ours
  plain=$(timeout 600 lua5.4 "run_$name.lua" 2>&1 | sed -n 's/^asserts passed\t//p')
  ours=$(timeout 900 "$roger" check --seeds 1 --lua-instructions 4000000000 "run_$name.lua" 2>&1 > /dev/null |
         sed -n 's/^asserts passed\t//p')
  local verdict=same
  if [ -z "$plain" ] || [ -z "$ours" ] || [ "$plain" != "$ours" ]; then verdict=DIFFERENT; failures=$((failures + 1)); fi
  printf '%-12s %10s %10s   %s\n' "$name.lua" "${plain:-stopped}" "${ours:-stopped}" "$verdict"
  if [ "$verdict" != same ]; then
    "$roger" check --seeds 1 --lua-instructions 4000000000 "run_$name.lua" 2>&1 | grep -m1 -A4 'roger: error' | sed 's/^/    /'
  fi
}

printf '%-12s %10s %10s\n' file lua5.4 sandbox
# The string library: %p of a file handle (no io) left out.
prepare strings "$still_os" '/string.format("%p", io.stdin)/d'
prepare pm ''
prepare tpack ''
prepare utf8 ''
prepare sort "$still_os $seeded_random"
prepare vararg ''
# Tables: pairs visits keys in a fixed order, not next's, so the loop that checks next against
# pairs walks with next itself; a file handle as a key becomes a table; the walk over _G counts
# none of its asserts (the sandbox has fewer globals than lua5.4, so more or fewer steps).
prepare nextvar "$undeclared" 's/\[io\.stdin\] = 9/[{0}] = 9/' \
  '/bug in 5.4.1/,/coroutine.yield(v)/s/for k, v in pairs(t) do/for k, v in next, t do/' \
  's/^    assert(_G\[n\] ~= undef)/    __assert(_G[n] ~= undef)/'
# math.random and randomseed are refused (scripts draw from their rng): that section left out.
prepare math '' "/^print(\"testing 'math.random'\")/,/^assert(not pcall(random, maxint, minint))/d"
# bit32 is defined by the test itself in package.preload: a local function instead.
prepare bitwise '' 's/^package.preload.bit32 = function ()/local __bit32 = function ()/' "s/^local bit32 = require'bit32'/local bit32 = __bit32()/"
# Calls: bytecode (string.dump, binary chunks) is refused, and debug's upvalues are not there.
prepare calls '' '/^print("testing binary chunks")/,/^end$/d' \
  '/^-- repeat the test loading a binary chunk/,+45d' \
  '/^-- load when _ENV is not first upvalue/,/^assert(x() == 123)/d' \
  '/^-- another small bug (in 5.2.1)/,/^assert(not pcall(string.dump, print))/d' \
  '/^assert(debug.getinfo(a).source == "modname")/d'
prepare constructs "$seeded_random" "s/^  assert(debug.getinfo(1, \"n\").name == 'F')/  -- (debug.getinfo left out)/"
prepare goto '' '/^-- all functions share same .a./,+32d'
# A chunk's current line from an error's position instead of debug.getinfo.
prepare literals "$still_os" 's/require"debug".getinfo(1).currentline/tonumber(select(2, pcall(function() local x; return x.y end)):match(":(%d+):"))/'
prepare closure "$undeclared" '/^-- test for debug manipulation of upvalues/,/^assert(not pcall(debug.upvaluejoin, foo1, 1, print, 1))/d'
# Metatables: no file handles, no debug.setmetatable on basic types.
prepare events "$undeclared" '/^assert(not pcall(rawlen, io.stdin))/d' \
  '/^-- testing metatables for basic types/,/^debug.setmetatable(nil, {})/d'
# Messages: no io, no debug, no bytecode; `pcall(assert, ...)` and a failed assert's position
# would name the harness's counting assert.
prepare errors "$undeclared" '/io\.stdin\|io\.input\|io\.write/d' \
  '/^_G.D = debug/,/^_G.D = nil/d' \
  '/^-- errors in functions without debug info/,/^end$/d' \
  '/^  -- .assert. with extra arguments/,/^  assert(tonumber(line) == debug.getinfo(1, "l").currentline - 2)/d'
# Coroutines: no debug hooks, no getinfo, no setupvalue.
prepare coroutine "$undeclared" '/^do   -- testing single trace of coroutines/,/^end$/d' \
  '/^  assert(debug.getinfo(1).currentline == debug.getinfo(foo).linedefined + 1)/d' \
  '/^  assert(debug.getinfo(2).currentline == debug.getinfo(goo).linedefined)/d' \
  '/^      Y = debug.getinfo(2)/d' 's/assert(X == 43 and Y.what == "C")/assert(X == 43)/' \
  '/^-- getuptable & setuptable/,/^assert(g.k.AAA == 11)/d'
# Locals and to-be-closed variables: no finalizers (tracegc), no getinfo, no hooks.
prepare locals "$undeclared" "$tracegc_idle" '/^local function getenv (f)/,/^end$/d' 's/^assert(getenv(.*$/assert(true)/' \
  's/assert(debug.getinfo(2).name == "[a-z]*")/assert(true)/' \
  "/^do   -- '__close' vs. return hooks in Lua functions/,/^end\$/d"
prepare cstack "$undeclared" "$tracegc_idle"
# The collector: its options, steps, long strings and weak tables; from the first finalizer on
# (the sandbox refuses __gc) the file is left out.
prepare gc "$undeclared $still_os" "/^-- 'bug' in 5.1/,\$d"
# Large tables and constants, whole (not _soft); it yields at its top level, as all.lua runs it in a
# coroutine, and takes debug's traceback, which the sandbox has, by require.
# Very big programs, whole (not _soft): the program it writes to a file and runs is gathered in a string and loaded
# (io.write's numbers as it writes them: %.14g for floats).
prepare verybig '_soft = false local __buf = {} local io = {write = function(...) for i = 1, select("#", ...) do local v = select(i, ...) if math.type(v) == "float" then v = string.format("%.14g", v) end __buf[#__buf + 1] = tostring(v) end end, output = function() end, close = function() end} local os = {tmpname = function() return "verybig" end, remove = function() return true end} local dofile = function() return assert(load(table.concat(__buf)))() end'
runner='coroutine.wrap(__body)()' prepare big 'local undef = nil _soft = false local require = function(n) if n == "debug" then return debug end return require(n) end'

for name in strings pm tpack utf8 sort vararg nextvar math bitwise calls constructs goto literals closure events errors \
            coroutine locals cstack gc big verybig; do
  run "$name"
done
if [ "$failures" -gt 0 ]; then
  echo "lua_testes: $failures file(s) differ"
  exit 1
fi
echo "lua_testes: every file gives plain Lua's count"
