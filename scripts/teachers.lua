-- teachers.lua: which task teacher helps which developmental context (docs/results.md, Teachers).
--   SG/DC2:             the paper's search-grasp, whose policy is trial i's Phi_SG in every T run;
--   T_<teacher>:        the transport over both of the paper's worlds (0-6 obstacles, four shapes,
--                       near and far starts) in B2, DC3 and DC6, tasks picked by random (every task
--                       alike), sequence (the paper's order), lcas (obstacles lifted), alp (ALP-GMM)
--                       or plr (Prioritized Level Replay), all measured on the same 200 test tasks;
--   SG_eyes, SG_lcas:   search-grasp in B1 with the full eyes, or with LCAS lifting them 32 -> 64 -> 128.
-- 20 trials each: 360 trials, about 40 minutes on 2 cores; one trial per row (`--trials 1`) about 5
-- minutes on one core. `roger run scripts/teachers.lua` (resumable; docs/batch.md).
local T = { "T_random", "T_sequence", "T_lcas", "T_alp", "T_plr" }

local runs = { { name = "SG", stage = "SG", contexts = { "DC2" } } }
for _, stage in ipairs(T) do
  runs[#runs + 1] = { name = stage, stage = stage, contexts = { "B2", "DC3", "DC6" },
                      skills = { Phi_SG = { run = "SG", context = "DC2" } } }
end
runs[#runs + 1] = { name = "SG_eyes", stage = "SG_eyes", contexts = { "B1" } }
runs[#runs + 1] = { name = "SG_lcas", stage = "SG_lcas", contexts = { "B1" } }

-- The rows of one context under every teacher, random first (the baseline).
local function rows(context)
  local out = {}
  for _, stage in ipairs(T) do out[#out + 1] = stage .. "/" .. context end
  return out
end

local tables, figures = {}, {}
for _, c in ipairs({ "B2", "DC3", "DC6" }) do
  tables[#tables + 1] = { title = "Teachers in " .. c .. ": time to 90% of the test tasks mastered", compare = rows(c) }
  tables[#tables + 1] = { title = "Teachers in " .. c .. ": final % mastered by obstacles", compare = rows(c),
                          by = "obstacles" }
  figures[#figures + 1] = { file = "teachers_" .. c, title = "% of 200 test tasks mastered, " .. c,
                            compare = rows(c), y = "success", log_x = true }
  for _, stage in ipairs({ "T_sequence", "T_lcas", "T_alp", "T_plr" }) do
    figures[#figures + 1] = { file = "tasks_" .. stage .. "_" .. c, kind = "tasks", run = stage, context = c,
                              param = "obstacles", title = stage .. " in " .. c .. ": obstacles drawn" }
  end
end
tables[#tables + 1] = { title = "Search-grasp in B1: LCAS over the eyes", compare = { "SG_eyes/B1", "SG_lcas/B1" } }
figures[#figures + 1] = { file = "teachers_SG", title = "% of 200 worlds mastered, SG in B1",
                          compare = { "SG_eyes/B1", "SG_lcas/B1" }, y = "success" }

return {
  name = "teachers",
  description = "Task teachers (random, sequence, LCAS, ALP-GMM, PLR) on the paper's transport over both "
    .. "worlds in B2, DC3, DC6, and LCAS over the eyes on search-grasp.",
  curriculum = "curricula/teachers.lua",
  trials = 20,
  seed = 1,
  runs = runs,
  tables = tables,
  figures = figures,
}
