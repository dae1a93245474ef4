// fuzz_support.h: what every libFuzzer harness of tests/fuzz shares.
//
// The contract a harness checks: whatever bytes a user's file holds, the reader either succeeds or
// throws roger::Error (a message for the user). A crash, an abort, a sanitizer report, a hang or any
// other exception escaping (a std::out_of_range, a nlohmann::json::type_error, ...) is a bug; the
// harness turns the last into an abort naming the exception, which libFuzzer reports as a crash.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <typeinfo>

#include "core/error.h"

namespace roger::fuzz {

// This process's scratch folder (under the system's temp folder), created on first use and removed
// when the fuzzer exits normally (after a crash it stays, with the files of the failing input).
inline const std::filesystem::path& scratch_dir() {
  struct Scratch {
    std::filesystem::path dir = std::filesystem::temp_directory_path() / ("roger_fuzz_" + std::to_string(::getpid()));
    Scratch() { std::filesystem::create_directories(dir); }
    ~Scratch() {
      std::error_code ec;
      std::filesystem::remove_all(dir, ec);
    }
  };
  static const Scratch scratch;
  return scratch.dir;
}

// Writes the fuzzer's bytes to a file, as a user's file would hold them.
inline void write_bytes(const std::filesystem::path& path, const uint8_t* data, size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
}

// Runs `read` and accepts success or roger::Error; any other exception aborts with its type and text.
template <class Read>
void expect_success_or_roger_error(Read&& read) {
  try {
    read();
  } catch (const roger::Error&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "\nnot a roger::Error: %s: %s\n", typeid(e).name(), e.what());
    std::abort();
  }
}

}  // namespace roger::fuzz
