-- lib/param_defaults.lua: a library's parameters added to a scenario's own, with the scenario's own
-- defaults for some of them (lib/body.lua's body.with_params is built on it):
--
--   params = defaults.with_params(body.PARAMS, { shape = ... }, { upper_arm = 0.6, eye_pixels = 48 },
--                                 "body.with_params", "lib/body.lua")
--
-- A name the scenario's params already define would be silently replaced by the library's entry,
-- so it is refused, as are an unknown name (with the nearest known one) and a default of the wrong
-- type or out of range: every problem at once, raised at the scenario's line.
local defaults = {}

-- The names of a parameter table, sorted (so that messages do not depend on the order of pairs()).
local function sorted_names(t)
  local names = {}
  for name in pairs(t) do names[#names + 1] = tostring(name) end
  table.sort(names)
  return names
end

-- Edits (insertions, deletions, substitutions) from a to b, for "did you mean".
local function edits(a, b)
  local row = {}
  for j = 0, #b do row[j] = j end
  for i = 1, #a do
    local diagonal, ca = row[0], a:sub(i, i)
    row[0] = i
    for j = 1, #b do
      local up = row[j]
      row[j] = math.min(up + 1, row[j - 1] + 1, diagonal + (ca == b:sub(j, j) and 0 or 1))
      diagonal = up
    end
  end
  return row[#b]
end

-- " (did you mean 'x'?)" for the nearest name within two edits, else "".
local function did_you_mean(name, names)
  local best, distance = nil, 3
  for _, known in ipairs(names) do
    local d = edits(name, known)
    if d < distance and d < math.max(#name, #known) then best, distance = known, d end
  end
  return best and (" (did you mean '" .. best .. "'?)") or ""
end

-- A scenario's own default in the parameter's type (an integer written for a real-valued
-- parameter becomes real, so that --set upper_arm=0.7 still reads as a number), or nil and why not.
local function own_default(value, spec)
  local kind = math.type(spec.default) or type(spec.default)
  if kind == "string" or kind == "boolean" then
    if type(value) ~= kind then return nil, "must be a " .. kind .. ", got " .. type(value) end
    return value
  end
  if type(value) ~= "number" or value ~= value then
    return nil, "must be a number, got " .. (value ~= value and "nan" or type(value))
  end
  if kind == "integer" then
    value = math.tointeger(value)
    if value == nil then return nil, "must be an integer" end
  else
    value = value + 0.0
  end
  if (spec.min and value < spec.min) or (spec.max and value > spec.max) then
    return nil, ("must be within [%s, %s] (%s), got %s"):format(spec.min or "-inf", spec.max or "inf",
                                                                spec.description or "no description", value)
  end
  return value
end

-- Adds each entry of `library` to `params` (with `own` defaults for some) and returns `params`;
-- `who` and `lib` name the caller in messages. Errors are raised at the scenario's line: `level`
-- is the number of Lua frames between the scenario and this function's caller (1 when the
-- scenario calls the caller directly).
function defaults.with_params(library, params, own, who, lib, level)
  local at = (level or 1) + 1
  if type(params) ~= "table" then
    error(who .. "(params [, defaults]): params must be the scenario's table of parameters, got " .. type(params), at)
  end
  if own ~= nil and type(own) ~= "table" then
    error(who .. "(params, defaults): defaults must be a table of parameters { name = value, ... }, got " ..
          type(own), at)
  end
  local names, problems, values = sorted_names(library), {}, {}
  for _, name in ipairs(names) do
    if params[name] ~= nil then
      problems[#problems + 1] = ("the scenario's params define '%s', which is a parameter of %s: give the " ..
        "scenario's own default as %s(params, { %s = ... })"):format(name, lib, who, name)
    end
  end
  local keys = {}
  for key in pairs(own or {}) do keys[#keys + 1] = key end
  table.sort(keys, function(a, b) return tostring(a) < tostring(b) end)
  for _, name in ipairs(keys) do
    local spec = type(name) == "string" and library[name] or nil
    if spec == nil then
      problems[#problems + 1] = ("defaults: '%s' is not a parameter of %s%s; its parameters: %s"):format(
        tostring(name), lib, type(name) == "string" and did_you_mean(name, names) or "", table.concat(names, ", "))
    else
      local value, why = own_default(own[name], spec)
      if value == nil then problems[#problems + 1] = ("defaults: '%s' %s"):format(name, why)
      else values[name] = value end
    end
  end
  if #problems > 0 then error(who .. ": " .. table.concat(problems, "; "), at) end
  for _, name in ipairs(names) do
    local spec = library[name]
    if values[name] ~= nil then
      -- Every field of the library's declaration but its default (found by a probe: `list` was
      -- left out, so a default of two locked joints, or none, was refused as not one choice).
      local own_spec = {}
      for key, field in pairs(spec) do own_spec[key] = field end
      own_spec.default = values[name]
      spec = own_spec
    end
    params[name] = spec
  end
  return params
end

return defaults
