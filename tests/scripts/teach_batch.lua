-- teach_batch.lua: one trial of every teacher of teach_curriculum.lua, as a batch: tests/test_teach.cpp
-- runs it with --jobs 1 and --jobs 2 and checks each teacher's choices against its rule in the
-- trials' records, and that both runs are the same to the bit.
local runs = {}
for _, stage in ipairs({ "Random", "Alp", "Plr", "PlrFail", "Sequence", "Lcas", "Function", "LiftOnly" }) do
  runs[#runs + 1] = { name = stage, stage = stage, contexts = { "A" } }
end
local rows = {}
for _, run in ipairs(runs) do rows[#rows + 1] = run.name .. "/A" end
return {
  name = "teach",
  curriculum = "tests/scripts/teach_curriculum.lua",
  trials = 1,
  seed = 3,
  runs = runs,
  tables = {
    { title = "Teachers: time to 90% mastered", compare = rows },
    { title = "Teachers: final % mastered by level", compare = { "Random/A", "Alp/A" }, by = "level" },
    -- Untitled: the report makes their titles from what they show.
    { compare = { "Random/A", "Alp/A" } },
    { run = "Sequence" },
  },
  figures = {
    { file = "teachers", title = "% of the test tasks mastered", compare = rows, y = "success" },
    { file = "tasks_Alp", kind = "tasks", run = "Alp", param = "level", title = "Where ALP-GMM sampled" },
    { file = "tasks_Sequence", kind = "tasks", run = "Sequence", param = "level" },
    { file = "two_teachers", compare = { "Random/A", "Alp/A" } },
  },
}
