-- transfer.lua: the paper's future work, measured: does a learned hierarchy carry over to another
-- body? (docs/results.md, "Transfer across bodies"). `roger run scripts/transfer.lua`.
--
--   (b) the T/DC6 policies and the Phi_SG they embed, both learned on the paper's Roger, run on
--       each of eight other bodies without retraining (evaluations b_<body>_open, b_<body>_clutter);
--   (c) the same T/DC6 policies over a Phi_SG retrained on that body, "modifying the skills which
--       make up its hierarchical control stack" and keeping the policy (SG_<body> runs, and
--       evaluations c_<body>_open, c_<body>_clutter): trial i's policy over trial i's Phi_SG;
--   (d) maturation: Phi_SG learned with coarse eyes (32 pixels over 60 degrees) or frozen eyes,
--       then T with the full body (curricula/maturation.lua), against the paper's SG/DC2 then
--       T/DC6: the T runs' tables and the cumulative figure.
-- (a), the hand-written task on each body, is `roger eval curricula/scripted.lua --policy task
-- --set ...` (docs/results.md gives the commands and the seeds).
--
-- 20 trials per setting, not the paper's 50: the 8 bodies' Phi_SG runs and 32 evaluations of 50
-- episodes per policy take 3 minutes on 2 cores (7 on a busy machine) this way.
local bodies = require("lib.bodies")

local runs = {
  { name = "SG", stage = "SG", contexts = { "DC2" } },
  { name = "T", stage = "T", contexts = { "DC6" }, skills = { Phi_SG = { run = "SG", context = "DC2" } } },
  { name = "SG_coarse", stage = "SG_coarse", contexts = { "DC2" } },
  { name = "T_coarse", stage = "T_coarse", contexts = { "DC6" },
    skills = { Phi_SG_coarse = { run = "SG_coarse", context = "DC2" } } },
  { name = "SG_frozen", stage = "SG_frozen", contexts = { "DC2" } },
  { name = "T_frozen", stage = "T_frozen", contexts = { "DC6" },
    skills = { Phi_SG_frozen = { run = "SG_frozen", context = "DC2" } } },
}
local evaluations = {}
local worlds = { open = { scenario = "unobstructed", params = {} },
                 clutter = { scenario = "cluttered", params = { obstacles = 3 } } }
for _, body in ipairs(bodies.FAMILY) do
  runs[#runs + 1] = { name = "SG_" .. body.name, stage = "SG", contexts = { "DC2" }, params = body.params }
  for _, w in ipairs({ "open", "clutter" }) do
    local params = {}
    for k, v in pairs(worlds[w].params) do params[k] = v end
    for k, v in pairs(body.params) do params[k] = v end
    evaluations[#evaluations + 1] = { name = "b_" .. body.name .. "_" .. w, run = "T", context = "DC6",
                                      scenario = worlds[w].scenario, params = params, episodes = 50 }
    evaluations[#evaluations + 1] = { name = "c_" .. body.name .. "_" .. w, run = "T", context = "DC6",
                                      scenario = worlds[w].scenario, params = params, episodes = 50,
                                      skills = { Phi_SG = { run = "SG_" .. body.name, context = "DC2" } } }
  end
end

return {
  name = "transfer",
  description = "Transfer across bodies: the paper's T/DC6 on eight bodies, with and without a retrained "
    .. "Phi_SG; maturation.",
  curriculum = "curricula/maturation.lua",
  trials = 20,
  seed = 1,
  runs = runs,
  evaluations = evaluations,
  figures = {
    { file = "maturation", title = "Maturation: SG (DC2) stacked under T (DC6)", kind = "cumulative", run = "T" },
    { file = "maturation_coarse", title = "SG with coarse eyes, then T", kind = "cumulative", run = "T_coarse" },
    { file = "maturation_frozen", title = "SG with frozen eyes, then T", kind = "cumulative", run = "T_frozen" },
  },
}
