-- sorting.lua: a third developmental stage after the paper's two (Figure 1): sort 2, 4 or 8 objects
-- by type, each type into its own region on the arena's edge (scenarios/sorting.lua), by using the
-- learned transport skill Phi_T again and again. Nothing here is compiled: the stage, its actions,
-- its reward and its absorbing state are this file.
--
--   roger check curricula/sorting.lua
--   roger train curricula/sorting.lua --stage T --context DC6 --seed 1 --out out/T       (trains SG first)
--   roger train curricula/sorting.lua --stage Sort2 --context Learned --seed 1 --out out/S2 \
--         --skill Phi_T=out/T/policy.json
--   roger train curricula/sorting.lua --stage Hand2 --context Scripted --seed 1 --out out/H2
--
-- How one Phi_T serves every type: roger.bind(name, skill, {stimulus = colour, region = k}) runs
-- the skill with its eyes attending to that colour (ignoring objects already let go of in region k)
-- and its goal='region' navigator delivering to region k. The learned table is the same for all
-- four bindings; only what the skill perceives and where it delivers change (docs/curricula.md).
local skills = require("lib.skills")
local paper = require("lib.paper_stages")
-- The types, their colours and regions, the carrying navigator's parameters and the sorting move
-- are lib/sorting.lua's, shared with the hand-written curricula/sort_by_hand.lua.
local sorting = require("lib.sorting")

-- Stages SG and T are the paper's (lib/paper_stages.lua: the same controllers, contexts, rewards,
-- learners and budgets), with two differences: the carrying navigator is sorting's
-- (sorting.CARRY: it converges inside a region's edge, and grows other objects less; T's worlds
-- hold one object, so only the first matters to T); and T also yields its DC6 policy as the
-- skill Phi_T.
local SG, T, c = paper.stages{ primitives = { carry = sorting.CARRY }, t_skill = "Phi_T" }
local p, Phi6, Phi7, transport = c.p, c.Phi6, c.Phi7, c.transport
local Phi_T = roger.learned("Phi_T")

-- The task's judge (Lua, at decision points): an object is sorted when its centre lies in the
-- region named after its type ("circle 3" belongs in "circle") and Roger has let go of it.
local function sorted(world)
  local n = 0
  for _, o in ipairs(world.objects) do
    if o.region ~= nil and o.region == o.name:match("^(%a+)") and not o.held then n = n + 1 end
  end
  return n, #world.objects
end

-- Absorbing: every object sorted.
local function all_sorted(state, time, world)
  local n, total = sorted(world)
  return n == total
end

-- 100 / n for each object sorted since the last decision (less for one knocked out of its region),
-- and -100 at the time-out: the return is 100 when all are sorted and 100 k / n - 100 when k of n
-- are at the time-out. Paying as objects are sorted, not all at the end, makes idling out the
-- clock worse than any try: with the k sorted paid only at the time-out, a chooser resting on a
-- type already put away with one object left kept almost all of the reward that trying the last
-- one could earn. `episode` (a table that lasts one episode) keeps the count at the last decision.
local function sorting_reward(state, action, event, time, world, episode)
  local n, total = sorted(world)
  local paid = 100 * (n - (episode.sorted or 0)) / total
  episode.sorted = n
  if event == "timeout" then return paid - 100 end
  return paid
end

-- The hand-written reference, as curricula/sort_by_hand.lua: the hand-written transport of
-- curricula/scripted.lua, converging (as a learned Phi_T does) only once the object is delivered,
-- bound to each type, the first type with something left to do run again and again. One policy
-- for every number of objects.
local scripted_SG = roger.sequence("scripted Phi_SG", { Phi6, Phi7, p.phi3 })
local scripted_carry = roger.sequence("scripted carry", { scripted_SG, transport })
local scripted_T = roger.policy("scripted Phi_T", {
  actions = { scripted_carry }, table = { ["*"] = scripted_carry }, done = skills.transported(transport),
})
local by_hand = sorting.by_hand(sorting.moves(scripted_T, { tag = " (by hand)" }))

-- The learned sorting stage: Psi is Phi_T bound to each of the four types, each run as that
-- type's task (sorting.task); the state is, per type, put away (CONV), its move gave up or saw
-- none left (NOREF), or something left to try (!CONV): 81 states whatever the number of objects.
-- The moves' NOREF is sticky: a type given up stays NOREF when retried, until it delivers again,
-- or until 30 s after its last give-up, when it shows !CONV again, worth another try (what
-- stopped it, a view blocked by another object or an object pinned by a neighbour, may have
-- cleared). With the learner's unconverged_first (below), a !CONV type is always chosen over a
-- given-up or put-away one, so the chooser goes round the types it gave up on instead of
-- retrying one until the time-out (docs/results.md, Sorting).
local learned_moves = sorting.tasks(sorting.moves(Phi_T, { sticky_noref = true, retry_after = 30 }))

-- T's learner, as in the paper, choosing among the types still on their way first.
local function sorting_learner()
  local learner = paper.learner(paper.defaults.t_alpha)
  learner.unconverged_first = true
  return learner
end

local function sorting_stage(name, n, contexts, budget)
  return roger.stage{
    name = name,
    description = "sort " .. n .. " objects by type, each into its region (Figure 1)",
    scenario = "sorting",
    params = { objects = n },
    -- 30 s per object of the world: a saved policy evaluated with another number of objects
    -- (roger eval ... --set objects=12) gets the time that number needs, as sort_by_hand does.
    time_limit = { per_object = 30 },
    absorbing = all_sorted,
    reward = sorting_reward,
    learner = sorting_learner(),
    budget = { episodes = budget },
    -- The final greedy evaluation on 50 held-out worlds, as the paper's stages: on 20, a policy that
    -- sorts 85% of all worlds reads anywhere from 75% to 95% (a standard error of 8 points).
    checkpoints = { every = math.max(1, budget // 5), episodes = 10, threshold = 0.8, seeds = 3000000,
                    stop_after = 0, final = 50 },
    contexts = contexts,
  }
end

local stages = { SG, T }
-- Training budgets of the learned sorting stages (episodes), by number of objects.
local BUDGET = { [2] = 300, [4] = 500, [8] = 1500 }
for _, n in ipairs({ 2, 4, 8 }) do
  stages[#stages + 1] = sorting_stage("Sort" .. n, n, { { name = "Learned", actions = learned_moves } }, BUDGET[n])
  stages[#stages + 1] = sorting_stage("Hand" .. n, n, { { name = "Scripted", actions = { by_hand } } }, 1)
end

return {
  name = "sorting",
  description = "Search-grasp and transport as in the paper, then sorting objects by type with Phi_T.",
  stages = stages,
}
