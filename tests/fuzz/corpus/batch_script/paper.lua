-- paper.lua: the paper's whole protocol (Sections III and IV), as `roger run scripts/paper.lua`.
--   Table I / Figure 3:  50 trials each of B1, DC1, DC2 on stage SG.
--   Table II / Figure 4: 50 trials each of B2, DC3, DC4, DC5, DC6 on stage T; trial i uses the
--                        Phi_SG policy of SG/DC2 trial i (the paper's footnote 3: only the DC2
--                        Phi_SG setting counts), so its SG time is that trial's.
--   Figure 5:            cumulative training time per T approach: SG (DC2) stacked under T.
--   Table III:           the final Phi_T policy of DC6 (the most restrictive context, the paper's
--                        "final Phi_T policy"), without retraining, with 3 random obstacles, on
--                        circle, triangle, pentagon and spade, 50 episodes each, for every trial.
-- docs/batch.md describes every field.
local SG_USAGE = { { context = "DC1", skill = "Phi7", subsumes = { "phi1", "phi4 <| phi2" } } }
local T_USAGE = { { context = "DC3", skill = "Phi_SG", subsumes = { "phi3", "Phi6", "Phi7" } } }

return {
  name = "paper",
  description = "Reproduction of Tables I-III and Figures 3-5 of the paper.",
  curriculum = "curricula/paper.lua",
  trials = 50,
  seed = 1,
  runs = {
    { name = "SG", stage = "SG", contexts = { "B1", "DC1", "DC2" } },
    { name = "T", stage = "T", contexts = { "B2", "DC3", "DC4", "DC5", "DC6" },
      skills = { Phi_SG = { run = "SG", context = "DC2" } } },
  },
  evaluations = {
    { name = "generalization", run = "T", context = "DC6", scenario = "cluttered",
      params = { obstacles = 3 }, shapes = { "circle", "triangle", "pentagon", "spade" }, episodes = 50 },
  },
  tables = {
    { title = "Table I: Phi_SG learning", run = "SG", baseline = "B1", usage = SG_USAGE },
    { title = "Table II: Phi_T learning", run = "T", baseline = "B2", usage = T_USAGE },
    { title = "Table III: Phi_T generalization", evaluation = "generalization" },
  },
  figures = {
    { file = "figure3", title = "Figure 3: Phi_SG learning curves", run = "SG" },
    { file = "figure4", title = "Figure 4: Phi_T learning curves", run = "T", log_x = true },
    { file = "figure5", title = "Figure 5: cumulative training time", kind = "cumulative", run = "T" },
  },
}
