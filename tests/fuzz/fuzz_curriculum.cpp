// fuzz_curriculum: arbitrary Lua source loaded as a curriculum or skill script (Curriculum::load):
// the sandbox, the control-basis bindings (engine/script/lua_control*.cpp), the curriculum's stages
// (engine/script/curriculum*.cpp) and the converters must turn every mistake into a roger::Error.
#include "fuzz_lua_script.h"
#include "script/curriculum/curriculum.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = roger::fuzz::lua_file("curriculum.lua", data, size);
  roger::fuzz::expect_success_or_roger_error([&] {
    const roger::Curriculum curriculum = roger::Curriculum::load(path, roger::fuzz::fuzz_limits());
    for (const auto& stage : curriculum.stages()) curriculum.producer(stage.name);
  });
  return 0;
}
