---@meta
-- docs/api/scenario.lua: what a scenario script reaches (docs/scenarios.md): roger.shape,
-- roger.robot, roger.version, and the world and rng objects its `generate` function receives.
-- A description for editors (LuaCATS, read by lua-language-server) and for the linter
-- (.luacheckrc); tests/test_lua_sandbox.cpp keeps it equal to what the sandbox registers.

---The engine's API, extended by each kind of script (docs/scenarios.md, docs/control.md,
---docs/curricula.md).
---@class roger
roger = {}

---The engine's version, e.g. "0.1.0".
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

---A disk of this radius about the base centre holds the default Roger in its start posture at any
---heading (about 0.383; another body's: roger.body_metrics{body = ...}.footprint_radius).
---@type number
roger.robot.footprint_radius = 0.38281835693315

---A servo's gains and limits (docs/scenarios.md, Bodies).
---@class roger.ServoSpec
---@field kp? number position gain (1/s), 0.01-1000
---@field max_rate? number largest rate (m/s or rad/s), 0.01-100
---@field kv? number rate gain (N/(m/s) or N m/(rad/s)), 0-1000: the base's servos alone (an arm's joint is a Box2D motor; an eye, a kinematic rate servo)
---@field max_effort? number largest force or torque (N or N m), 0-1000: the base's and the arms' servos, not the eyes

---Roger's body (world:robot's `body`); an omitted field keeps the paper's Roger.
---@class roger.BodySpec
---@field upper_arm? number upper arm length (m), 0.1-2 (0.5)
---@field forearm? number forearm length (m), 0.1-2 (0.5)
---@field base_radius? number base radius (m), 0.05-1 (0.16), and above eye_y (0.08 unless given)
---@field axle_half_width? number wheel axle half width (m), 0.02-1 (0.2)
---@field base_mass? number kg, 0.01-100 (1)
---@field link_mass? number kg per link, 0.001-100 (0.2)
---@field hand_radius? number hand radius (m), 0.01-0.3 (0.08)
---@field hand_mass? number kg, 0.001-100 (0.05)
---@field shoulder_y? number shoulders at (0, +-shoulder_y) in the base frame (m), 0-1 (0.18)
---@field eye_y? number eyes at (0, +-eye_y) (m), 0.005 to the base's radius (0.08)
---@field shoulder? {min: number?, max: number?} the left shoulder's range (rad, within +-pi; the right mirrors it)
---@field elbow? {min: number?, max: number?} the left elbow's range (rad)
---@field eye_pan? number each eye pans within +-eye_pan of the heading (rad), 0.05-pi/2
---@field friction? number Coulomb coefficient of the base and hands, 0-10 (1)
---@field servos? {base_forward: roger.ServoSpec?, base_heading: roger.ServoSpec?, eye: roger.ServoSpec?, shoulder: roger.ServoSpec?, elbow: roger.ServoSpec?}
---@field locked? ("left_eye"|"right_eye"|"left_shoulder"|"left_elbow"|"right_shoulder"|"right_elbow")[] joints held at their start angle

---Roger's eyes (world:robot's `eyes`).
---@class roger.EyesSpec
---@field pixels? integer pixels of each 1-D camera, 16-512 (128)
---@field fov? number the full field of view (rad), 0.1-2.8 (pi/2)

---One channel's noise as kinds (docs/scenarios.md, Noise): each in the channel's unit.
---@class roger.ChannelNoiseSpec
---@field sigma? number white: N(0, sigma) per component, every tick
---@field bias? number N(0, bias) per component, drawn at the episode's start and held
---@field drift? {sigma: number, tau: number} a Gauss-Markov process: stationary sigma, correlation time tau (s)
---@field delay? integer readings (effort: commands) this many control ticks late (0-50)
---@field dropout? number probability per tick that a reading (effort: a command) is lost (0-1)
---@field quantum? number readings (effort: commanded errors) rounded to multiples of this

---Roger's sensor and actuator noise (world:robot's `noise`): per channel a number (white noise's
---sigma) or a table of kinds; each channel and kind draws from its own stream seeded by the world's
---seed; a channel left out draws nothing. The controllers read the noisy senses; the judges of
---success read the true world.
---@class roger.NoiseSpec
---@field image? number|roger.ChannelNoiseSpec colour levels on each channel of each pixel of both eyes (0-255)
---@field joints? number|roger.ChannelNoiseSpec rad on each joint angle read: eye pans, shoulders, elbows (0-1)
---@field base? number|roger.ChannelNoiseSpec m on the base position and odometer, rad on its heading (0-1)
---@field touch? number|roger.ChannelNoiseSpec a fraction of each contact force (0-5)
---@field effort? number|roger.ChannelNoiseSpec a fraction of each commanded force, torque and servo rate (0-5)

---What follows from a body: the controllers' body-derived numbers (docs/control.md, Bodies).
---Reading a number it does not have is an error at that line, naming the nearest
---("roger.body_metrics(...) has no number 'footprnt_radius' (did you mean 'footprint_radius'?)").
---@class roger.BodyMetrics
---@field footprint_radius number a disk of this radius holds Roger, arms folded, at any heading (m)
---@field approach number phi1's approach ring (m)
---@field preshape_reach number phi2's reach (m)
---@field grasp_reach number phi3's reach (m)
---@field grid_inflate number the planner's obstacle growth (m)
---@field objects_growth number phi1's growth of other objects (m)
---@field squeeze number phi1's narrower growth (m)
---@field release_distance number how far release backs off (m)
---@field half_view number search's half view (rad)
---@field sidestep number search's sideways step (m)
---@field carry number the grasped object's centre ahead of the base (m)
---@field fold_shoulder number the left shoulder's fold angle (rad; the right mirrors it)
---@field fold_elbow number the left elbow's fold angle (rad)

---The numbers that follow from a body and its eyes (the default Roger's without arguments); a
---body that cannot be built is an error naming why.
---@param spec? {body: roger.BodySpec?, eyes: roger.EyesSpec?}
---@return roger.BodyMetrics
function roger.body_metrics(spec) end

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

---Places Roger: base pose, start posture (the body's folded one by default), body, eyes and noise. Call it once.
---@param spec {x: number, y: number, heading: number?, left_shoulder: number?, left_elbow: number?, right_shoulder: number?, right_elbow: number?, left_eye: number?, right_eye: number?, body: roger.BodySpec?, eyes: roger.EyesSpec?, noise: roger.NoiseSpec?}
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
---must come from it. A world's rng and its forks draw only while its generate runs.
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
---@field list? boolean true: the value is a comma-separated list of distinct `choices` (or "")

---The parameters `generate` receives: each declared parameter's value in force, by name. Reading a
---name the scenario does not declare is an error at that line, naming the nearest
---("the scenario has no parameter 'goal_raduis' (did you mean 'goal_radius'?); its parameters: ...").
---@class roger.Params: { [string]: any }

---What a scenario script returns.
---@class roger.Scenario
---@field name? string default: the file name
---@field description? string one paragraph
---@field params? table<string, any|roger.ParamSpec> defaults of the --set parameters
---@field generate fun(world: roger.World, rng: roger.Rng, params: roger.Params) builds one world
