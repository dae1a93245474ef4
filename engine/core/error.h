// error.h: the one exception type the engine throws for bad input. Its message is meant for the
// researcher who wrote the input: it names the file, line or field, what was expected and what exists.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace roger {

// An input or script error with a complete, human-readable message.
struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A file that could not be written or read for a reason of the machine, not of the input: a full
// disk, a folder without write permission, a script removed or changed while a run uses it. A batch
// run stops at the first one, since no trial is at fault and every later write would fail too, and
// says what to do; the same command then resumes (docs/reliability.md).
struct FileError : Error {
  // `message` is the whole text ("cannot write the policy file '<path>': No space left on device").
  FileError(const std::string& message, std::string path_in, int error_number_in)
      : Error(message), path(std::move(path_in)), error_number(error_number_in) {}
  std::string path;      // the file or folder
  int error_number = 0;  // errno (ENOSPC, EDQUOT, EACCES, EROFS, ENOENT, ...); 0 for a changed file
};

}  // namespace roger
