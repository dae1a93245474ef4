-- lib/shapes.lua: the object shapes of the paper (Figure 1) and helpers to make more.
--
-- Every shape is a roger.shape: a union of convex polygons (3 to 8 vertices) and disks in the
-- object's own frame (metres, centred near the origin). The engine validates a shape where it is
-- made, so a mistake here names this file and line. Scenarios pick a shape by name:
--
--   local shapes = require("lib.shapes")
--   local s = shapes.get(params.shape)      -- circle, pentagon, spade or triangle
--
-- All four are about the ball's size (bounding radius about 0.2 m), so the same grasp distances
-- and placement margins fit all of them.
local shapes = {}

-- The helpers' arguments, checked at the caller's line (found by a probe: a negative width made a
-- box all the same, a size written as a string passed, and a forgotten name ended in "arithmetic
-- on a nil value (local 'h')" at this file's line).
local function check_args(fn, name, sizes)
  if type(name) ~= "string" then
    error(string.format("shapes.%s: the first argument is the shape's name (a string), got %s", fn,
                        type(name) == "number" and tostring(name) or "a " .. type(name)), 3)
  end
  for _, size in ipairs(sizes) do
    local what, value = size[1], size[2]
    if math.type(value) == nil or value ~= value or value <= 0 or value == math.huge then
      error(string.format("shapes.%s('%s', ...): %s must be a number above 0 (metres), got %s", fn, name, what,
                          type(value) == "string" and string.format("%q", value) or tostring(value)), 3)
    end
  end
end

-- A disk of radius r centred on the origin.
function shapes.disk(name, r)
  check_args("disk", name, { { "r", r } })
  return roger.shape{ name = name, disks = { { r = r } } }
end

-- A regular convex polygon: n vertices (3 to 8) on a circle of radius r, the first on +x.
function shapes.regular(name, n, r)
  check_args("regular", name, { { "r", r } })
  if math.type(n) == nil or n ~= math.floor(n) or n < 3 or n > 8 then
    error(string.format("shapes.regular('%s', n, r): n is the number of vertices, an integer from 3 to 8, got %s",
                        name, tostring(n)), 2)
  end
  local vertices = {}
  for i = 0, n - 1 do
    local a = 2 * math.pi * i / n
    vertices[#vertices + 1] = { r * math.cos(a), r * math.sin(a) }
  end
  return roger.shape{ name = name, polygons = { vertices } }
end

-- A w x h rectangle centred on the origin.
function shapes.box(name, w, h)
  check_args("box", name, { { "w", w }, { "h", h } })
  local x, y = w / 2, h / 2
  return roger.shape{ name = name, polygons = { { { -x, -y }, { x, -y }, { x, y }, { -x, y } } } }
end

-- The shapes scenarios choose from by name.
shapes.library = {
  -- The paper's red ball: radius 0.2 m.
  circle = shapes.disk("circle", 0.2),
  -- Equilateral; a slightly larger circumradius than the pentagon's, since a triangle's sides sit
  -- closer to its centre (inradius 0.11 m).
  triangle = shapes.regular("triangle", 3, 0.22),
  pentagon = shapes.regular("pentagon", 5, 0.2),
  -- Non-convex, like the card suit: a triangular blade pointing to +y over two round lobes, and a
  -- flared stem below. Four convex parts that overlap; Box2D makes one fixture per part.
  spade = roger.shape{
    name = "spade",
    polygons = {
      { { -0.165, 0.02 }, { 0.165, 0.02 }, { 0.0, 0.2 } },                      -- blade tip
      { { -0.07, -0.19 }, { 0.07, -0.19 }, { 0.025, -0.07 }, { -0.025, -0.07 } }, -- stem
    },
    disks = {
      { x = -0.08, y = -0.01, r = 0.09 },  -- left lobe
      { x = 0.08, y = -0.01, r = 0.09 },   -- right lobe
    },
  },
}

-- The names in shapes.library, sorted.
function shapes.names()
  local names = {}
  for name in pairs(shapes.library) do names[#names + 1] = name end
  table.sort(names)
  return names
end

-- The library shape called `name`; an unknown name is an error at the caller's line that lists
-- the known shapes. A library step reading the scenario's `shape` parameter names itself as
-- `step`: the error is then at its caller's line, the scenario's (found by a probe: a default of
-- "hexagon" failed at lib/place.lua's line).
function shapes.get(name, step)
  local shape = shapes.library[name]
  if shape == nil and step then
    error(string.format("%s: the parameter shape is '%s', which is no shape of lib.shapes; known shapes: %s " ..
                        "(declare it with choices = shapes.names() to have it checked where it is set)",
                        step, tostring(name), table.concat(shapes.names(), ", ")), 3)
  elseif shape == nil then
    error(string.format("unknown shape '%s'; known shapes: %s", tostring(name),
                        table.concat(shapes.names(), ", ")), 2)
  end
  return shape
end

return shapes
