-- Fixture of tests/browser/check_pages.py: a batch whose dashboard must cope with failed trials
-- (run "boom": its reward raises), a figure that cannot be drawn (no finished trial of "boom"), a
-- context name far longer than its column, curves over a short time range (0.05 to 0.15 min), and
-- contexts not in alphabetical order ("B" first).
return {
  name = "dashboard", curriculum = "dashboard_curriculum.lua", trials = 4, seed = 1,
  runs = {
    { name = "sound", stage = "sound" },
    { name = "boom", stage = "boom", trials = 2 },
  },
}
