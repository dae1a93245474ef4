-- quick.lua: the paper's protocol in miniature (about 12 seconds on two idle cores): 2 trials per
-- context instead of 50, and 10 generalization episodes per object instead of 50. The training
-- budgets are the curriculum's own (a batch script cannot shrink them). Every table and figure of
-- scripts/paper.lua is produced, from too few trials to mean much.
--   roger run scripts/quick.lua --out results/quick
local paper = require("paper")

local quick = {}
for k, v in pairs(paper) do quick[k] = v end
quick.name = "quick"
quick.description = "A 2-trial miniature of scripts/paper.lua (for trying roger run and report)."
quick.trials = 2
quick.evaluations = {
  { name = "generalization", run = "T", context = "DC6", scenario = "cluttered",
    params = { obstacles = 3 }, shapes = { "circle", "triangle", "pentagon", "spade" }, episodes = 10 },
}
return quick
