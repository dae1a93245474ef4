-- lib/sorting.lua: what every sorting policy shares, hand-written or learned (curricula/sorting.lua,
-- curricula/sort_by_hand.lua): the four types of scenarios/sorting.lua with their colours and
-- regions, the sorting move (one transport skill bound to a type), and the hand-written chooser.
--
--   local sorting = require("lib.sorting")
--   local moves = sorting.moves(Phi_T)          -- Phi_T bound to each type, in region order
--   local sort = sorting.by_hand(moves)         -- the first type with something left to do
--   local tasks = sorting.tasks(moves)          -- per type, its move until the type is put away
--
-- Nothing here counts objects: a move carries one object of its type, and run again carries the
-- next; a move whose search has looked everywhere and seen none of its type left is NOREF
-- (docs/control.md, search and Bindings). So one policy serves any number of objects.
local sorting = {}

-- The types in region order (scenarios/sorting.lua: region k - 1 belongs to TYPES[k]) and their
-- colours; the order the scenario's "cycle" mix lays objects out in.
sorting.TYPES = { "circle", "triangle", "pentagon", "spade" }
sorting.COLOURS = { circle = "#dc1e1e", triangle = "#2850dc", pentagon = "#e6aa14", spade = "#9628aa" }
sorting.CYCLE = { "circle", "spade", "pentagon", "triangle" }
sorting.REGION = {}
for k, t in ipairs(sorting.TYPES) do sorting.REGION[t] = k - 1 end

-- How long (s) one move may run without delivering before it is given up and started over (a
-- grasp lost on the way, a stimulus hidden from one eye by another object, an object pinned
-- against a wall). A stuck move wastes less of the episode's 30 s per object than at 20 or 30 s
-- (8-object sorting by hand on the development seeds 90000-90039, 3000000-3000019 and, with 2
-- obstacles, 91000-91019: 77, 72 and 70 of 80 fully sorted with 15, 20 and 30 s).
sorting.PATIENCE = 15

-- The carrying navigator's parameters for sorting (skills.primitives' `carry` overrides): it
-- converges 0.25 m inside a region's edge (`depth`), not at the edge, because sorting's judge asks
-- for the object's centre inside its region and the control point (the carried object as the eyes
-- see it) may lie a few centimetres off that centre; and it grows other objects by 0.25 m, not the
-- 0.4 m that keeps preshaped hands off them: what it steers is the carried object, and at 0.4 m
-- one object put away near a region's centre left no goal cell for the next of its type
-- (docs/control.md, phi1).
sorting.CARRY = { depth = 0.25, margin = 0.2, objects = 0.25 }

-- One sorting move for type `t`: let go of whatever the hands hold and back off, carry one object
-- of that colour into that type's region with `transport` (which must converge only once the
-- object is delivered, as a learned Phi_T does), then let go of it. Without falling back, a
-- transport that finds nothing to carry ends the move NOREF instead of letting go for ever.
-- `t` is one of TYPES, or a name of the caller's own given with both `colour` and `region`.
-- `options` (all optional):
--   tag          text appended to the names, to keep them unique ("" by default)
--   sticky_noref a move that gave up (or found none left) stays NOREF until it delivers again
--                (roger.bind's sticky_noref): a learned chooser that retries such a type sees the
--                retry as what it is, not as the all-!CONV state every episode starts in
--   retry_after  seconds after which that NOREF is forgotten and the type shows !CONV again,
--                worth another try (roger.bind's retry_after; 0, the default: never)
--   colour       the objects to carry ("#rrggbb" or {r, g, b}; sorting.move only): by default
--                COLOURS[t]
--   region       the goal region (0-based index) to carry them into (sorting.move only): by
--                default REGION[t]
-- The hand-written chooser uses neither sticky_noref nor retry_after: its rotate fallback waits
-- for a given-up move's NOREF to clear.
local MOVES_OPTIONS = { { "tag", "string" }, { "sticky_noref", "boolean" }, { "retry_after", "number" } }
local MOVE_OPTIONS = { { "tag", "string" }, { "sticky_noref", "boolean" }, { "retry_after", "number" },
                       { "colour", "table or string" }, { "region", "number" } }

-- Checks `options` against `known` (a list of {name, type}) for `fn`, raising at `level`.
local function check_options(fn, options, known, level)
  if options == nil then return {} end
  local names, want = {}, {}
  for k, o in ipairs(known) do names[k], want[o[1]] = o[1], o[2] end
  if type(options) ~= "table" then
    error(fn .. ": options must be a table {" .. table.concat(names, ", ") .. "}, got " .. type(options), level)
  end
  table.sort(names)
  for k, v in pairs(options) do
    if not want[k] then
      error(fn .. ": unknown option '" .. tostring(k) .. "' (known: " .. table.concat(names, ", ") .. ")", level)
    elseif not want[k]:find(type(v), 1, true) then
      error(fn .. ": option '" .. k .. "' must be a " .. want[k] .. ", got " .. type(v), level)
    end
  end
  return options
end

-- The colour and region of type `t`: the options', else the built-in type's. Raises at the
-- caller of sorting.move (level 3 from here) for a type that is neither.
local function colour_and_region(t, options)
  local colour, region = options.colour or sorting.COLOURS[t], options.region or sorting.REGION[t]
  if type(t) ~= "string" or colour == nil or region == nil then
    error("sorting.move: unknown type '" .. tostring(t) .. "' (known: " .. table.concat(sorting.TYPES, ", ") ..
          "); for a type of your own give both options colour and region", 3)
  end
  return colour, region
end

-- Returns f()'s value; its error is raised, its place replaced, at the line `level` levels above
-- this function (as error's levels count): a value that roger.bind, roger.sequence or roger.policy
-- refuses is the caller's (found by a probe: sorting.move's colour = "red" read
-- "curricula/lib/sorting.lua:98: roger.bind('sort circle'): field 'stimulus' ..."). lib.skills'
-- made_for_caller is the same rule for builders one level shallower.
local function at_caller(level, f)
  local ok, result = pcall(f)
  if not ok then error((tostring(result):gsub("^[^\n]-:%d+: ", "", 1)), level) end
  return result
end

-- The move of one type: its errors at the caller of sorting.move or sorting.moves (4 levels up
-- from at_caller: at_caller, this, sorting.move(s), the caller).
local function build_move(transport, t, colour, region, options)
  local tag = options.tag or ""
  local steps = at_caller(4, function()
    return roger.sequence("move " .. t .. tag, { roger.primitive("release"), transport, roger.primitive("release") },
                          { fall_back = false })
  end)
  local move = at_caller(4, function()
    return roger.bind("sort " .. t .. tag, steps,
                      { stimulus = colour, region = region,
                        patience = sorting.PATIENCE, sticky_noref = options.sticky_noref or false,
                        retry_after = options.retry_after or 0 })
  end)
  return move
end

function sorting.move(transport, t, options)
  options = check_options("sorting.move", options, MOVE_OPTIONS, 3)
  local colour, region = colour_and_region(t, options)
  local move = build_move(transport, t, colour, region, options)  -- not a tail call: it keeps the levels
  return move
end

-- The four moves, in region order (`options` as for sorting.move).
function sorting.moves(transport, options)
  options = check_options("sorting.moves", options, MOVES_OPTIONS, 3)
  local moves = {}
  for k, t in ipairs(sorting.TYPES) do
    moves[k] = build_move(transport, t, sorting.COLOURS[t], sorting.REGION[t], options)
  end
  return moves
end

-- How long (s) a type's objects must have lain sorted before its task counts it put away. The
-- judge's "not held" turns true the moment the hands part from the object, while the move's
-- last release is still backing off; resting then, Roger stopped with a hand at the object, and
-- the touch came and went every few ticks, each a change of state, each a decision.
sorting.SETTLE = 1.0

-- One type's task for a learned chooser: `move` (sorting.move for type `t`) run until every object
-- of that type has lain sorted for SETTLE seconds (roger.sorted(colour), the world's judgement, as
-- the stage's absorbing state is). Its gamma is what a chooser needs to know of that type: CONV when the type is put
-- away, NOREF when its move gave up or looked everywhere and saw none left, !CONV otherwise (not
-- yet tried, running, or one delivered and more left). A bare move's gamma tells neither "put
-- away" (it is CONV after each delivery, more left or not) nor "gave up" from "none left" (NOREF).
-- Delivering one of several objects of the type changes nothing a chooser sees: the move runs
-- again for the next one, without a decision. Chosen once its type is put away, it rests: a move
-- run again would turn about looking for more and might knock a put-away object out of its region.
-- `options` is the tag (text appended to the name) or a table { tag, colour }: `colour`, the objects
-- the task judges put away ("#rrggbb" or {r, g, b}), is needed for a type of one's own, as
-- sorting.move's colour is (by default COLOURS[t]).
local TASK_OPTIONS = { { "tag", "string" }, { "colour", "table or string" } }

-- The task of one type: its errors at the caller of sorting.task or sorting.tasks (4 levels up
-- from at_caller, as build_move's).
local function build_task(move, t, colour, tag)
  local task = at_caller(4, function()
    return roger.policy("put away " .. t .. (tag or ""), {
      actions = { move }, table = { ["*"] = move }, rest_when_done = true,
      done = roger.held(roger.sorted(colour), sorting.SETTLE),
    })
  end)
  return task
end

function sorting.task(move, t, options)
  if type(options) ~= "table" then options = { tag = options } end
  options = check_options("sorting.task", options, TASK_OPTIONS, 3)
  -- Found by a probe: a nil move was "'actions' must hold at least one action", of a policy the
  -- caller never wrote.
  if type(move) ~= "userdata" then
    error("sorting.task: its first argument is the type's move (sorting.move), got " .. type(move), 2)
  end
  -- roger.sorted(nil) would judge every colour, not this type's.
  local colour = options.colour or sorting.COLOURS[t]
  if type(t) ~= "string" or colour == nil then
    error("sorting.task: unknown type '" .. tostring(t) .. "' (known: " .. table.concat(sorting.TYPES, ", ") ..
          "); for a type of your own give the option colour, as to sorting.move", 2)
  end
  local task = build_task(move, t, colour, options.tag)
  return task
end

-- The four tasks over `moves` (sorting.moves), in region order.
function sorting.tasks(moves, tag)
  -- Found by a probe: one move given was refused inside roger.policy ("'actions' must hold at
  -- least one action, got an empty list"), naming a policy the caller never wrote.
  if type(moves) ~= "table" or #moves ~= #sorting.TYPES then
    local got = type(moves) ~= "table" and type(moves) or #moves == 1 and "1 move" or #moves .. " moves"
    error("sorting.tasks: takes the " .. #sorting.TYPES .. " moves of sorting.moves (one per type, in region order: " ..
          table.concat(sorting.TYPES, ", ") .. "), got " .. got .. "; for one type, sorting.task(move, type)", 2)
  end
  -- Found by a probe: moves in another order were taken, each task judging one type while its move
  -- sorted another, and a table { tag, colour } judged one colour in all four tasks.
  if tag ~= nil and type(tag) ~= "string" then
    error("sorting.tasks: its second argument is the tag (text appended to the names), got " .. type(tag) ..
          "; a colour is one type's: give it to sorting.task(move, type, { colour = ... })", 2)
  end
  for k, t in ipairs(sorting.TYPES) do
    local ok, name = pcall(function() return moves[k].name end)
    if not ok or type(name) ~= "string" or name:sub(1, #("sort " .. t)) ~= "sort " .. t then
      error("sorting.tasks: move " .. k .. " must be the " .. t .. " move of sorting.moves (in region order: " ..
            table.concat(sorting.TYPES, ", ") .. "), got " .. (ok and type(name) == "string" and "'" .. name .. "'"
            or tostring(moves[k])), 2)
    end
  end
  local tasks = {}
  for k, t in ipairs(sorting.TYPES) do tasks[k] = build_task(moves[k], t, sorting.COLOURS[t], tag) end
  return tasks
end

-- How far (m) the hand-written chooser goes to look from elsewhere, at least (phi1's `away`).
sorting.AWAY = 1.0

-- The hand-written chooser over `moves`: run the first move that is not NOREF (a move that
-- delivered, CONV, runs again for the next object of its type; one not yet run is !CONV). When
-- every move is NOREF (each found nothing from where it looked, or gave up) while the world is not
-- sorted yet, run them again in turn, each until it ends ("rotate"): one of them, searching from
-- where Roger now is, finds what is left. After the last move of each round comes phi1 with
-- goal = "elsewhere": where a whole round saw nothing from the spot the round before it ended at,
-- what is left is hidden from there, and it drives to a vantage point at least AWAY metres off;
-- otherwise it ends at once, and the round goes on in the same tick (docs/control.md, phi1 and
-- policies). Rounds from one spot alone searched for 158 s for a triangle hidden behind a pentagon
-- put away (sorting seed 182003, random mix); going elsewhere before any round instead sorted
-- fewer development worlds, as most rounds find what is left.
--
-- At most MAX_BY_HAND moves: with phi1 they are the policy's actions, and a policy has at most 12
-- (3^12 states). Its table is written with wildcards, one key per move and state other than NOREF
-- ("NOREF NOREF CONV * ... *": the first two NOREF, the third CONV), not state by state.
sorting.MAX_BY_HAND = 11

function sorting.by_hand(moves, name)
  if type(moves) ~= "table" or #moves == 0 or #moves > sorting.MAX_BY_HAND then
    error("sorting.by_hand: takes a list of 1 to " .. sorting.MAX_BY_HAND .. " moves (with phi1 they are the " ..
          "policy's actions, at most 12), got " .. (type(moves) == "table" and #moves .. " moves" or type(moves)), 2)
  end
  local n = #moves
  local actions = {}
  for i = 1, n do actions[i] = moves[i] end
  actions[n + 1] = roger.primitive("phi1", { goal = "elsewhere", away = sorting.AWAY })
  local table_ = {}
  for i = 1, n do
    local before, after = string.rep("NOREF ", i - 1), string.rep(" *", n - i + 1)
    table_[before .. "!CONV" .. after] = moves[i]
    table_[before .. "CONV" .. after] = moves[i]
  end
  if name ~= nil and type(name) ~= "string" then
    error("sorting.by_hand: its second argument is the policy's name (a string), got " .. type(name), 2)
  end
  local chooser = at_caller(3, function()
    return roger.policy(name or "sort by hand", { actions = actions, table = table_, fallback = "rotate" })
  end)
  return chooser
end

-- A misspelt name (sorting.mve, sorting.REGIONS) is an error naming the ones there are, as lib.skills
-- does (found by a probe: a misspelt builder said "attempt to call a nil value", a misspelt table
-- was nil without a word).
return setmetatable(sorting, { __index = function(_, name)
  local names = {}
  for k in pairs(sorting) do names[#names + 1] = tostring(k) end
  table.sort(names)
  error("lib.sorting has no " .. string.format("%q", tostring(name)) .. "; it has: " .. table.concat(names, ", "), 2)
end })
