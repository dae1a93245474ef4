-- sorting_moves.lua: sorting moves in a row, written by hand (docs/control.md, Bindings). One
-- transport skill, bound to the red circles and their region, then to the purple spades and
-- theirs (two_moves), and on to the pentagons and triangles (four_moves, in a 4-object world).
--
--   roger eval docs/examples/sorting_moves.lua --policy two_moves --episodes 20
--   roger render docs/examples/sorting_moves.lua --policy four_moves --seed 1003 --out out/four.png
local skills = require("lib.skills")

-- The carrying navigator converges 0.25 m inside the region's edge, so the object ends inside it.
local p = skills.primitives({ carry = { depth = 0.25, margin = 0.2 } })
local transport = skills.transport(p)
local carry = roger.sequence("carry", {
  roger.sequence("search-grasp", { skills.Phi6(p), skills.Phi7(p), p.phi3 }), transport })
-- Transport converges only once the object is delivered (phi1 itself CONV, the grasp held).
local Phi_T = roger.policy("Phi_T", {
  actions = { carry }, table = { ["*"] = carry }, done = skills.transported(transport) })

-- A move: let go and back off, carry an object of `colour` to region `region`, let go and back off.
-- Given up and started over when it has not delivered within 20 s.
local function move(name, colour, region)
  local steps = roger.sequence(name .. " steps", { roger.primitive("release"), Phi_T, roger.primitive("release") })
  return roger.bind(name, steps, { stimulus = colour, region = region, patience = 20 })
end
local circle = move("sort circle", "#dc1e1e", 0)      -- region 0: "circle" (scenarios/sorting.lua)
local spade = move("sort spade", "#9628aa", 3)        -- region 3: "spade"
local pentagon = move("sort pentagon", "#e6aa14", 2)  -- region 2: "pentagon"
local triangle = move("sort triangle", "#2850dc", 1)  -- region 1: "triangle"

-- The first move not yet CONV runs, once each: these policies are for a known number of objects.
-- curricula/sort_by_hand.lua sorts any number (a move run again carries the next of its type).
local two_moves = roger.policy("two moves", {
  actions = { circle, spade },
  table = { ["* *"] = circle, ["CONV *"] = spade },
  done = spade,
})
local four_moves = roger.policy("four moves", {
  actions = { circle, spade, pentagon, triangle },
  table = { ["* * * *"] = circle, ["CONV * * *"] = spade, ["CONV CONV * *"] = pentagon,
            ["CONV CONV CONV *"] = triangle },
  done = triangle,
})

return {
  name = "sorting_moves",
  description = "Bound transport moves in a row: each object to the region of its type.",
  policies = {
    two_moves = { action = two_moves, goal = roger.converged(spade), time_limit = 60, scenario = "sorting",
                  description = "sort the circle, then the spade" },
    four_moves = { action = four_moves, goal = roger.converged(triangle), time_limit = 120, scenario = "sorting",
                   params = { objects = 4 }, description = "sort a circle, a spade, a pentagon and a triangle" },
  },
}
