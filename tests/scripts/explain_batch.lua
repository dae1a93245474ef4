-- Fixture of the [explain] tests (tests/test_report.cpp): a batch of the stages of
-- explain_curriculum.lua built to fail, and one that reaches its threshold; the report says why each
-- trial missed it.
return {
  name = "explain", curriculum = "explain_curriculum.lua", trials = 1, seed = 1,
  runs = {
    { name = "L", stage = "livelock", contexts = { "A" } },
    { name = "U", stage = "unused", contexts = { "A" } },
    { name = "R", stage = "reach", contexts = { "A" } },
  },
  tables = {
    { title = "Livelock", run = "L" },
    { title = "Unused", run = "U" },
    { title = "Reach", run = "R" },
  },
}
