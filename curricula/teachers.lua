-- teachers.lua: the paper's stages under teachers that pick each training episode's task
-- (docs/curricula.md, Teachers; docs/results.md, Teachers; scripts/teachers.lua runs them).
--
-- Stage T (transport) learns over a task space spanning the paper's two worlds: 0 to 6 obstacles
-- (scenarios/cluttered.lua, which with 0 obstacles is the unobstructed world, seed for seed), the
-- four shapes, and starts from near (0.8 m between Roger and the object) to far (2 m). One stage
-- per teacher, each in the contexts B2, DC3 and DC6 of the paper, measured on the same 200
-- held-out tasks:
--   T_random    every task alike (domain randomization: no teacher beyond the space)
--   T_sequence  the paper's order: the unobstructed ball first, then up to 3 obstacles, then all
--   T_lcas      obstacles lifted 0 -> 2 -> 4 -> 6 as the success curve saturates
--   T_alp       ALP-GMM: where the absolute learning progress is
--   T_plr       PLR: replaying the levels (task and world) with the largest TD errors
-- Stage SG (search-grasp) in B1 with LCAS over the eyes (SG_lcas: 32, 64, then 128 pixels)
-- against the same stage with the full eyes throughout (SG_eyes), both measured on the same 200
-- worlds with the full eyes. Each stage is the paper's (lib/paper_stages.lua) in every other
-- respect; SG itself is the paper's, whose DC2 policy is every T trial's Phi_SG.
--
--   roger check curricula/teachers.lua
--   roger train curricula/teachers.lua --stage T_alp --context DC6 --seed 1 --out out/T-alp
local paper = require("lib.paper_stages")

local SG, T = paper.stages{}

-- A shallow copy of a stage table with some fields replaced (false: removed).
local function with(stage, fields)
  local s = {}
  for k, v in pairs(stage) do s[k] = v end
  for k, v in pairs(fields) do
    if v == false then s[k] = nil else s[k] = v end
  end
  return s
end

-- T's contexts of the comparison, in the paper's order.
local function contexts_of(stage, names)
  local out = {}
  for _, c in ipairs(stage.contexts) do
    for _, n in ipairs(names) do
      if c.name == n then out[#out + 1] = c end
    end
  end
  return out
end

-- The greedy checkpoints of a stage that teaches: every 50 training episodes on the 200 test
-- tasks (the test set replaces checkpoints.episodes and final), stopping after 3 passes of one
-- greedy policy (the paper's T checks 20 worlds every 10 episodes and stops after 5 passes; 200
-- tasks every 10 episodes would spend most of a trial evaluating).
local T_checkpoints = { every = 50, threshold = 0.9, seeds = 2000000, stop_after = 3, settle = true }

local function teach_T(name, teacher)
  return roger.stage(with(T, {
    name = "T_" .. name,
    description = "transport over the paper's two worlds, near and far starts, tasks by " .. name,
    scenario = "cluttered",
    params = false,
    skill = false,
    contexts = contexts_of(T, { "B2", "DC3", "DC6" }),
    tasks = {
      obstacles = roger.int(0, 6),
      shape = roger.choice{ "circle", "triangle", "pentagon", "spade" },
      robot_distance = roger.real(0.8, 2.0),
    },
    teacher = teacher,
    test = { tasks = 200, seed = 59 },
    checkpoints = T_checkpoints,
  }))
end

-- SG in B1 measured on 200 worlds (with the full eyes) every 20 episodes, trained to its budget.
local SG_checkpoints = { every = 20, threshold = 0.9, seeds = 1000000, stop_after = 0 }

local SG_eyes = roger.stage(with(SG, {
  name = "SG_eyes",
  description = "search-grasp in B1 with the full eyes throughout, measured on 200 worlds",
  skill = false,
  contexts = contexts_of(SG, { "B1" }),
  checkpoints = with(SG_checkpoints, { episodes = 200, final = 200 }),
}))

local SG_lcas = roger.stage(with(SG, {
  name = "SG_lcas",
  description = "search-grasp in B1, the eyes lifted from 32 to 64 to 128 pixels as learning saturates",
  skill = false,
  contexts = contexts_of(SG, { "B1" }),
  teacher = roger.teacher.lcas{ lift = { eye_pixels = { 32, 64, 128 } }, window = 25, slope = 0.05 },
  test = { tasks = 200 },
  checkpoints = SG_checkpoints,
}))

return {
  name = "teachers",
  description = "The paper's transport over both worlds and the search-grasp's eyes, under task teachers.",
  stages = {
    SG,
    teach_T("random", roger.teacher.random{}),
    -- Training success includes exploration (epsilon falls from 1 to 0.05 over the 1500 episodes):
    -- measured with random tasks, DC6 succeeds in 30-45% of its unobstructed training episodes
    -- while its greedy policy masters 96% of the test tasks, so the thresholds sit at 0.5.
    teach_T("sequence", roger.teacher.sequence{
      { obstacles = 0, shape = "circle", promote = 0.5, window = 30 },
      { obstacles = roger.int(0, 3), promote = 0.5, demote = 0.15, window = 30 },
      {},
    }),
    teach_T("lcas", roger.teacher.lcas{ lift = { obstacles = { 0, 2, 4, 6 } }, window = 50, slope = 0.05 }),
    teach_T("alp", roger.teacher.alp_gmm{}),
    teach_T("plr", roger.teacher.plr{}),
    SG_eyes,
    SG_lcas,
  },
}
