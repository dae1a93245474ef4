// fuzz_lua_script.h: the Lua harnesses' shared part: the fuzzer's bytes become a script file that a
// loader runs in the sandbox, with limits small enough that a runaway script stops in milliseconds.
#pragma once

#include "fuzz_support.h"
#include "script/sandbox/lua_sandbox.h"

namespace roger::fuzz {

// The sandbox limits of a fuzzed script: the real mechanism, a smaller budget.
inline SandboxLimits fuzz_limits() {
  SandboxLimits limits;
  limits.instructions = 2'000'000;
  limits.memory_bytes = 64u << 20;
  return limits;
}

// Writes the bytes as <scratch>/<name> and returns its path (a `require` then finds the shipped
// modules: scenarios/lib, curricula/lib, scripts/).
inline std::string lua_file(const char* name, const uint8_t* data, size_t size) {
  const auto path = scratch_dir() / name;
  write_bytes(path, data, size);
  return path.string();
}

}  // namespace roger::fuzz
