-- Fixture of the kill test (tests/kill/run_kill_test.sh) and the [faults] tests: the paper's
-- curriculum with budgets small enough for seconds of training (20 episodes per trial, checkpoints
-- of 4 episodes, a final evaluation of 6).
local paper = require("paper")
for _, stage in ipairs(paper.stages) do
  stage.budget = { episodes = 20 }
  stage.checkpoints.every = 5
  stage.checkpoints.episodes = 4
  stage.checkpoints.final = 6
  stage.checkpoints.stop_after = 0
end
paper.name = "kill"
return paper
