// json_input.cpp: JSON parsed with its nesting bounded (json_input.h).
#include "core/json_input.h"

namespace roger {
namespace {

// Where the text first opens a bracket past kJsonMaxDepth levels, outside strings; npos when never.
size_t too_deep_at(std::string::const_iterator first, std::string::const_iterator last) {
  int depth = 0;
  bool in_string = false;
  for (auto it = first; it != last; ++it) {
    const char c = *it;
    if (in_string) {
      if (c == '\\' && it + 1 != last) ++it;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kJsonMaxDepth) return size_t(it - first);
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return std::string::npos;
}

}  // namespace

nlohmann::json parse_json(std::string::const_iterator first, std::string::const_iterator last, bool allow_exceptions) {
  const size_t at = too_deep_at(first, last);
  if (at != std::string::npos) {
    if (!allow_exceptions) return nlohmann::json(nlohmann::json::value_t::discarded);
    throw nlohmann::json::parse_error::create(101, at + 1,
                                              "nested more than " + std::to_string(kJsonMaxDepth) +
                                                  " levels deep (no file of roger's nests more than a few)",
                                              nullptr);
  }
  return nlohmann::json::parse(first, last, nullptr, allow_exceptions);
}

nlohmann::json parse_json(const std::string& text) { return parse_json(text.cbegin(), text.cend()); }

}  // namespace roger
