---@meta
-- docs/api/control.lua: the control basis in Lua (docs/control.md), reached by skill scripts and
-- curricula: primitives, subject-to compositions, sequences, policies, bindings, predicates.
-- tests/test_lua_sandbox.cpp keeps it equal to what the sandbox registers.

---A controller's state (Equation 1 of the paper).
---@alias roger.GammaName "NOREF"|"!CONV"|"CONV"

---A primitive kind.
---@alias roger.PrimitiveKind "phi0"|"search"|"phi1"|"phi2"|"phi3"|"phi4"|"phi5"|"release"

---Where a controller is expected, its name works too: a named controller (defined before or
---after this line) or a primitive kind (that kind's shared default instance).
---@alias roger.ControllerRef roger.Controller|string

---A controller: a primitive, a composition, a sequence, a policy, a binding or a learned skill.
---Immutable; the same controller is the same Lua value.
---@class roger.Controller
---@field name string its name, shown in policies, pictures and messages
---@field kind string a primitive kind, "subject_to", "sequence", "policy", "binding" or "learned" (roger.learned)
---@field subordinate? roger.Controller a composition's subordinate (c2 of c2 <| c1)
---@field superior? roger.Controller a composition's superior (c1 of c2 <| c1)
---@field steps? roger.Controller[] a sequence's steps
---@field actions? roger.Controller[] a policy's actions
local Controller = {}

---A copy of this primitive with some parameters changed (and a fresh state).
---@param params table<string, number|string>
---@return roger.Controller
function Controller:with(params) end

---This controller subject to `superior` (self <| superior).
---@param superior roger.ControllerRef
---@return roger.Controller
function Controller:subject_to(superior) end

---A primitive's parameter value.
---@param name string
---@return number|string
function Controller:param(name) end

---All of a primitive's parameters, as a table.
---@return table<string, number|string>
function Controller:params() end

---A condition over controller states, evaluated in C++ every control tick. It has no fields.
---@class roger.Predicate

---A new primitive of `kind` with its default parameters, then `params` (docs/control.md,
---Primitives); `params.name` makes it a named controller.
---@param kind roger.PrimitiveKind
---@param params? table<string, number|string>
---@return roger.Controller
function roger.primitive(kind, params) end

---`sub <| sup`: sub runs in the nullspace of sup's task.
---@param sub roger.ControllerRef
---@param sup roger.ControllerRef
---@return roger.Controller
function roger.subject_to(sub, sup) end

---Parses the paper's notation ("phi1 <| phi4 <| phi5", right-associative), names looked up in
---`names`, then among named controllers, then as primitive kinds.
---@param expression string
---@param names? table<string, roger.Controller>
---@return roger.Controller
function roger.compose(expression, names) end

---A skill running its steps in order: each until it converges, falling back a step when the
---current one loses its reference (with {fall_back = false}: NOREF there instead). NOREF when
---every step is, or when the first step is running without a reference.
---@param name string
---@param steps roger.ControllerRef[]
---@param options? roger.SequenceOptions
---@return roger.Controller
function roger.sequence(name, steps, options) end

---The options of roger.sequence(name, steps, {...}).
---@class roger.SequenceOptions
---@field fall_back? boolean false: a step that loses its reference ends the sequence NOREF (default true)

---A skill mapping the state (its actions' gammas) to one of its actions by a table.
---@param name string
---@param spec roger.PolicySpec
---@return roger.Controller
function roger.policy(name, spec) end

---Runs `c` under bindings set per invocation: the stimulus colour attended to and the goal region
---its navigators deliver to.
---@param name string
---@param c roger.ControllerRef
---@param spec roger.BindSpec
---@return roger.Controller
function roger.bind(name, c, spec) end

---Holds when gamma(c) is CONV.
---@param c roger.ControllerRef
---@return roger.Predicate
function roger.converged(c) end

---Holds when gamma(c) is the given state.
---@param c roger.ControllerRef
---@param state roger.GammaName
---@return roger.Predicate
function roger.gamma(c, state) end

---Holds when every part holds (true when empty, refused as a goal or absorbing state): roger.all{p1, p2} or roger.all(p1, p2).
---@param ... roger.Predicate|roger.Predicate[]
---@return roger.Predicate
function roger.all(...) end

---Holds when some part holds (false when empty, refused as a goal or absorbing state): roger.any{p1, p2} or roger.any(p1, p2).
---@param ... roger.Predicate|roger.Predicate[]
---@return roger.Predicate
function roger.any(...) end

---Holds when `p` does not.
---@param p roger.Predicate
---@return roger.Predicate
function roger.negate(p) end

---Holds when `p` does not (the same as roger.negate).
---@param p roger.Predicate
---@return roger.Predicate
roger["not"] = function(p) end

---Holds once `p` has held without interruption for `seconds` of simulated time. A policy's goal
---or a stage's absorbing state that can first hold after its time_limit is refused at load.
---@param p roger.Predicate
---@param seconds number
---@return roger.Predicate
function roger.held(p, seconds) end

---The world's judge of a sorting task: every object whose colour is a goal region's colour lies in a
---region of its colour and is not held. With a colour, the objects of that colour alone (true when
---there is none). An object matches the region of its exact colour. In a world with objects, its
---first evaluation is an error when none of them has a region of its colour, or when no region has
---`colour`, naming the objects' and the regions' colours (a world without objects is sorted).
---@param colour? roger.Colour
---@return roger.Predicate
function roger.sorted(colour) end

---The primitive kinds, in order.
---@type roger.PrimitiveKind[]
roger.primitive_kinds = {}

---The fields of roger.policy(name, {...}).
---@class roger.PolicySpec
---@field actions roger.ControllerRef[] 1 to 12 actions
---@field table table<string, roger.ControllerRef|integer> state keys ("CONV * NOREF") to actions
---@field done? roger.ControllerRef|roger.Predicate the policy is CONV when this is
---@field fallback? roger.ControllerRef|integer|"rotate" the action of states no key matches, or "rotate": the actions in turn
---@field rest_when_done? boolean run nothing while `done` holds (default false; needs `done`)

---The fields of roger.bind(name, c, {...}).
---@class roger.BindSpec
---@field stimulus? roger.Colour the colour the eyes attend to
---@field region? integer the goal region (0 to 63) that goal = "region" navigators deliver to
---@field ignore_delivered? boolean objects already delivered to `region` are no stimulus
---@field patience? number seconds before an invocation is given up (0: no limit)
---@field sticky_noref? boolean after a NOREF, NOREF through later invocations until one converges (default false)
---@field retry_after? number seconds after its start that a NOREF is forgotten: !CONV again, worth a try (0: never)

---A time limit that grows with the world: `per_object` simulated seconds for each object
---(`time_limit = {per_object = 3}`; a skill script's policy and a curriculum's stage take it).
---@class roger.TimePerObject
---@field per_object number simulated seconds per object (> 0, at most 3600)

---A policy of a skill script.
---@class roger.SkillPolicy
---@field action roger.ControllerRef the controller to run
---@field goal roger.Predicate success ends the episode
---@field time_limit number|roger.TimePerObject simulated seconds (> 0, at most 3600), or per object of the world
---@field scenario? string scenario name or path (default "unobstructed")
---@field params? table<string, number|string|boolean> scenario parameters its episodes run with (--set overrides them)
---@field description? string

---What a skill script returns (docs/control.md).
---@class roger.SkillScript
---@field name? string default: the file name
---@field description? string
---@field policies table<string, roger.SkillPolicy> at least one
