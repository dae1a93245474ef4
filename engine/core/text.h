// text.h: numbers and lists as text for messages and records, the same way in every layer.
#pragma once

#include <string>
#include <vector>

namespace roger {

// FNV-1a of a text, as 16 hex digits: which text a record measured (propose's candidates, the
// curriculum a policy was trained with), the same on every machine.
std::string text_hash(const std::string& text);

// Formats a number the shortest way that reads back exactly (0.95, not 0.94999999999999996).
std::string format_number(double value);

// An argument as a POSIX shell reads it back: as is when plain, else in single quotes (a command
// printed for pasting: a folder with a space or a quote in its name).
std::string shell_word(const std::string& s);

// Joins items with a separator ("a, b, c"), for messages that list what exists.
std::string join(const std::vector<std::string>& items, const char* sep = ", ");

// The message with `note` appended to its first line, before any traceback that follows it
// ("file:7: bad value (world seed 3)\nstack traceback: ..."), so the note reads with the error.
std::string with_note_on_first_line(const std::string& message, const std::string& note);

// A JSON parser's message without the library's tag: "[json.exception.parse_error.101] parse error
// at line 25, column 21: ..." reads "parse error at line 25, column 21: ...". Other text is kept.
std::string json_error_text(const std::string& what);

// Edits from a to b: insertions, deletions, substitutions, and swaps of neighbours (pirnt -> print
// is one), for the hints of messages.
size_t edit_distance(const std::string& a, const std::string& b);

// " (did you mean 'x'?)" when a known name is within two edits of the given one (and nearer than
// its length), the nearest first in `known`'s order; else "". Every message refusing an unknown
// name (a field, a parameter, a controller) adds it.
std::string suggestion(const std::string& given, const std::vector<std::string>& known);

// The length of the UTF-8 character starting at s[i] (1 to 4), or 0 when the bytes there are not
// one (a stray continuation byte, a truncated or overlong sequence, a surrogate, past U+10FFFF).
size_t utf8_char_length(const std::string& s, size_t i);

// Text a user's script produced (an error message, a value it returned), fit for a terminal and a
// JSON record: valid UTF-8 kept as it is, every byte that is not part of a character and every
// control character but newline and tab written as \xHH (a NUL as \0), so a message is never cut
// at a NUL, never refused by a JSON writer and never drives a terminal. Text without such bytes
// is returned unchanged.
std::string printable_text(const std::string& s);

// Why `s` is not UTF-8 text ("byte 0xe9 at byte 4 is not part of a UTF-8 character"; a NUL is
// refused too), or "" when it is.
std::string utf8_problem(const std::string& s);

// For a name records and pages show (a controller's, a stage's, a context's): "" when it is UTF-8
// text, else "must be UTF-8 text (records and pages show it): in '<name>', <utf8_problem>"
// (found by a probe: a controller named "search\xffgrasp" trained its whole budget, then every
// record's writer refused it).
std::string name_text_problem(const std::string& name);

// At most `max` bytes of printable_text(s), cut at a character's boundary, "..." added when cut.
std::string shortened_text(const std::string& s, size_t max);

// A count and its noun, plural when it is not 1: "1 episode", "3 episodes" (the noun's plural
// is the noun and "s").
std::string counted(long long n, const std::string& noun);

// `s` with its ASCII letters in lower case (a file extension, a keyword), other bytes as they are.
std::string lower_ascii(std::string s);

}  // namespace roger
