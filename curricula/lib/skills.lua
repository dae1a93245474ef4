-- lib/skills.lua: the skills the paper assumes (Section II-C), written as compositions of the
-- primitive controllers. `require("lib.skills")` returns this module table; nothing is built
-- until a builder is called, so a script chooses its own primitives and parameters:
--
--   local skills = require("lib.skills")
--   local p = skills.primitives()              -- search, phi0 ... phi5 and the carrying phi1
--   local Phi6 = skills.Phi6(p)                -- search, then track
--   local Phi7 = skills.Phi7(p)                -- approach while preshaping
--   local transport = skills.transport(p)      -- phi1 <| phi4 <| phi5, carrying to the goal
--   local done = skills.transported(transport) -- its absorbing state: phi1, phi4, phi5 CONV
--
-- Skill names are unique within a script: pass a second argument to build another copy
-- (skills.Phi6(p, "Phi6_fast")).
local skills = {}

-- A builder given something else than it takes fails at its caller's line, saying what it takes,
-- not inside this file ("attempt to index a nil value (local 'p')").
local function described(v)
  if type(v) ~= "userdata" then return type(v) end
  local ok, name = pcall(function() return v.name end)
  return ok and ("controller '" .. tostring(name) .. "'") or "a " .. tostring(v)
end

local function expect_primitives(p, builder, fields)
  if type(p) ~= "table" then
    error(builder .. " takes the controllers of skills.primitives() (local p = skills.primitives()), got " ..
          described(p), 3)
  end
  for _, field in ipairs(fields) do
    local ok, value = pcall(function() return p[field] end)  -- skills.primitives() refuses a missing name
    if not ok or value == nil then
      error(builder .. " takes the controllers of skills.primitives(): its table has no '" .. field .. "'", 3)
    end
  end
end

local primitive_fields = { "search", "phi0", "phi1", "phi2", "phi3", "phi4", "phi5", "carry" }

-- A builder's `name`: the default when nil, else a string, refused at the caller's line.
local function skill_name(name, default, builder)
  if name == nil then return default end
  if type(name) ~= "string" then
    error(builder .. ": its last argument is the skill's name (a string), got " .. described(name), 3)
  end
  return name
end

-- make(...) (roger.primitive, roger.sequence) for a builder: its refusal (a parameter, or a name
-- that is a primitive kind's or the script has given another controller) is said at the line that
-- called the builder, not at this file's (found by probes: skills.Phi6(p, "phi0") was refused at
-- lib/skills.lua's line). Called from the builder itself, not in a tail call: that line is three up.
local function made_for_caller(make, ...)
  local ok, made = pcall(make, ...)
  if not ok then error((tostring(made):gsub("^[^\n]-:%d+: ", "", 1)), 3) end
  return made
end

-- Why `overrides` cannot be the overrides of skills.primitives, or nil when it can: a misspelt
-- field ({ phi33 = ... }, { cary = ... }) would otherwise leave that primitive at its defaults
-- without a word (found by a probe: an ablation trained with the phi3 it meant to change).
local function primitive_overrides_problem(overrides)
  if overrides == nil then return nil end
  if type(overrides) ~= "table" then
    return "the overrides of skills.primitives are a table of parameters by controller " ..
           "({ phi3 = { epsilon = 0.05 } }), got " .. described(overrides)
  end
  local known = {}
  for _, field in ipairs(primitive_fields) do known[field] = true end
  local keys = {}
  for k in pairs(overrides) do keys[#keys + 1] = k end
  table.sort(keys, function(a, b) return tostring(a) < tostring(b) end)
  for _, k in ipairs(keys) do
    if not known[k] then
      return "skills.primitives has no controller " .. string.format("%q", tostring(k)) ..
             " to override; it has: " .. table.concat(primitive_fields, ", ")
    end
    if type(overrides[k]) ~= "table" then
      return "skills.primitives: the overrides of '" .. k .. "' are a table of its parameters " ..
             "({ " .. k .. " = { ... } }), got " .. described(overrides[k])
    end
  end
  return nil
end

-- One instance of each primitive with default parameters, plus the carrying navigator. The
-- skills built from one set share them, as in the paper, where phi4 in "phi4 <| phi2" and in
-- "phi4 <| phi5" is the same controller. `overrides` maps a field of the set to parameters,
-- e.g. { phi3 = { epsilon = 0.05 } }; a mistake in them is an error at the caller's line.
function skills.primitives(overrides)
  local problem = primitive_overrides_problem(overrides)
  if problem then error(problem, 2) end
  overrides = overrides or {}
  local p = {}
  for _, kind in ipairs({ "search", "phi0", "phi1", "phi2", "phi3", "phi4", "phi5" }) do
    p[kind] = made_for_caller(roger.primitive, kind, overrides[kind])
  end
  -- The transport navigator: phi1 towards the scenario's goal region, with its control point
  -- carried ahead of the base at the grasped object's centre (carry = "body": 0.36 m for the
  -- default Roger, docs/control.md, Bodies) and a gentler cruise speed so the grasp holds through
  -- the accelerations. Its name stays "phi1", as in the paper's "phi1 <| phi4 <| phi5".
  local carry = { goal = "region", carry = "body", speed = 0.8 }
  for k, v in pairs(overrides.carry or {}) do carry[k] = v end
  p.carry = made_for_caller(roger.primitive, "phi1", carry)
  -- A misspelt name (p.phi33, p.Phi3) is an error at the line that reads it. Without this it is
  -- nil, and a nil at the end of an action list vanishes from the table: the stage would train
  -- on one action fewer without a word.
  return setmetatable(p, { __index = function(_, name)
    local names = {}
    for k in pairs(p) do names[#names + 1] = tostring(k) end
    table.sort(names)
    error("skills.primitives() has no controller " .. string.format("%q", tostring(name)) ..
          "; it has: " .. table.concat(names, ", "), 2)
  end })
end

-- Phi6: "a control policy that searches for and then tracks prescribed stimuli using phi0".
-- search turns until both eyes see the stimulus (CONV), then phi0 centres it; if phi0 loses it
-- (NOREF), the sequence falls back to search.
function skills.Phi6(p, name)
  expect_primitives(p, "skills.Phi6", { "search", "phi0" })
  local skill = made_for_caller(roger.sequence, skill_name(name, "Phi6", "skills.Phi6"), { p.search, p.phi0 })
  return skill  -- not a tail call: the caller's line is two levels up
end

-- Phi7: "a control policy that combines phi1 and phi4 <| phi2 sequentially to approach an object
-- while pre-shaping the arms for prehensile grasping". phi1 drives to the approach ring around
-- the seen object; then phi2 places body and hands on a standoff circle around it, with phi4
-- conditioning the arms in phi2's nullspace.
function skills.Phi7(p, name)
  expect_primitives(p, "skills.Phi7", { "phi1", "phi2", "phi4" })
  local skill = made_for_caller(roger.sequence, skill_name(name, "Phi7", "skills.Phi7"),
                                { p.phi1, p.phi4:subject_to(p.phi2) })
  return skill  -- not a tail call: the caller's line is two levels up
end

-- The grasp keeper phi4 <| phi5: phi5 holds the three contacts while the base moves, phi4
-- conditions the arms in its nullspace.
function skills.keep_grasp(p)
  expect_primitives(p, "skills.keep_grasp", { "phi4", "phi5" })
  return p.phi4:subject_to(p.phi5)
end

-- Phi_STG: "combines the Phi_SG skill with the primitive phi4 <| phi5 in order to Search for and
-- then Track a Grasp whenever all the contacts are on the ball and Phi_SG is converged". `sg` is
-- a search-grasp skill (learned or hand-written) whose CONV means the grasp is formed.
function skills.Phi_STG(sg, p, name)
  expect_primitives(p, "skills.Phi_STG (its second argument)", { "phi4", "phi5" })
  local skill = made_for_caller(roger.sequence, skill_name(name, "Phi_STG", "skills.Phi_STG"),
                                { sg, skills.keep_grasp(p) })
  return skill  -- not a tail call: the caller's line is two levels up
end

-- The transport composite of Section III-B, phi1 <| phi4 <| phi5 (= phi1 <| (phi4 <| phi5)):
-- carry the object to the goal region while phi5 keeps the grasp and phi4 the arm posture, the
-- navigation projected into their nullspace so it never pulls the hands off the object.
function skills.transport(p)
  expect_primitives(p, "skills.transport", { "carry", "phi4", "phi5" })
  return roger.compose("phi1 <| phi4 <| phi5", { phi1 = p.carry, phi4 = p.phi4, phi5 = p.phi5 })
end

-- The absorbing state of Phi_T for a transport composite t = phi1 <| (phi4 <| phi5): "gamma(phi1)
-- = CONV and gamma(phi4) = CONV and gamma(phi5) = CONV", the object grasped at the goal. phi1 must
-- itself be CONV (the object in the goal region): as the subordinate of t it would also count as
-- converged once it merely stops making progress, which says nothing about where the object is.
-- phi4 and phi5 are read through their composite phi4 <| phi5, where phi4 converges when it
-- reaches its constrained equilibrium under phi5 (docs/control.md, subject-to).
function skills.transported(t)
  local ok, kind = pcall(function() return t.kind end)
  if not ok or kind ~= "subject_to" then
    error("skills.transported takes the transport composite (skills.transport(p)), got " .. described(t), 2)
  end
  return roger.all{ roger.converged(t.subordinate), roger.converged(t.superior) }
end

-- A misspelt builder (skills.Phi8(p)) is an error naming the ones there are, as a misspelt
-- primitive is: without this, Lua says only "attempt to call a nil value (field 'Phi8')".
return setmetatable(skills, { __index = function(_, name)
  local names = {}
  for k in pairs(skills) do names[#names + 1] = tostring(k) end
  table.sort(names)
  error("lib.skills has no " .. string.format("%q", tostring(name)) .. "; it has: " .. table.concat(names, ", "), 2)
end })
