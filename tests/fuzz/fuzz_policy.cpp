// fuzz_policy: the policy-file reader (QTable::load, engine/learn/qtable.cpp) on arbitrary bytes.
// A policy.json is read back by `roger eval --policy`, by `roger train --skill` and by batches
// that reuse a trial's policy; a hand-edited or damaged file must give a roger::Error.
#include "fuzz_support.h"
#include "learn/learning.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = roger::fuzz::scratch_dir() / "policy.json";
  roger::fuzz::write_bytes(path, data, size);
  roger::fuzz::expect_success_or_roger_error([&] {
    roger::PolicyMetadata meta;
    const roger::QTable q = roger::QTable::load(path.string(), {}, &meta);
    // A table that loads is usable: its greedy policy answers for every state.
    for (int s = 0; s < q.states(); ++s) q.policy_action(s);
  });
  return 0;
}
