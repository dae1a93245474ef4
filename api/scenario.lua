---@meta
-- api/scenario.lua: what a scenario script reaches (docs/scenarios.md): roger.shape,
-- roger.robot, roger.version, and the world and rng objects its `generate` function receives.
-- A description for editors (LuaCATS, read by lua-language-server) and for the linter
-- (.luacheckrc); tests/test_lua_sandbox.cpp keeps it equal to what the sandbox registers.

---The engine's API, extended by each kind of script (docs/scenarios.md, docs/control.md,
---docs/curricula.md).
---@class roger
roger = {}

---The engine's version, e.g. "0.9.0".
---@type string
roger.version = ""

---Makes a shape: a union of convex polygons (3 to 8 vertices) and disks in the object's frame.
---@param spec roger.ShapeSpec
---@return roger.Shape
function roger.shape(spec) end

---Roger's dimensions (metres), for placement arithmetic.
---@class roger.RobotDimensions
roger.robot = {}

---Radius of Roger's base disk (0.16).
---@type number
roger.robot.base_radius = 0.16

---Radius of a hand disk (0.08).
---@type number
roger.robot.hand_radius = 0.08

---Length of the upper arm link (0.5).
---@type number
roger.robot.upper_arm = 0.5

---Length of the forearm link (0.5).
---@type number
roger.robot.forearm = 0.5

---Lateral offset of each shoulder from the base centre (0.18).
---@type number
roger.robot.shoulder_y = 0.18

---Lateral offset of each eye from the base centre (0.08).
---@type number
roger.robot.eye_y = 0.08

---A disk of this radius about the base centre holds Roger in its start posture at any heading.
---@type number
roger.robot.footprint_radius = 0.0

---A colour: {r, g, b}, {r = , g = , b = } (integers 0-255) or "#rrggbb".
---@alias roger.Colour integer[]|{r: integer, g: integer, b: integer}|string

---A point of a polygon: {x, y} or {x = , y = }.
---@alias roger.Point number[]|{x: number, y: number}

---The fields of roger.shape{...}.
---@class roger.ShapeSpec
---@field name? string used in messages (default "unnamed")
---@field polygons? roger.Point[][] convex polygons, 3 to 8 vertices each, either winding
---@field disks? {x: number?, y: number?, r: number}[] disks, r >= 0.01 m

---An immutable shape made by roger.shape (or lib/shapes.lua).
---@class roger.Shape
---@field name string the shape's name
---@field radius number bounding radius about the origin (m)
---@field area number area, parts summed (m^2)
---@field polygons number[][][] copies of the polygons, {{x, y}, ...} each
---@field disks {x: number, y: number, r: number}[] copies of the disks
local Shape = {}

---A copy scaled by `factor` > 0, optionally renamed.
---@param factor number
---@param name? string
---@return roger.Shape
function Shape:scaled(factor, name) end

---The world a scenario's `generate` builds; valid only while `generate` runs.
---@class roger.World
local World = {}

---Sets the walled arena and the planner's grid cell; call it first, if at all.
---@param spec {xmin: number?, xmax: number?, ymin: number?, ymax: number?, cell: number?, wall_colour: roger.Colour?}
function World:arena(spec) end

---The arena's extent (and fixes it, as placing something does).
---@return number xmin
---@return number xmax
---@return number ymin
---@return number ymax
function World:bounds() end

---Places Roger: base pose and start posture. Call it once.
---@param spec {x: number, y: number, heading: number?, left_shoulder: number?, left_elbow: number?, right_shoulder: number?, right_elbow: number?, left_eye: number?, right_eye: number?}
function World:robot(spec) end

---Places a movable object (what Roger searches for, grasps and transports).
---@param spec roger.ObjectSpec
function World:object(spec) end

---Places a static obstacle: it blocks motion and sight, and the planner sees it.
---@param spec {shape: roger.Shape, x: number, y: number, theta: number?, name: string?, colour: roger.Colour?}
function World:obstacle(spec) end

---Adds a circular goal region on the floor (seen by the planner and the predicates, not the eyes).
---@param spec {x: number, y: number, radius: number?, name: string?, colour: roger.Colour?}
function World:goal(spec) end

---Sets the colour the eyes track (default: the first object's).
---@param spec {colour: roger.Colour}
function World:stimulus(spec) end

---Rejection-samples a free spot for a disk, drawing from the generator's rng; returns x, y.
---@param spec roger.PlacementSpec
---@return number x
---@return number y
function World:sample_position(spec) end

---The fields of world:object{...}.
---@class roger.ObjectSpec
---@field shape roger.Shape required
---@field x number where the shape's origin goes
---@field y number
---@field theta? number orientation (rad, default 0)
---@field name? string unique among objects (default "object N")
---@field colour? roger.Colour default {220, 30, 30}
---@field mass? number kg (default 0.5)
---@field friction_force? number N: static-friction threshold against the floor (default 10)
---@field friction_torque? number N m: the same against spinning (default 1)
---@field viscosity? number 1/s: linear damping once it slides (default 1)
---@field angular_viscosity? number 1/s (default 1)
---@field surface_friction? number Coulomb coefficient against the hands and the base (default 0.8)

---The fields of world:sample_position{...}.
---@class roger.PlacementSpec
---@field radius? number the disk to fit (default 0)
---@field shape? roger.Shape stands for its bounding radius
---@field name? string for the error message (default "position")
---@field clearance? number free floor to keep around the disk (default 0.05)
---@field wall_margin? number from the walls to the centre (default radius + clearance)
---@field robot_distance? number from Roger's base centre (default 0)
---@field away_from? {x: number, y: number, distance: number, name: string?}[]
---@field avoid_goals? boolean keep clearance from goal regions (default true)
---@field region? {xmin: number?, xmax: number?, ymin: number?, ymax: number?} bounds the centre
---@field tries? integer 1 to 1000000 (default 1000)

---A portable random generator (xoshiro256**), seeded from the world's seed: all randomness
---must come from it.
---@class roger.Rng
local Rng = {}

---A number in [0, 1), or in [a, b) when given bounds.
---@param a? number
---@param b? number
---@return number
function Rng:uniform(a, b) end

---An integer in 1..n, or in a..b (inclusive) when given two bounds.
---@param a integer
---@param b? integer
---@return integer
function Rng:int(a, b) end

---A normal draw (default mu 0, sigma 1).
---@param mu? number
---@param sigma? number
---@return number
function Rng:normal(mu, sigma) end

---An angle uniform in [-pi, pi).
---@return number
function Rng:angle() end

---One element of a non-empty list, uniformly.
---@generic T
---@param list T[]
---@return T
function Rng:choice(list) end

---Shuffles the list in place and returns it.
---@generic T
---@param list T[]
---@return T[]
function Rng:shuffle(list) end

---An independent generator seeded from this one.
---@return roger.Rng
function Rng:fork() end

---A scenario parameter's long form (its short form is the default value alone).
---@class roger.ParamSpec
---@field default any required; its Lua type fixes the parameter's type
---@field description? string shown by the CLI
---@field choices? (string|number)[] allowed values
---@field min? number lower bound of a number or integer
---@field max? number upper bound

---What a scenario script returns.
---@class roger.Scenario
---@field name? string default: the file name
---@field description? string one paragraph
---@field params? table<string, any|roger.ParamSpec> defaults of the --set parameters
---@field generate fun(world: roger.World, rng: roger.Rng, params: table<string, any>) builds one world
