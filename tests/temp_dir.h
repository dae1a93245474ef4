// temp_dir.h: a fresh, empty scratch folder for tests that write files.
#pragma once

#include <stdlib.h>

#include <filesystem>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

namespace roger::test {

// A fresh, empty directory (named <tmp>/<prefix>_ plus six random characters by mkdtemp),
// removed with its content when the test ends.
struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& prefix = "roger_test") {
    // mkdtemp replaces the six trailing X of its template with a unique suffix.
    std::string name = (std::filesystem::temp_directory_path() / (prefix + "_XXXXXX")).string();
    REQUIRE(mkdtemp(name.data()) != nullptr);
    path = name;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  // The path of a file in the folder.
  std::string file(const std::string& name) const { return (path / name).string(); }

  // The names of what the folder holds (to check that no temporary was left behind).
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& e : std::filesystem::directory_iterator(path))
      out.push_back(e.path().filename().string());
    return out;
  }
};

}  // namespace roger::test
