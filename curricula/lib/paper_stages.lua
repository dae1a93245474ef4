-- lib/paper_stages.lua: the paper's two stages, search-grasp (SG) and transport (T), with all their
-- developmental contexts (lists, so that they keep this order: the tables' order), built from one
-- set of controllers. curricula/paper.lua is
-- `stages{}`; curricula/ablation.lua builds the same stages again under other learner settings,
-- so that an ablation differs from the paper in the settings it names and in nothing else.
--
--   local paper = require("lib.paper_stages")
--   local sg, t = paper.stages{}                                  -- the paper's settings
--   local sg2, t2 = paper.stages{ suffix = "_q100", initial_q = -100 } -- stages SG_q100, T_q100
local skills = require("lib.skills")

local M = {}

-- The controllers the stages are built from, for one set of primitive overrides
-- (skills.primitives). Skill names are unique within a script, so the paper's set is built once,
-- when a script first asks for it, and a script that overrides the primitives never builds it.
local function controllers(overrides)
  local p = skills.primitives(overrides)
  return {
    p = p,
    Phi6 = skills.Phi6(p),                  -- search, then track with phi0
    Phi7 = skills.Phi7(p),                  -- phi1, then phi4 <| phi2
    preshape = p.phi4:subject_to(p.phi2),   -- phi4 <| phi2
    keep = skills.keep_grasp(p),            -- phi4 <| phi5
    transport = skills.transport(p),        -- phi1 <| phi4 <| phi5 (carrying to the goal)
  }
end
local paper_controllers

-- The paper's settings (docs/results.md measures each choice):
--  * rewards +100 absorbing, -100 at the time-out, 0 otherwise; exploration falling linearly
--    from 100% to 5% over the budget (the paper's);
--  * initial_q = 0: an action never tried looks better than one that failed and worse than one
--    that reached the goal, so a trial whose greedy policy settles on a mediocre action keeps
--    trying the others. At -100 (untried = failed) 2 of 50 B2 trials sit on a plateau below the
--    threshold for their whole budget and never reach it (with earlier primitives, 7 to 9 of 50
--    B1 and 4 to 16 of 50 B2 trials did);
--  * SG trains to the end of its budget (sg_stop_after = 0), so the Phi_SG it yields has had
--    all 400 episodes; T stops after 5 consecutive passing checkpoints of one greedy policy
--    (stop_after, settle). SG stopped early, its 20 held-out checkpoint seeds cannot tell every
--    weak policy from a good one: stopped after any 5 passes, 2 SG/DC2 policies of 50 were weak
--    (88.5% on fresh seeds; one had changed in the 10 episodes before its fifth pass), after 5
--    passes of one policy 1 was (passing its checkpoints at 95%), and the DC4-DC6 trials built
--    on them stalled at 80%. Trained to the end, every DC4-DC6 trial reaches the threshold
--    (in an earlier version of the primitives one SG/DC2 policy of 50 lost its grasp choice in
--    its last 10 episodes that way, which is why stopping was tried);
--  * every action may be chosen in every state (referenced_only = false), as the paper's
--    learner: choosing only actions with a reference cuts the baselines' median times to a fifth
--    (B1) and a tenth (B2), and makes DC3 slower than B2 (docs/results.md, "Ablations");
--  * learning rates (the paper gives none), one per stage: SG 0.1 (its short greedy chains fail
--    mostly by bad luck late in training, and a slower average keeps one unlucky time-out from
--    flipping them: at 0.2 DC2 reached the threshold in 94% of trials, after B1), T 0.2 (its
--    chains of four or five decisions need the value of the goal to travel back faster: at 0.1
--    B2 reached the threshold in 1 of 10 seeds within its budget).
--
-- Two settings serve curricula that build on these stages (curricula/sorting.lua): `primitives`,
-- overrides of the primitives' parameters (false: the paper's), and `t_skill`, the name of the
-- skill stage T yields from its DC6 policy (false: none, as in the paper). `sg_params`, scenario
-- parameters of every SG context (false: none), lets a maturational curriculum learn Phi_SG with a
-- restricted body or senses and T with the full body (curricula/maturation.lua).
M.defaults = { suffix = "", initial_q = 0, sg_stop_after = 0, t_stop_after = 5, settle = true,
               referenced_only = false, sg_alpha = 0.1, t_alpha = 0.2,
               primitives = false, t_skill = false, sg_params = false }

-- The Q-learner of a stage, with learning rate `alpha` under `settings` (default: the paper's).
function M.learner(alpha, settings)
  local s = settings or M.defaults
  return { alpha = alpha, discount = 0.95, epsilon_start = 1.0, epsilon_end = 0.05, initial_q = s.initial_q,
           referenced_only = s.referenced_only }
end
local learner = M.learner

-- Settings: M.defaults overridden by the fields of `settings`.
local function with_defaults(settings)
  local s = {}
  for k, v in pairs(M.defaults) do s[k] = v end
  for k, v in pairs(settings or {}) do
    if M.defaults[k] == nil then error("paper_stages: unknown setting '" .. tostring(k) .. "'", 3) end
    s[k] = v
  end
  return s
end

-- The two stages under `settings`; their names, and the skill SG yields, end in settings.suffix.
-- Also returns the controllers they are built from (fields p, Phi6, Phi7, preshape, keep,
-- transport), for a curriculum that adds stages of its own.
function M.stages(settings)
  local s = with_defaults(settings)
  local c
  if s.primitives then
    -- A mistake in the overrides (a misspelt controller or parameter) said at the caller's line.
    local ok, made = pcall(controllers, s.primitives)
    if not ok then error((tostring(made):gsub("^[^\n]-:%d+: ", "", 1)), 2) end
    c = made
  else
    paper_controllers = paper_controllers or controllers()
    c = paper_controllers
  end
  local p, Phi6, Phi7, preshape, keep, transport = c.p, c.Phi6, c.Phi7, c.preshape, c.keep, c.transport
  local Phi_SG_name = "Phi_SG" .. s.suffix
  local sg_params = s.sg_params or nil
  -- The skill stage SG yields (its greedy policy in DC2), and Phi_STG built on it: search-grasp,
  -- then hold the grasp with phi4 <| phi5 once Phi_SG has converged.
  local Phi_SG = roger.learned(Phi_SG_name)
  local Phi_STG = skills.Phi_STG(Phi_SG, p, "Phi_STG" .. s.suffix)
  local sg = roger.stage{
    name = "SG" .. s.suffix,
    description = "search for the ball, approach it while preshaping, and grasp it",
    scenario = "unobstructed",
    time_limit = 5,
    absorbing = roger.converged(p.phi3),  -- gamma(phi3) = CONV
    reward = { absorbing = 100, timeout = -100, step = 0 },
    learner = learner(s.sg_alpha, s),
    budget = { episodes = 400 },
    checkpoints = { every = 10, episodes = 20, threshold = 0.9, seeds = 1000000, stop_after = s.sg_stop_after,
                    settle = s.settle, final = 50 },
    contexts = {
      { name = "B1",  actions = { p.phi1, p.phi3, preshape, Phi6 }, params = sg_params },
      { name = "DC1", actions = { p.phi1, p.phi3, preshape, Phi6, Phi7 }, params = sg_params },
      { name = "DC2", actions = { p.phi3, Phi6, Phi7 }, params = sg_params },
    },
    skill = { name = Phi_SG_name, context = "DC2" },
  }
  local t = roger.stage{
    name = "T" .. s.suffix,
    description = "search, grasp and carry the ball to the goal region, keeping the grasp",
    scenario = "unobstructed",
    time_limit = 10,
    -- gamma(phi1) = gamma(phi4) = gamma(phi5) = CONV: the object grasped at the goal. phi1 must be
    -- CONV itself (in the goal region), not merely settled under phi4 <| phi5 (skills.lua).
    absorbing = skills.transported(transport),
    reward = { absorbing = 100, timeout = -100, step = 0 },
    learner = learner(s.t_alpha, s),
    budget = { episodes = 1500 },
    checkpoints = { every = 10, episodes = 20, threshold = 0.9, seeds = 2000000, stop_after = s.t_stop_after,
                    settle = s.settle, final = 50 },
    contexts = {
      { name = "B2",  actions = { p.phi3, keep, Phi6, Phi7, transport } },
      { name = "DC3", actions = { p.phi3, keep, Phi6, Phi7, Phi_SG, transport } },
      { name = "DC4", actions = { Phi7, keep, Phi_SG, transport } },
      { name = "DC5", actions = { keep, Phi_SG, Phi_STG, transport } },
      { name = "DC6", actions = { Phi_STG, transport } },
    },
    skill = s.t_skill and { name = s.t_skill, context = "DC6" } or nil,
  }
  return sg, t, c
end

return M
