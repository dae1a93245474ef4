-- teachers_example.lua: stages whose training episodes draw their world from a task space, with a
-- teacher that picks where (docs/curricula.md, Teachers). Roger learns to find the ball and hold it
-- centred among 0 to 4 obstacles, whatever the object's shape. In Look, ALP-GMM picks each
-- episode's task where the success is changing fastest, and every checkpoint counts how many of 30
-- held-out tasks the greedy policy masters; the other stages show each other teacher on the same
-- task (each trains in under a second). It shows the mechanics: finding the ball is one decision,
-- which the task barely changes, so the teachers' episodes succeed alike (docs/curricula.md).
--
--   roger check docs/examples/teachers_example.lua
--   roger train docs/examples/teachers_example.lua --stage Look --context Gaze --seed 1 --out out/look-tasks
local skills = require("lib.skills")
local p = skills.primitives()

-- The other stages: Look but for their name, task space, teacher and test set.
local function look(fields)
  local stage = {
    scenario = "cluttered", time_limit = 4,
    absorbing = roger.converged(p.phi0),
    learner = { alpha = 0.2, discount = 0.95, epsilon_start = 1.0, epsilon_end = 0.05 },
    budget = { episodes = 60 },
    checkpoints = { every = 20, threshold = 0.9 },
    contexts = { { name = "Gaze", actions = { p.search, p.phi0 } } },
  }
  for k, v in pairs(fields) do stage[k] = v end
  return roger.stage(stage)
end

return {
  name = "look_tasks",
  stages = {
    roger.stage{
      name = "Look", scenario = "cluttered", time_limit = 4,
      absorbing = roger.converged(p.phi0),
      learner = { alpha = 0.2, discount = 0.95, epsilon_start = 1.0, epsilon_end = 0.05 },
      budget = { episodes = 60 },
      checkpoints = { every = 20, threshold = 0.9 },
      contexts = { { name = "Gaze", actions = { p.search, p.phi0 } } },
      tasks = {                                   -- each training episode's world
        obstacles = roger.int(0, 4),
        shape = roger.choice{ "circle", "triangle", "pentagon", "spade" },
      },
      teacher = roger.teacher.alp_gmm{ fit_every = 10 },
      test = { tasks = 30, seed = 1 },            -- what "mastered" means: % of these 30 mastered
    },
    -- Domain randomization over a real axis too, measured on a list of tasks written out.
    look{
      name = "LookRandom",
      tasks = { obstacles = roger.int(0, 4), robot_distance = roger.real(0.8, 2.0) },
      teacher = roger.teacher.random{},
      test = { list = { { obstacles = 0, robot_distance = 1.0 }, { obstacles = 2, robot_distance = 1.5 },
                        { obstacles = 4, robot_distance = 2.0 } } },
    },
    -- The unobstructed world first, then up to 2 obstacles, then the whole space.
    look{
      name = "LookSequence",
      tasks = { obstacles = roger.int(0, 4) },
      teacher = roger.teacher.sequence{
        { obstacles = 0, promote = 0.5, window = 10 },
        { obstacles = roger.int(0, 2), promote = 0.5, demote = 0.1, window = 10 },
        {},
      },
      test = { tasks = 20 },
    },
    -- Lift-Constraint-Act-Saturate over the eyes (a parameter outside the space): 32, 64, then 128 pixels.
    look{
      name = "LookLcas",
      tasks = { obstacles = roger.int(0, 4) },
      teacher = roger.teacher.lcas{ lift = { eye_pixels = { 32, 64, 128 } }, window = 10, slope = 0.05 },
      test = { tasks = 20 },
    },
    -- Prioritized Level Replay: levels are (task, world seed), scored by 1 - success.
    look{
      name = "LookPlr",
      tasks = { obstacles = roger.int(0, 4) },
      teacher = roger.teacher.plr{ replay = 0.5, temperature = 0.1, staleness = 0.1, score = "success" },
      test = { tasks = 20 },
    },
    -- A teacher of your own: 2 to 4 obstacles while the last 10 episodes failed more than once.
    look{
      name = "LookFunction",
      tasks = { obstacles = roger.int(0, 4) },
      teacher = function(history, rng)
        local wins = 0
        for i = math.max(1, #history - 9), #history do
          if history[i].success then wins = wins + 1 end
        end
        if #history < 10 or wins <= 8 then return { obstacles = rng:int(2, 4) } end
        return {}                        -- anywhere: the axes left out are drawn uniformly
      end,
      test = { tasks = 20 },
    },
  },
}
