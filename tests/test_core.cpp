// Tests of engine/core: the planar geometry every layer shares (shape.h).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "core/json_input.h"
#include "core/rng.h"
#include "core/shape.h"
#include "core/text.h"

using namespace roger;

namespace {
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
}  // namespace

TEST_CASE("Rng::integer covers any range, the full int64_t range and its ends included", "[core]") {
  // Found by a probe: hi - lo overflowed on the full range, and the compiled code divided by zero.
  Rng rng(11);
  const int64_t lo = std::numeric_limits<int64_t>::min(), hi = std::numeric_limits<int64_t>::max();
  bool negative = false, positive = false;
  for (int i = 0; i < 64; ++i) {
    const int64_t v = rng.integer(lo, hi);
    negative |= v < 0, positive |= v > 0;
  }
  CHECK((negative && positive));
  int seen_top[2] = {0, 0}, seen_bottom[2] = {0, 0};
  for (int i = 0; i < 200; ++i) {
    const int64_t t = rng.integer(hi - 1, hi), b = rng.integer(lo, lo + 1);
    REQUIRE((t == hi - 1 || t == hi));
    REQUIRE((b == lo || b == lo + 1));
    ++seen_top[t - (hi - 1)], ++seen_bottom[b - lo];
  }
  CHECK((seen_top[0] > 60 && seen_top[1] > 60 && seen_bottom[0] > 60 && seen_bottom[1] > 60));
  // An ordinary range draws as before (the trials' worlds depend on it): -3..3, uniform.
  int counts[7] = {};
  for (int i = 0; i < 7000; ++i) ++counts[rng.integer(-3, 3) + 3];
  for (int c : counts) CHECK((c > 850 && c < 1150));
}

TEST_CASE("heading_vector gives the bits of cos and sin whatever was asked before", "[core]") {
  // It remembers the last angle: asked in any order, repeated or alternating, each answer must be
  // what computing afresh gives, to the bit.
  Rng rng(3);
  std::vector<double> angles = {0.0, -0.0, M_PI, -M_PI, 1e-300, -1e-300, 1e6, 0.1, 0.1};
  for (int i = 0; i < 2000; ++i) angles.push_back(rng.uniform(-10.0, 10.0));
  for (int i = 0; i < 200; ++i) angles.push_back(angles[size_t(rng.integer(0, int(angles.size()) - 1))]);
  int mismatches = 0;
  for (double a : angles) {
    const Vec2 v = heading_vector(a);
    const double c = std::cos(a), s = std::sin(a);
    mismatches += !same_bits(v.x(), c) || !same_bits(v.y(), s);
  }
  CHECK(mismatches == 0);
  // -0 and +0 compare equal, but their sines differ in sign: the memo must keep them apart.
  heading_vector(0.0);
  CHECK(std::signbit(heading_vector(-0.0).y()));
  CHECK_FALSE(std::signbit(heading_vector(0.0).y()));
  // A NaN heading gives NaNs, not the last answer.
  heading_vector(0.3);
  const Vec2 nan = heading_vector(std::numeric_limits<double>::quiet_NaN());
  CHECK(std::isnan(nan.x()));
  CHECK(std::isnan(nan.y()));
}

TEST_CASE("heading_vector keeps one memory per thread", "[core]") {
  // Two threads asking for different angles in lockstep-free interleaving: each must get its own
  // angle's values, which a memory shared between threads would mix up.
  auto run = [](double base, int& wrong) {
    for (int i = 0; i < 20000; ++i) {
      const double a = base + 1e-3 * (i % 7);
      const Vec2 v = heading_vector(a);
      wrong += !same_bits(v.x(), std::cos(a)) || !same_bits(v.y(), std::sin(a));
    }
  };
  int wrong_a = 0, wrong_b = 0;
  std::thread a(run, 0.25, std::ref(wrong_a)), b(run, -2.5, std::ref(wrong_b));
  a.join();
  b.join();
  CHECK(wrong_a == 0);
  CHECK(wrong_b == 0);
}

TEST_CASE("to_world and to_local are inverse rigid motions", "[core]") {
  Rng rng(8);
  for (int i = 0; i < 500; ++i) {
    const Pose pose{rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0), rng.uniform(-M_PI, M_PI)};
    const Vec2 p(rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0));
    const Vec2 w = to_world(pose, p);
    // Distances from the frame's origin are kept, and the round trip returns the point.
    CHECK(std::abs((w - Vec2(pose.x, pose.y)).norm() - p.norm()) < 1e-12);
    CHECK((to_local(pose, w) - p).norm() < 1e-12);
  }
  // A quarter turn takes the body's x axis to the world's y axis.
  const Vec2 ahead = to_world(Pose{1.0, 2.0, M_PI / 2}, Vec2(1.0, 0.0));
  CHECK(ahead.x() == Approx(1.0).margin(1e-15));
  CHECK(ahead.y() == Approx(3.0));
}

TEST_CASE("with_note_on_first_line puts the note before a traceback", "[core]") {
  CHECK(roger::with_note_on_first_line("a.lua:3: bad", " (world seed 2)") == "a.lua:3: bad (world seed 2)");
  CHECK(roger::with_note_on_first_line("a.lua:3: bad\nstack traceback:\n\ta.lua:3", " (seed 2)") ==
        "a.lua:3: bad (seed 2)\nstack traceback:\n\ta.lua:3");
  CHECK(roger::with_note_on_first_line("", " (seed 2)") == " (seed 2)");
}

TEST_CASE("format_number is short and exact", "[core]") {
  CHECK(format_number(0.95) == "0.95");
  CHECK(format_number(4.0) == "4");
  CHECK(format_number(0.1 + 0.2) == "0.30000000000000004");
  CHECK(format_number(1e14) == "100000000000000");
  CHECK(format_number(1e15) == "1e+15");
  CHECK(format_number(-2.5e-5) == "-2.5e-05");
  CHECK(format_number(5e-324) == "5e-324");
}

// format_number starts its search at the shortest decimal's digits: the same text as the search
// from one digit, on numbers of every kind.
TEST_CASE("format_number gives what the search from one digit gives", "[core]") {
  const auto from_one = [](double value) {
    const bool plain = value == 0.0 || (std::abs(value) >= 1e-4 && std::abs(value) < 1e15);
    char buf[40];
    for (int precision = 1; precision <= 17; ++precision) {
      std::snprintf(buf, sizeof buf, "%.*g", precision, value);
      if (std::strtod(buf, nullptr) == value && (!plain || !std::strchr(buf, 'e'))) break;
    }
    return std::string(buf);
  };
  Rng rng(7);
  std::vector<double> values{0.0, -0.0, 1e-4, 9.9999999999999995e14, 999999999999999.9, 1e-5, 0.5, 123456789.0,
                             std::numeric_limits<double>::max(), std::numeric_limits<double>::min(),
                             std::numeric_limits<double>::denorm_min()};
  for (int i = 0; i < 40000; ++i) {
    values.push_back(rng.uniform(-10.0, 10.0));                                    // positions
    values.push_back(std::round(rng.uniform(0.0, 1e4)) / 100.0);                   // round ones
    values.push_back(std::ldexp(rng.uniform(0.5, 1.0), int(rng.uniform(-1070, 1020))));  // any magnitude
    uint64_t bits = rng.next();
    double any;
    std::memcpy(&any, &bits, sizeof any);
    if (std::isfinite(any)) values.push_back(any);
  }
  int differ = 0;
  for (double v : values)
    if (format_number(v) != from_one(v) && ++differ <= 5) FAIL_CHECK(from_one(v) + " became " + format_number(v));
  CHECK(differ == 0);
}

// A command printed for pasting (a path with a space or a quote, found by probes) reads back as
// one word in a POSIX shell.
TEST_CASE("shell_word quotes what a shell would split or expand", "[core]") {
  CHECK(shell_word("results/paper-2") == "results/paper-2");
  CHECK(shell_word("/tmp/sp dir/my scen.lua") == "'/tmp/sp dir/my scen.lua'");
  CHECK(shell_word("it's") == "'it'\\''s'");
  CHECK(shell_word("$HOME") == "'$HOME'");
  CHECK(shell_word("") == "''");
}

// Found by a probe: a result.json nesting 100,000 brackets crashed roger report, nlohmann copying
// and writing a value by recursion. The nesting is bounded where a file's JSON is read.
TEST_CASE("parse_json reads JSON as nlohmann does and refuses nesting past its bound", "[core]") {
  auto nested = [](int depth, const std::string& inside = "1") {
    return std::string(size_t(depth), '[') + inside + std::string(size_t(depth), ']');
  };
  CHECK(roger::parse_json(nested(roger::kJsonMaxDepth)) == nlohmann::json::parse(nested(roger::kJsonMaxDepth)));
  CHECK_THROWS_WITH(roger::parse_json(nested(roger::kJsonMaxDepth + 1)),
                    Catch::Contains("parse error at byte 65: nested more than 64 levels deep"));
  CHECK_THROWS_AS(roger::parse_json(nested(100000)), nlohmann::json::parse_error);
  // Brackets in strings, escaped quotes among them, are text, not nesting.
  const std::string text = "{\"a\": \"" + std::string(100, '[') + "\\\"" + std::string(100, '{') + "\"}";
  CHECK(roger::parse_json(text)["a"].get<std::string>().size() == 201);
  // Without exceptions, a discarded value, as nlohmann gives for text that does not parse.
  const std::string deep = nested(100000);
  CHECK(roger::parse_json(deep.cbegin(), deep.cend(), false).is_discarded());
  const std::string bad = "{\"a\": ";
  CHECK(roger::parse_json(bad.cbegin(), bad.cend(), false).is_discarded());
  CHECK_THROWS_AS(roger::parse_json(bad), nlohmann::json::parse_error);
}
