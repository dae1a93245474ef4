// fuzz_scenario: arbitrary Lua source loaded as a scenario script (Scenario::load, then generate()
// for two seeds): the sandbox, the world-building API (engine/script/scenario_*.cpp) and the
// Lua-value converters (engine/script/sandbox/lua_fields.cpp) must turn every mistake into a roger::Error.
#include "fuzz_lua_script.h"
#include "script/scenario/scenario.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = roger::fuzz::lua_file("scenario.lua", data, size);
  roger::fuzz::expect_success_or_roger_error([&] {
    roger::Scenario scenario = roger::Scenario::load(path, roger::fuzz::fuzz_limits());
    scenario.params();
    for (uint64_t seed : {1, 2}) scenario.generate(seed);
  });
  return 0;
}
