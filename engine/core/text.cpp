#include "core/text.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace roger {

std::string format_number(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  // Exponent notation only for very large or small magnitudes ("10", not "1e+01").
  const bool plain = value == 0.0 || (std::abs(value) >= 1e-4 && std::abs(value) < 1e15);
  char buf[40];
  for (int precision = 1; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, value);
    if (std::strtod(buf, nullptr) == value && (!plain || !std::strchr(buf, 'e'))) break;
  }
  return buf;
}

std::string join(const std::vector<std::string>& items, const char* sep) {
  std::string out;
  for (size_t i = 0; i < items.size(); ++i) out += (i ? sep : "") + items[i];
  return out;
}

std::string with_note_on_first_line(const std::string& message, const std::string& note) {
  const size_t nl = message.find('\n');
  if (nl == std::string::npos) return message + note;
  return message.substr(0, nl) + note + message.substr(nl);
}

}  // namespace roger
