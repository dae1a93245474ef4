// scenario_text.h: scenarios written by a test as Lua text, for the tests of world:robot's fields
// (test_body, test_noise). Errors name the file they were written to and its lines.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

#include "script/scenario/scenario.h"

namespace roger::test {

// A scenario of Lua `text` written to <tmp>/roger_test_<name>.lua, and loaded.
inline Scenario scenario_from(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("roger_test_" + name + ".lua");
  std::ofstream(path) << text;
  return Scenario::load(path.string());
}

// The message of loading scenario_from(name, text) and generating its seed 0, or "no error".
inline std::string generate_error(const std::string& name, const std::string& text) {
  try {
    scenario_from(name, text).generate(0);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "no error";
}

// The message of generating seed 0 of a scenario whose world:robot call is `robot` (line 2 of
// <tmp>/roger_test_<name>.lua), or "no error".
inline std::string robot_error(const std::string& name, const std::string& robot) {
  return generate_error(name, "return { generate = function(world, rng, p)\n  world:robot" + robot + "\nend }\n");
}

}  // namespace roger::test
