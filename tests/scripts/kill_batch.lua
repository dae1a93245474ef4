-- Fixture of the kill test (tests/kill/run_kill_test.sh) and the [faults] tests: a miniature of
-- scripts/quick.lua on kill_curriculum.lua, with every kind of trial (training, training on a
-- learned skill, evaluation) and every kind of report output (tables and figures).
return {
  name = "kill", curriculum = "kill_curriculum.lua", trials = 2, seed = 7,
  runs = {
    { name = "SG", stage = "SG", contexts = { "B1", "DC2" } },
    { name = "T", stage = "T", contexts = { "DC6" }, skills = { Phi_SG = { run = "SG", context = "DC2" } } },
  },
  evaluations = {
    { name = "gen", run = "T", context = "DC6", scenario = "cluttered", params = { obstacles = 2 },
      shapes = { "circle", "spade" }, episodes = 12 },
  },
  tables = {
    { title = "Table I", run = "SG", baseline = "B1" },
    { title = "Table II", run = "T" },
    { title = "Table III", evaluation = "gen" },
  },
  figures = {
    { file = "figure3", run = "SG" },
    { file = "figure4", run = "T", log_x = true },
    { file = "figure5", run = "T", kind = "cumulative" },
  },
}
