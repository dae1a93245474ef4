-- teachers_example.lua: a stage whose training episodes draw their world from a task space, with a
-- teacher that picks where (docs/curricula.md, Teachers). Roger learns to find the ball and hold it
-- centred among 0 to 4 obstacles, whatever the object's shape; ALP-GMM picks each episode's task
-- where the success is changing fastest, and every checkpoint counts how many of 30 held-out tasks
-- the greedy policy masters.
--
--   roger check docs/examples/teachers_example.lua
--   roger train docs/examples/teachers_example.lua --stage Look --context Gaze --seed 1 --out out/look-tasks
local skills = require("lib.skills")
local p = skills.primitives()

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
      -- Each training episode's world: its obstacles and its object's shape, as the teacher says.
      tasks = {
        obstacles = roger.int(0, 4),
        shape = roger.choice{ "circle", "triangle", "pentagon", "spade" },
      },
      teacher = roger.teacher.alp_gmm{ fit_every = 10 },
      -- The checkpoints' measure: % of these 30 tasks (drawn once from the space) mastered.
      test = { tasks = 30, seed = 1 },
    },
  },
}
