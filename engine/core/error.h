// error.h: the one exception type the engine throws for bad input. Its message is meant for the
// researcher who wrote the input: it names the file, line or field, what was expected and what exists.
#pragma once

#include <stdexcept>
#include <string>

namespace roger {

// An input or script error with a complete, human-readable message.
struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace roger
