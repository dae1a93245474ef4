-- Fixture of the [explain] tests (tests/test_report.cpp): a batch of the stages of
-- explain_curriculum.lua built to fail; its report says why each trial missed the threshold.
return {
  name = "explain", curriculum = "explain_curriculum.lua", trials = 1, seed = 1,
  runs = {
    { name = "L", stage = "livelock", contexts = { "A" } },
    { name = "U", stage = "unused", contexts = { "A" } },
  },
  tables = {
    { title = "Livelock", run = "L" },
    { title = "Unused", run = "U" },
  },
}
