-- Fixture of the [faults] tests (tests/test_batch.cpp): a run per stage of faults_curriculum.lua,
-- two trials each. Only the trials of "sound" (the last phase) succeed.
return {
  name = "faults", curriculum = "faults_curriculum.lua", trials = 2, seed = 3,
  runs = {
    { name = "loop", stage = "loop", contexts = { "A" } },
    { name = "bomb", stage = "bomb", contexts = { "A" } },
    { name = "nan", stage = "nan", contexts = { "A" } },
    { name = "type", stage = "type", contexts = { "A" } },
    { name = "finalizer", stage = "finalizer", contexts = { "A" } },
    { name = "pattern", stage = "pattern", contexts = { "A" } },
    { name = "chain", stage = "chain", contexts = { "A" } },
    { name = "compare", stage = "compare", contexts = { "A" } },
    { name = "escape", stage = "escape", contexts = { "A" } },
    { name = "unlucky", stage = "unlucky", contexts = { "A" } },
    { name = "sound", stage = "sound", contexts = { "A" } },
  },
}
