// fuzz_batch_script: arbitrary Lua source loaded as a batch script (load_batch_script, which also
// loads and checks the curriculum it names), then its configuration written and read back as the
// manifest does (batch_config_json / batch_config_from_json) and planned.
#include "batch/batch.h"
#include "fuzz_lua_script.h"
#include "script/batch/batch_script.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = roger::fuzz::lua_file("batch.lua", data, size);
  roger::fuzz::expect_success_or_roger_error([&] {
    const roger::BatchScript script = roger::load_batch_script(path, {}, roger::fuzz::fuzz_limits());
    auto reread = std::make_shared<roger::BatchScript>(roger::batch_config_from_json(roger::batch_config_json(script)));
    roger::plan_batch(std::move(reread), (roger::fuzz::scratch_dir() / "batch_out").string());
  });
  return 0;
}
