// json_input.h: JSON read from files a user may have edited or damaged (results, policies,
// manifests, records), parsed as nlohmann::json::parse parses them but with their nesting bounded.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace roger {

// No file roger writes nests more than a few levels; past this many the text is refused.
constexpr int kJsonMaxDepth = 64;

// nlohmann::json::parse(text), throwing its parse_error for text nested past kJsonMaxDepth levels
// too. nlohmann copies, compares and writes a value by recursion, a frame per level: a result.json
// holding 100,000 nested brackets overflowed the stack when a message quoted it (found by a
// probe). The nesting is counted on the text, before any value is built.
nlohmann::json parse_json(const std::string& text);
// The same over [first, last); with allow_exceptions false, a discarded value for text that does
// not parse or nests too deeply, as nlohmann::json::parse gives.
nlohmann::json parse_json(std::string::const_iterator first, std::string::const_iterator last,
                          bool allow_exceptions = true);

}  // namespace roger
