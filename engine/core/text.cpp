#include "core/text.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <system_error>

namespace roger {

std::string text_hash(const std::string& text) {
  uint64_t h = 1469598103934665603ull;
  for (const unsigned char ch : text) h = (h ^ ch) * 1099511628211ull;
  char b[20];
  std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(h));
  return b;
}

namespace {

// The significant digits of the shortest decimal that reads back as `value` (finite): no
// precision below it can, so format_number's search starts there.
int shortest_digits(double value) {
  char buf[40];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, value, std::chars_format::scientific);
  if (ec != std::errc()) return 1;
  int digits = 0;
  for (const char* c = buf; c != end && *c != 'e'; ++c) digits += std::isdigit(static_cast<unsigned char>(*c)) != 0;
  return std::max(1, digits);
}

}  // namespace

std::string format_number(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  // Exponent notation only for very large or small magnitudes ("10", not "1e+01").
  const bool plain = value == 0.0 || (std::abs(value) >= 1e-4 && std::abs(value) < 1e15);
  char buf[40];
  // The least precision whose %g reads back (and, in the plain range, has no exponent). Every
  // precision below the shortest decimal's digits fails, so the search starts there: the same
  // text as from 1, without up to 16 rounds of printing and reading back (they were a quarter
  // of generating a world, whose parameters and positions are all formatted).
  for (int precision = shortest_digits(value); precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, value);
    if (std::strtod(buf, nullptr) == value && (!plain || !std::strchr(buf, 'e'))) break;
  }
  return buf;
}

std::string shell_word(const std::string& s) {
  const bool plain = !s.empty() && s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                                       "0123456789_./=:,+-@%") == std::string::npos;
  if (plain) return s;
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
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

std::string json_error_text(const std::string& what) {
  static const std::string tag = "[json.exception.";
  if (what.compare(0, tag.size(), tag) != 0) return what;
  const size_t end = what.find("] ");
  return end == std::string::npos ? what : what.substr(end + 2);
}

size_t utf8_char_length(const std::string& s, size_t i) {
  const auto byte = [&](size_t k) { return k < s.size() ? static_cast<unsigned char>(s[k]) : 0u; };
  const unsigned c = byte(i);
  if (c < 0x80) return 1;
  const size_t n = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
  if (n == 0) return 0;
  for (size_t k = 1; k < n; ++k)
    if ((byte(i + k) & 0xC0) != 0x80) return 0;
  const unsigned second = byte(i + 1);
  // Overlong forms, the UTF-16 surrogates and code points past U+10FFFF.
  if ((c == 0xE0 && second < 0xA0) || (c == 0xED && second > 0x9F) || (c == 0xF0 && second < 0x90) ||
      (c == 0xF4 && second > 0x8F))
    return 0;
  return n;
}

std::string printable_text(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (size_t i = 0; i < s.size();) {
    const size_t n = utf8_char_length(s, i);
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (n > 1 || (n == 1 && (c >= 0x20 || c == '\n' || c == '\t') && c != 0x7F)) {
      out.append(s, i, n);
      i += n;
      continue;
    }
    char hex[8];
    std::snprintf(hex, sizeof hex, "\\x%02X", unsigned(c));
    out += c == 0 ? std::string("\\0") : std::string(hex);
    ++i;
  }
  return out;
}

std::string utf8_problem(const std::string& s) {
  for (size_t i = 0; i < s.size();) {
    const size_t n = utf8_char_length(s, i);
    char text[80];
    if (n == 0 || s[i] == '\0') {
      std::snprintf(text, sizeof text, "byte 0x%02x at byte %zu is %s", unsigned(static_cast<unsigned char>(s[i])),
                    i + 1, s[i] == '\0' ? "a NUL" : "not part of a UTF-8 character");
      return text;
    }
    i += n;
  }
  return "";
}

std::string shortened_text(const std::string& s, size_t max) {
  const std::string text = printable_text(s);
  if (text.size() <= max) return text;
  size_t end = 0;
  while (end < text.size()) {
    const size_t n = std::max<size_t>(1, utf8_char_length(text, end));
    if (end + n + 3 > max) break;
    end += n;
  }
  return text.substr(0, end) + "...";
}

std::string lower_ascii(std::string s) {
  for (char& c : s)
    if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
  return s;
}

std::string counted(long long n, const std::string& noun) {
  return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

size_t edit_distance(const std::string& a, const std::string& b) {
  // Three rows of the optimal-string-alignment table: two back for a swap of neighbours.
  std::vector<size_t> before(b.size() + 1), above(b.size() + 1), row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) above[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      row[j] = std::min({above[j] + 1, row[j - 1] + 1, above[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) row[j] = std::min(row[j], before[j - 2] + 1);
    }
    std::swap(before, above);
    std::swap(above, row);
  }
  return above[b.size()];
}

std::string suggestion(const std::string& given, const std::vector<std::string>& known) {
  // The same name but for case first (Phi3 for phi3), ahead of any one-letter slip (Phi6).
  auto lower = [](std::string t) {
    for (char& c : t) c = char(std::tolower(static_cast<unsigned char>(c)));
    return t;
  };
  for (const auto& k : known)
    if (k != given && lower(k) == lower(given)) return " (did you mean '" + k + "'?)";
  std::string best;
  size_t best_distance = 3;
  for (const auto& k : known) {
    const size_t d = edit_distance(given, k);
    if (d < best_distance && d < std::max(given.size(), k.size())) best = k, best_distance = d;
  }
  // A name cut short or run on by a few letters (absorb for absorbing, radiuses for radius): the
  // one known name it begins, or that begins it, of 4 letters at least (found by a probe: no hint
  // for absorb). A longer run-on is another name (noise_joints_resolution is not noise_joints).
  if (best.empty()) {
    for (const auto& k : known) {
      const std::string& shorter = k.size() < given.size() ? k : given;
      const std::string& longer = k.size() < given.size() ? given : k;
      if (shorter.size() < 4 || longer.compare(0, shorter.size(), shorter) != 0) continue;
      if (&shorter == &k && given.size() - k.size() > 3) continue;
      if (!best.empty()) return "";  // two of them: no one guess
      best = k;
    }
  }
  return best.empty() ? "" : " (did you mean '" + best + "'?)";
}

std::string name_text_problem(const std::string& name) {
  const std::string problem = utf8_problem(name);
  if (problem.empty()) return "";
  return "must be UTF-8 text (records and pages show it): in '" + printable_text(name) + "', " + problem;
}

}  // namespace roger
