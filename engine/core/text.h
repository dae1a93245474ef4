// text.h: numbers and lists as text for messages and records, the same way in every layer.
#pragma once

#include <string>
#include <vector>

namespace roger {

// Formats a number the shortest way that reads back exactly (0.95, not 0.94999999999999996).
std::string format_number(double value);

// Joins items with a separator ("a, b, c"), for messages that list what exists.
std::string join(const std::vector<std::string>& items, const char* sep = ", ");

// The message with `note` appended to its first line, before any traceback that follows it
// ("file:7: bad value (world seed 3)\nstack traceback: ..."), so the note reads with the error.
std::string with_note_on_first_line(const std::string& message, const std::string& note);

}  // namespace roger
