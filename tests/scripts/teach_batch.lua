-- teach_batch.lua: one trial of every teacher of teach_curriculum.lua, as a batch: tests/test_teach.cpp
-- runs it with --jobs 1 and --jobs 2 and checks each teacher's choices against its rule in the
-- trials' records, and that both runs are the same to the bit.
local runs = {}
for _, stage in ipairs({ "Random", "Alp", "Plr", "PlrFail", "Sequence", "Lcas", "Function", "LiftOnly" }) do
  runs[#runs + 1] = { name = stage, stage = stage, contexts = { "A" } }
end
return {
  name = "teach",
  curriculum = "tests/scripts/teach_curriculum.lua",
  trials = 1,
  seed = 3,
  runs = runs,
}
