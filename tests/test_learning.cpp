// Tests of engine/learning: Q-learning finds the optimal policy of a small synthetic MDP, the
// exploration schedule is exact, policy files round-trip bit for bit and refuse other action sets,
// the semi-MDP decides only when the state changes, a learned skill's gamma follows its absorbing
// predicate, and training on a physical stage is repeatable and improves the greedy policy.
#include <catch2/catch.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <unistd.h>

#include "control/agent.h"
#include "core/error.h"
#include "learn/decision_cycle.h"
#include "learn/learning.h"
#include "learn/warm_start.h"
#include "control/predicate.h"
#include "control/primitives.h"
#include "core/rng.h"
#include "script/scenario/scenario.h"
#include "world_fixtures.h"

using namespace roger;
using namespace roger::test;

namespace {

// A controller whose state is a given function of the tick, and whose command is a constant
// marker, so tests control exactly when the state changes and can tell which action ran.
class Scripted final : public Controller {
 public:
  Scripted(std::string name, std::function<Gamma(uint64_t)> gamma, double marker = 0.0)
      : gamma_(std::move(gamma)), marker_(marker) {
    set_name(std::move(name));
  }
  const char* kind() const override { return "scripted"; }
  // Gives the controller another script (between episodes).
  void set_script(std::function<Gamma(uint64_t)> gamma) { gamma_ = std::move(gamma); }

 protected:
  void compute(const ControlInput& in, ControlOutput& out, Gamma& gamma_raw) override {
    gamma_raw = gamma_(in.tick);
    out.command[0] = marker_;
  }

 private:
  std::function<Gamma(uint64_t)> gamma_;
  double marker_;
};

// A gamma that switches at given ticks: `states[i]` from `at[i]` (at[0] = 0) on.
std::function<Gamma(uint64_t)> piecewise(std::vector<uint64_t> at, std::vector<Gamma> states) {
  return [at, states](uint64_t tick) {
    Gamma g = states[0];
    for (size_t i = 0; i < at.size(); ++i)
      if (tick >= at[i]) g = states[i];
    return g;
  };
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// A unique temporary path for policy files.
std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("roger_test_learning_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

// Whether `f` throws roger::Error with a message containing every one of `parts`.
bool throws_with(const std::function<void()>& f, const std::vector<std::string>& parts) {
  try {
    f();
  } catch (const Error& e) {
    const std::string m = e.what();
    for (const auto& p : parts)
      if (m.find(p) == std::string::npos) {
        UNSCOPED_INFO("message: " << m << " lacks \"" << p << "\"");
        return false;
      }
    return true;
  }
  return false;
}

Gamma G(int g) { return Gamma(g); }

}  // namespace

TEST_CASE("QParams are validated with the field named", "[learning]") {
  QParams ok;
  CHECK_NOTHROW(ok.validate());
  const std::vector<std::pair<std::string, std::function<void(QParams&)>>> bad = {
      {"alpha", [](QParams& p) { p.alpha = 0.0; }},
      {"alpha", [](QParams& p) { p.alpha = 1.5; }},
      {"discount", [](QParams& p) { p.discount = -0.1; }},
      {"discount", [](QParams& p) { p.discount = std::nan(""); }},
      {"epsilon_start", [](QParams& p) { p.epsilon_start = 2.0; }},
      {"epsilon_end", [](QParams& p) { p.epsilon_end = -1.0; }},
      {"initial_q", [](QParams& p) { p.initial_q = INFINITY; }},
  };
  for (const auto& [field, spoil] : bad) {
    QParams p;
    spoil(p);
    CHECK(throws_with([&] { p.validate("stage X"); }, {"stage X", field}));
    CHECK_THROWS_AS(QTable({"a"}, p), Error);
  }
  CHECK_THROWS_AS(QTable({}), Error);
  CHECK_THROWS_AS(QTable(std::vector<std::string>(13, "x")), Error);
  CHECK_THROWS_AS(QTable({"a", "a"}), Error);
  CHECK(QTable({"a", "b", "c"}).states() == 27);
}

TEST_CASE("Q-learning finds the optimal policy of a synthetic combination lock", "[learning]") {
  // Five states in a chain; in state i only action code[i] moves on (to i + 1, or to the +100
  // terminal from the last one); the other actions stay put. 30 steps without reaching the end is
  // a -100 time-out. The optimal policy is unique: code[i] in every state.
  const std::vector<int> code = {2, 0, 1, 1, 2};
  const int chain = int(code.size()), limit = 30;
  QTable q({"a", "b", "c"});
  Rng rng(12345);
  const int episodes = 400, budget = 300;
  const ExplorationSchedule schedule = ExplorationSchedule::episodes(q.params(), budget);
  auto run = [&](double epsilon, bool learn) {
    int s = 0;
    for (int step = 0; step < limit; ++step) {
      const int a = learn ? q.choose(s, epsilon, rng) : q.greedy(s);
      const int next = a == code[size_t(s)] ? s + 1 : s;
      if (next == chain) {
        if (learn) q.update(s, a, 100.0, s, true, q.params().discount);
        return true;
      }
      if (learn) {
        const bool timeout = step + 1 == limit;
        q.update(s, a, timeout ? -100.0 : 0.0, next, timeout, q.params().discount);
      }
      s = next;
    }
    return false;
  };
  int late_successes = 0;
  for (int e = 0; e < episodes; ++e) {
    const bool ok = run(schedule.epsilon(e), true);
    if (e >= episodes - 50) late_successes += ok;
  }
  CHECK(late_successes >= 40);
  for (int s = 0; s < chain; ++s) {
    INFO("state " << s << ": Q = " << q.value(s, 0) << ", " << q.value(s, 1) << ", " << q.value(s, 2));
    CHECK(q.visited(s));
    CHECK(q.greedy(s) == code[size_t(s)]);
    CHECK(q.policy_action(s) == code[size_t(s)]);
  }
  CHECK_FALSE(q.visited(chain));  // a state index the chain never reaches
  CHECK(run(0.0, false));          // the greedy policy opens the lock
}

TEST_CASE("QTable basics: ties, epsilon-greedy, the backup and the nearest visited state", "[learning]") {
  QTable q({"a", "b", "c"}, QParams{0.5, 0.9, 1.0, 0.05, 0.0});
  // Ties go to the lowest index.
  CHECK(q.greedy(4) == 0);
  q.set(4, 2, 1.0);
  q.set(4, 1, 1.0);
  CHECK(q.greedy(4) == 1);
  CHECK_FALSE(q.visited(4));
  // epsilon 0 is greedy and draws nothing; epsilon 1 is uniform over the actions.
  Rng rng(1), copy(1);
  CHECK(q.choose(4, 0.0, rng) == 1);
  CHECK(rng.next() == copy.next());
  int counts[3] = {0, 0, 0};
  for (int i = 0; i < 3000; ++i) ++counts[q.choose(4, 1.0, rng)];
  for (int c : counts) CHECK(c > 850);
  // The backup: Q += alpha (r + d max Q(s') - Q), TD error returned; terminal drops the bootstrap.
  q.set(7, 0, 10.0);
  const double td = q.update(3, 1, 2.0, 7, false, 0.81);
  CHECK(td == Approx(2.0 + 0.81 * 10.0));
  CHECK(q.value(3, 1) == Approx(0.5 * (2.0 + 8.1)));
  CHECK(q.visits(3, 1) == 1);
  CHECK(q.visited(3));
  const double td2 = q.update(3, 1, -1.0, 7, true, 0.81);
  CHECK(td2 == Approx(-1.0 - 5.05));
  CHECK(q.visits(3, 1) == 2);
  CHECK_THROWS_AS(q.update(27, 0, 0.0, 0, true, 0.9), Error);
  CHECK_THROWS_AS(q.update(0, 0, 0.0, 0, true, 1.5), Error);

  // policy_action: an unvisited state borrows the greedy action of the nearest visited state.
  QTable p({"x", "y"});  // states: index = 3 g_x + g_y
  const int conv_noref = gamma_state_index({Gamma::kConv, Gamma::kNoRef});    // 6
  const int conv_conv = gamma_state_index({Gamma::kConv, Gamma::kConv});      // 8
  const int noref_noref = gamma_state_index({Gamma::kNoRef, Gamma::kNoRef});  // 0
  CHECK(p.policy_action(conv_conv) == 0);  // nothing visited: plain greedy
  p.update(conv_noref, 1, 5.0, conv_noref, true, 0.9);
  p.update(noref_noref, 0, 5.0, noref_noref, true, 0.9);
  CHECK(p.greedy(conv_conv) == 0);
  // (CONV, CONV) is 2 from (CONV, NOREF) and 4 from (NOREF, NOREF).
  CHECK(p.policy_action(conv_conv) == 1);
  CHECK(p.policy_action(gamma_state_index({Gamma::kNotConv, Gamma::kNoRef})) == 0);  // tie: lower index
}

TEST_CASE("an action whose controller has no reference is never chosen, explored or backed up from", "[learning]") {
  // The paper's Eq. 1: a controller's gradient may be engaged only where gamma != NOREF.
  QParams on;
  on.referenced_only = true;
  QTable q({"x", "y", "z"}, on);
  const int s = gamma_state_index({Gamma::kNoRef, Gamma::kNotConv, Gamma::kConv});
  q.set(s, 0, 50.0);  // the best value, on the action without a reference
  q.set(s, 1, 1.0);
  q.set(s, 2, 2.0);
  CHECK_FALSE(q.engageable(s, 0));
  CHECK(q.engageable(s, 1));
  CHECK(q.greedy(s) == 2);
  CHECK(q.max_value(s) == 2.0);
  CHECK(q.policy_action(s) == 2);
  Rng rng(3);
  int counts[3] = {0, 0, 0};
  for (int i = 0; i < 2000; ++i) ++counts[q.choose(s, 1.0, rng)];
  CHECK(counts[0] == 0);
  CHECK(counts[1] > 850);
  CHECK(counts[2] > 850);
  // The bootstrap of a backup into s takes its best engageable value, not the 50.
  const int t = gamma_state_index({Gamma::kConv, Gamma::kConv, Gamma::kConv});
  CHECK(q.update(t, 1, 0.0, s, false, 0.5) == Approx(0.5 * 2.0));
  // Every action NOREF: every action may run (something must).
  const int none = gamma_state_index({Gamma::kNoRef, Gamma::kNoRef, Gamma::kNoRef});
  for (int a = 0; a < 3; ++a) CHECK(q.engageable(none, a));
  // An unvisited state borrows the nearest visited state's values, among its own engageable
  // actions: t was visited (action 1); from (CONV, NOREF, CONV) action 1 has no reference.
  q.set(t, 1, 10.0);
  q.set(t, 0, 5.0);
  const int u = gamma_state_index({Gamma::kConv, Gamma::kNoRef, Gamma::kConv});
  CHECK(q.policy_action(u) == 0);
  // Off (the default, the paper's learner), the same table chooses the 50.
  QTable o({"x", "y", "z"});
  o.set(s, 0, 50.0);
  CHECK(o.greedy(s) == 0);
}

TEST_CASE("while some action is still on its way, a converged or unreferenced one is never chosen", "[learning]") {
  // unconverged_first: a CONV controller is at its attractor and a NOREF one has no reference;
  // only a !CONV one has work to do.
  QParams on;
  on.unconverged_first = true;
  QTable q({"x", "y", "z"}, on);
  const int s = gamma_state_index({Gamma::kNoRef, Gamma::kNotConv, Gamma::kConv});
  q.set(s, 0, 50.0);  // the best values, on the actions without work
  q.set(s, 1, 1.0);
  q.set(s, 2, 40.0);
  CHECK_FALSE(q.engageable(s, 0));
  CHECK(q.engageable(s, 1));
  CHECK_FALSE(q.engageable(s, 2));
  CHECK(q.greedy(s) == 1);
  CHECK(q.max_value(s) == 1.0);
  CHECK(q.policy_action(s) == 1);
  Rng rng(5);
  for (int i = 0; i < 200; ++i) CHECK(q.choose(s, 1.0, rng) == 1);
  // The bootstrap of a backup into s takes the !CONV action's value.
  const int t = gamma_state_index({Gamma::kConv, Gamma::kConv, Gamma::kConv});
  CHECK(q.update(t, 1, 0.0, s, false, 0.5) == Approx(0.5 * 1.0));
  // No action on its way: every action may run, or with referenced_only as well, those with a
  // reference.
  const int rest = gamma_state_index({Gamma::kNoRef, Gamma::kConv, Gamma::kConv});
  for (int a = 0; a < 3; ++a) CHECK(q.engageable(rest, a));
  QParams both = on;
  both.referenced_only = true;
  QTable b({"x", "y", "z"}, both);
  CHECK_FALSE(b.engageable(rest, 0));
  CHECK(b.engageable(rest, 1));
  CHECK(b.engageable(s, 1));
  CHECK_FALSE(b.engageable(s, 2));
  // Off (the default, the paper's learner), the same table chooses the 50.
  QTable o({"x", "y", "z"});
  o.set(s, 0, 50.0);
  CHECK(o.greedy(s) == 0);
}

TEST_CASE("the exploration schedule is exact at both ends and linear between", "[learning]") {
  const QParams params;  // 1.0 -> 0.05
  const ExplorationSchedule s = ExplorationSchedule::episodes(params, 100);
  CHECK(s.unit() == BudgetUnit::kEpisodes);
  CHECK(s.epsilon(0) == 1.0);
  CHECK(s.epsilon(-3) == 1.0);
  CHECK(s.epsilon(100) == 0.05);
  CHECK(s.epsilon(101) == 0.05);
  CHECK(s.epsilon(1e9) == 0.05);
  CHECK(s.epsilon(50) == Approx(0.525).epsilon(1e-12));
  CHECK(s.epsilon(25) == Approx(1.0 - 0.95 * 0.25).epsilon(1e-12));
  // Linear: equal steps fall by equal amounts, and never outside [end, start].
  for (int e = 1; e < 100; ++e) {
    CHECK(s.epsilon(e) - s.epsilon(e + 1) == Approx(0.0095).margin(1e-12));
    CHECK(s.epsilon(e) <= 1.0);
    CHECK(s.epsilon(e) >= 0.05);
  }
  const ExplorationSchedule t = ExplorationSchedule::sim_seconds(params, 3600.0);
  CHECK(t.unit() == BudgetUnit::kSimSeconds);
  CHECK(t.epsilon(0.0) == 1.0);
  CHECK(t.epsilon(3600.0) == 0.05);
  CHECK(t.epsilon(7200.0) == 0.05);
  CHECK(t.epsilon(1800.0) == Approx(0.525).epsilon(1e-12));
  CHECK_THROWS_AS(ExplorationSchedule::episodes(params, 0), Error);
  CHECK_THROWS_AS(ExplorationSchedule(1.0, 0.05, -1.0), Error);
  CHECK_THROWS_AS(ExplorationSchedule(1.5, 0.05, 10.0), Error);
}

TEST_CASE("a QTable round-trips through a policy file bit for bit", "[learning]") {
  QParams params;
  params.alpha = 0.1 + 0.2;  // not a short decimal
  params.discount = 1.0 / 3.0;
  params.initial_q = -0.0;
  params.referenced_only = true;  // not the default
  params.unconverged_first = true;  // nor this
  QTable q({"search", "phi0", "phi4 <| phi2"}, params);
  Rng rng(99);
  // Values with awkward binary expansions, extremes and subnormals, plus real backups.
  const double awkward[] = {0.1, 1.0 / 3.0, -2.0 / 7.0, 1e-300, 4.9406564584124654e-324,
                            1.7976931348623157e308, -123456.789012345678, 100.0, -0.0};
  int k = 0;
  for (int s = 0; s < q.states(); s += 2)
    for (int a = 0; a < q.actions(); ++a) q.set(s, a, awkward[k++ % 9] * (0.5 + 0.5 * rng.uniform()));
  for (int i = 0; i < 200; ++i)
    q.update(int(rng.integer(0, 26)), int(rng.integer(0, 2)), rng.uniform(-100, 100),
             int(rng.integer(0, 26)), rng.uniform() < 0.2, q.params().discount);
  PolicyMetadata meta;
  meta.stage = "search_grasp";
  meta.context = "DC1";
  meta.seed = 18446744073709551557ull;  // above INT64_MAX
  meta.extra = {{"episodes", 200}, {"note", "test"}};
  const std::string path = temp_path("roundtrip.json");
  q.save(path, meta);
  // The write is atomic: nothing but the file itself is left beside it.
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(path).parent_path()))
    CHECK(entry.path().string().find(path + ".tmp") == std::string::npos);

  PolicyMetadata back;
  const QTable r = QTable::load(path, q.action_names(), &back);
  CHECK(r.action_names() == q.action_names());
  CHECK(same_bits(r.params().alpha, q.params().alpha));
  CHECK(same_bits(r.params().discount, q.params().discount));
  CHECK(same_bits(r.params().initial_q, q.params().initial_q));
  CHECK(same_bits(r.params().epsilon_start, q.params().epsilon_start));
  CHECK(same_bits(r.params().epsilon_end, q.params().epsilon_end));
  CHECK(r.params().referenced_only == q.params().referenced_only);
  CHECK(r.params().unconverged_first == q.params().unconverged_first);
  // A file from before referenced_only and unconverged_first existed was learned with every
  // action allowed.
  {
    std::ifstream in(path);
    nlohmann::json old = nlohmann::json::parse(in);
    old["params"].erase("referenced_only");
    old["params"].erase("unconverged_first");
    const std::string old_path = temp_path("roundtrip_old.json");
    std::ofstream(old_path) << old.dump();
    const QTable o = QTable::load(old_path, q.action_names());
    CHECK_FALSE(o.params().referenced_only);
    CHECK_FALSE(o.params().unconverged_first);
    std::filesystem::remove(old_path);
  }
  int differing = 0;
  for (int s = 0; s < q.states(); ++s) {
    CHECK(r.visited(s) == q.visited(s));
    for (int a = 0; a < q.actions(); ++a) {
      differing += !same_bits(r.value(s, a), q.value(s, a));
      differing += r.visits(s, a) != q.visits(s, a);
    }
  }
  CHECK(differing == 0);
  CHECK(back.stage == "search_grasp");
  CHECK(back.context == "DC1");
  CHECK(back.seed == meta.seed);
  CHECK(back.extra == meta.extra);
  // Saving again gives the same text: a second round trip changes nothing.
  const std::string path2 = temp_path("roundtrip2.json");
  r.save(path2, back);
  auto slurp = [](const std::string& p) {
    std::ifstream in(p);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  CHECK(slurp(path) == slurp(path2));
  // An empty expectation accepts the file's own actions.
  CHECK(QTable::load(path, {}).action_names() == q.action_names());
  std::filesystem::remove(path2);

  // Another action set, order or count is refused, naming the file and the field.
  CHECK(throws_with([&] { QTable::load(path, {"search", "phi0", "phi7"}); }, {path, "actions", "phi7"}));
  CHECK(throws_with([&] { QTable::load(path, {"phi0", "search", "phi4 <| phi2"}); }, {path, "actions"}));
  CHECK(throws_with([&] { QTable::load(path, {"search", "phi0"}); }, {path, "actions"}));

  // Damaged files: each problem names the file and the field.
  nlohmann::json good = q.to_json(meta);
  auto damaged = [&](const std::function<void(nlohmann::json&)>& spoil) {
    nlohmann::json j = good;
    spoil(j);
    const std::string p = temp_path("damaged.json");
    std::ofstream(p) << j.dump();
    return p;
  };
  const std::vector<std::pair<std::string, std::function<void(nlohmann::json&)>>> cases = {
      {"\"q\"", [](nlohmann::json& j) { j.erase("q"); }},
      {"\"visits\"", [](nlohmann::json& j) { j.erase("visits"); }},
      {"\"params\"", [](nlohmann::json& j) { j.erase("params"); }},
      {"alpha", [](nlohmann::json& j) { j["params"].erase("alpha"); }},
      {"alpha", [](nlohmann::json& j) { j["params"]["alpha"] = 3.0; }},
      {"\"q\"", [](nlohmann::json& j) { j["q"].erase(j["q"].size() - 1); }},
      {"\"q\" row 5", [](nlohmann::json& j) { j["q"][5].push_back(1.0); }},
      {"\"q\" [2][1]", [](nlohmann::json& j) { j["q"][2][1] = "x"; }},
      {"\"visits\" [3][0]", [](nlohmann::json& j) { j["visits"][3][0] = -1; }},
      {"\"format\"", [](nlohmann::json& j) { j["format"] = "other"; }},
      {"\"version\"", [](nlohmann::json& j) { j["version"] = 2; }},
      {"\"stage\"", [](nlohmann::json& j) { j.erase("stage"); }},
      {"\"seed\"", [](nlohmann::json& j) { j["seed"] = -4; }},
  };
  for (const auto& [what, spoil] : cases) {
    const std::string p = damaged(spoil);
    INFO(what);
    CHECK(throws_with([&] { QTable::load(p, q.action_names()); }, {p, what}));
    std::filesystem::remove(p);
  }
  {
    const std::string p = temp_path("notjson.json");
    std::ofstream(p) << "{ \"format\": ";
    CHECK(throws_with([&] { QTable::load(p, {}); }, {p, "JSON", ": parse error at line 1, column 13"}));
    // The parser's own tag is the library's detail, not the user's (found by a probe).
    try {
      QTable::load(p, {});
    } catch (const Error& e) {
      CHECK_THAT(e.what(), !Catch::Matchers::Contains("json.exception"));
    }
    std::filesystem::remove(p);
  }
  {
    // Valid JSON syntax, but a number beyond double (found by tests/fuzz/fuzz_policy): nlohmann
    // throws out_of_range, not parse_error; the reader still says which file is not valid JSON.
    const std::string p = temp_path("overflow.json");
    std::ofstream(p) << "{ \"format\": \"roger-policy\", \"version\": 1e999 }";
    CHECK(throws_with([&] { QTable::load(p, {}); }, {p, "JSON", "1e999"}));
    std::filesystem::remove(p);
  }
  CHECK(throws_with([&] { QTable::load(temp_path("missing.json"), {}); }, {"missing.json: no such file"}));
  std::filesystem::remove(path);
}

// Found by a probe: a context of 12 actions wrote a 98 MB policy.json of 531441 default rows, and
// the next stage, which embeds it, 157 MB. Past 3^6 states a file holds only the rows that hold
// something, keyed by state; it reads back to the same table, as does the full list of rows.
TEST_CASE("a large QTable's file holds only the rows that hold something, and reads back the same", "[learning]") {
  QParams params;
  params.initial_q = 0.5;
  std::vector<std::string> names;
  for (int a = 0; a < 7; ++a) names.push_back("a" + std::to_string(a));
  QTable q(names, params);
  REQUIRE(q.states() == 2187);
  Rng rng(5);
  for (int i = 0; i < 40; ++i)
    q.update(int(rng.integer(0, 2186)), int(rng.integer(0, 6)), rng.uniform(-100, 100), int(rng.integer(0, 2186)),
             false, 0.9);
  q.set(2186, 3, 1.0 / 3.0);  // a value without a visit (as a warm start writes) is a row too
  PolicyMetadata meta;
  meta.stage = "S", meta.context = "C";
  const nlohmann::json j = q.to_json(meta);
  REQUIRE(j["q"].is_object());
  CHECK(j["q"].size() <= 41);
  CHECK(j["q"].contains("2186"));
  const std::string path = temp_path("sparse.json");
  std::ofstream(path) << j.dump();
  const QTable back = QTable::load(path, names);
  const auto same = [&](const QTable& t) {
    for (int s = 0; s < q.states(); ++s) {
      if (t.visited(s) != q.visited(s)) return false;
      for (int a = 0; a < q.actions(); ++a)
        if (t.value(s, a) != q.value(s, a) || t.visits(s, a) != q.visits(s, a)) return false;
    }
    return true;
  };
  CHECK(same(back));
  // Every row as a list, as a file of a small table is written, reads the same.
  nlohmann::json dense = j;
  dense["q"] = nlohmann::json::array(), dense["visits"] = nlohmann::json::array();
  for (int s = 0; s < q.states(); ++s) {
    nlohmann::json qrow = nlohmann::json::array(), vrow = nlohmann::json::array();
    for (int a = 0; a < q.actions(); ++a) qrow.push_back(q.value(s, a)), vrow.push_back(q.visits(s, a));
    dense["q"].push_back(qrow), dense["visits"].push_back(vrow);
  }
  std::ofstream(path) << dense.dump();
  CHECK(same(QTable::load(path, names)));
  // A key that is no state, and rows of the two fields for other states, are refused by name.
  nlohmann::json bad = j;
  bad["q"]["2187"] = bad["q"].begin().value();
  std::ofstream(path) << bad.dump();
  CHECK(throws_with([&] { QTable::load(path, names); }, {path, "field \"q\" is keyed by state (0 to 2186", "\"2187\""}));
  bad = j;
  bad["visits"].erase("2186");
  std::ofstream(path) << bad.dump();
  CHECK(throws_with([&] { QTable::load(path, names); }, {path, "fields \"q\" and \"visits\" must hold the same states"}));
  std::filesystem::remove(path);
}

TEST_CASE("the semi-MDP decides when the state changes, and at no other tick", "[learning]") {
  SECTION("scripted controllers") {
    // A: NOREF, then !CONV at 10, CONV at 40, !CONV at 70. B: !CONV, CONV at 25, !CONV at 55.
    auto a = std::make_shared<Scripted>("A", piecewise({0, 10, 40, 70}, {G(0), G(1), G(2), G(1)}));
    auto b = std::make_shared<Scripted>("B", piecewise({0, 25, 55}, {G(1), G(2), G(1)}));
    auto never = std::make_shared<Scripted>("never", [](uint64_t) { return Gamma::kNotConv; });
    const std::vector<ControllerPtr> psi = {a, b};
    PredicatePtr absorbing = converged(never);
    QTable q(controller_names(psi));
    Agent agent;
    Rng rng(5);
    LearningEpisodeOptions options;
    options.time_limit = 2.0;  // 100 ticks
    const TrainingEpisode ep =
        run_learning_episode(agent, open_world(false), 3, psi, *absorbing, q, 1.0, rng, options, true);
    CHECK(ep.ticks == 100);
    CHECK_FALSE(ep.success);
    CHECK(ep.reward == -100.0);
    CHECK(ep.sim_seconds == Approx(2.0));
    // The states each tick as the script defines them, and their changes.
    std::vector<int> expected_states;
    int previous = -1;
    for (uint64_t t = 0; t < 100; ++t) {
      const int s = gamma_state_index({piecewise({0, 10, 40, 70}, {G(0), G(1), G(2), G(1)})(t),
                                       piecewise({0, 25, 55}, {G(1), G(2), G(1)})(t)});
      if (s != previous) expected_states.push_back(s);
      previous = s;
    }
    CHECK(expected_states.size() == 6);  // the first tick plus 5 changes (10, 25, 40, 55, 70)
    CHECK(ep.decisions == int(expected_states.size()));
    CHECK(ep.decision_states == expected_states);
    CHECK(ep.actions_taken.size() == expected_states.size());
    CHECK(ep.action_ticks[0] + ep.action_ticks[1] == 100);
    // Every decision but the last was backed up once with a bootstrap, the last terminally.
    uint64_t backups = 0;
    for (int s = 0; s < q.states(); ++s)
      for (int k = 0; k < q.actions(); ++k) backups += q.visits(s, k);
    CHECK(backups == expected_states.size());
  }

  SECTION("real primitives in an open world") {
    // phi4, search and phi0 with a hand-set table: search until both eyes see the ball, then
    // track it. The state changes when the ball comes into view and when tracking converges,
    // and stays put for many ticks in between.
    PrimitivePtr phi4 = make_primitive("phi4"), search = make_primitive("search"),
                 phi0 = make_primitive("phi0");
    const std::vector<ControllerPtr> psi = {phi4, search, phi0};
    QTable q(controller_names(psi));
    auto rule = [](int s) { return (s / 3) % 3 == int(Gamma::kConv) ? 2 : 1; };  // search's digit
    for (int s = 0; s < q.states(); ++s) q.set(s, rule(s), 1.0);
    auto never = std::make_shared<Scripted>("never", [](uint64_t) { return Gamma::kNotConv; });
    PredicatePtr absorbing = converged(never);
    Agent agent;
    Rng rng(0);
    LearningEpisodeOptions options;
    options.time_limit = 3.0;
    const WorldSpec world = open_world(true, Vec2(-1.2, 0.9));  // behind Roger: search must turn
    const TrainingEpisode ep =
        run_learning_episode(agent, world, 11, psi, *absorbing, q, 0.0, rng, options, false);
    CHECK(ep.ticks == 150);
    CHECK(ep.decisions >= 3);
    CHECK(ep.decisions < ep.ticks / 10);
    CHECK(ep.action_ticks[0] == 0);
    CHECK(ep.action_ticks[1] > 0);
    CHECK(ep.action_ticks[2] > 0);
    // Replay the same episode by hand, choosing by the rule every tick (the same as choosing at
    // changes, since the choice depends on the state alone), and count the state changes.
    agent.reset(world);
    for (const auto& c : psi) c->reset(11);
    int changes = 0, previous = -1;
    std::vector<int> states;
    for (int t = 0; t < ep.ticks; ++t) {
      const ControlInput& in = agent.input();
      const int s = gamma_state_index({phi4->state(in), search->state(in), phi0->state(in)});
      if (s != previous) ++changes, states.push_back(s);
      previous = s;
      agent.step(*psi[size_t(rule(s))]);
    }
    INFO("decisions " << ep.decisions << ", ticks " << ep.ticks);
    CHECK(ep.decisions == changes);  // the first tick's decision plus one per change after it
    CHECK(ep.decision_states == states);
    CHECK(q.visited_states() == 0);  // learn = false touches nothing
  }
}

TEST_CASE("the semi-MDP decides when the running action gives up, though the state stays", "[learning]") {
  // A sticky binding retried after a give-up stays NOREF; when the retry gives up too, nothing
  // changes the state, yet the action has ended: without a decision there the stage would be
  // locked into retrying until the time-out.
  auto stuck = std::make_shared<Scripted>("stuck", [](uint64_t) { return Gamma::kNotConv; }, 1.0);
  auto other = std::make_shared<Scripted>("other", [](uint64_t) { return Gamma::kNotConv; }, 2.0);
  Binding::Bindings b;
  b.stimulus = true;
  b.colour = Colour{0, 200, 0};
  b.patience = 0.4;
  b.sticky_noref = true;
  auto bound = std::make_shared<Binding>(stuck, b);
  const std::vector<ControllerPtr> psi = {bound, other};
  QTable q(controller_names(psi));
  for (int s = 0; s < q.states(); ++s) q.set(s, 0, 1.0);  // greedy: always the bound action
  auto never = std::make_shared<Scripted>("never", [](uint64_t) { return Gamma::kNotConv; });
  PredicatePtr absorbing = converged(never);
  Agent agent;
  Rng rng(0);
  LearningEpisodeOptions options;
  options.time_limit = 2.0;  // 100 ticks: a give-up about every 20
  const TrainingEpisode ep =
      run_learning_episode(agent, open_world(false), 3, psi, *absorbing, q, 0.0, rng, options, false);
  CHECK(ep.ticks == 100);
  // The first decision, then one per give-up; each give-up starts the next invocation at once.
  CHECK(bound->invocations() >= 4);
  CHECK(ep.decisions == bound->invocations());
  REQUIRE(ep.decision_states.size() >= 3);
  const int noref = gamma_state_index({Gamma::kNoRef, Gamma::kNotConv});
  CHECK(ep.decision_states[0] == gamma_state_index({Gamma::kNotConv, Gamma::kNotConv}));
  for (size_t k = 1; k < ep.decision_states.size(); ++k) CHECK(ep.decision_states[k] == noref);
}

// Decision hooks (what a curriculum's Lua functions become) that pay what the declarative rewards
// pay: 0 at a decision, +100 absorbing, -100 at the time-out; optionally the absorbing state too,
// read from the third controller of psi.
class PayLikeTheTable final : public DecisionHooks {
 public:
  explicit PayLikeTheTable(bool absorbing) : absorbing_(absorbing) {}
  bool has_absorbing() const override { return absorbing_; }
  bool has_reward() const override { return true; }
  bool absorbing(const std::vector<Gamma>& state, double) override {
    ++absorbing_calls;
    return state[2] == Gamma::kConv;
  }
  double reward(const std::vector<Gamma>&, int, const char* event, double) override {
    ++reward_calls;
    if (std::strcmp(event, "absorbing") == 0) return 100.0;
    if (std::strcmp(event, "timeout") == 0) return -100.0;
    return 0.0;
  }
  int absorbing_calls = 0, reward_calls = 0;

 private:
  bool absorbing_;
};

TEST_CASE("one loop: a stage paid by decision hooks learns what the declarative stage learns", "[learning]") {
  // A and B change state now and then; the goal converges at tick 60 in even episodes and never in
  // odd ones, so both ends (absorbing, time-out) are learned from.
  auto a = std::make_shared<Scripted>("A", piecewise({0, 10, 40, 70}, {G(0), G(1), G(2), G(1)}));
  auto b = std::make_shared<Scripted>("B", piecewise({0, 25, 55}, {G(1), G(2), G(1)}));
  auto goal = std::make_shared<Scripted>("goal", [](uint64_t) { return Gamma::kNotConv; });
  const std::vector<ControllerPtr> psi = {a, b, goal};
  PredicatePtr absorbing = converged(goal);
  LearningEpisodeOptions options;
  options.time_limit = 2.0;  // 100 ticks
  auto train = [&](DecisionHooks* hooks, Predicate* predicate, QTable& q) {
    Agent agent;
    Rng rng(9);
    std::vector<TrainingEpisode> episodes;
    for (int e = 0; e < 8; ++e) {
      goal->set_script(e % 2 == 0 ? piecewise({0, 60}, {G(1), G(2)}) : piecewise({0}, {G(1)}));
      SemiMdpDriver driver(psi, predicate, q, 0.5, rng, options, true, hooks);
      run_episode(agent, open_world(false), uint64_t(e), driver, options.time_limit);
      episodes.push_back(driver.episode());
    }
    return episodes;
  };
  QTable declared(controller_names(psi));
  const std::vector<TrainingEpisode> plain = train(nullptr, absorbing.get(), declared);
  for (bool hooked_absorbing : {false, true}) {
    INFO("absorbing state from the hooks: " << hooked_absorbing);
    PayLikeTheTable hooks(hooked_absorbing);
    QTable scripted(controller_names(psi));
    const std::vector<TrainingEpisode> paid = train(&hooks, hooked_absorbing ? nullptr : absorbing.get(), scripted);
    CHECK(hooks.reward_calls > 8);
    CHECK((hooks.absorbing_calls > 0) == hooked_absorbing);
    for (size_t e = 0; e < plain.size(); ++e) {
      CHECK(paid[e].success == (e % 2 == 0));
      CHECK(paid[e].success == plain[e].success);
      CHECK(paid[e].ticks == plain[e].ticks);
      CHECK(paid[e].reward == plain[e].reward);
      CHECK(paid[e].actions_taken == plain[e].actions_taken);
    }
    for (int s = 0; s < declared.states(); ++s)
      for (int k = 0; k < declared.actions(); ++k) {
        CHECK(scripted.value(s, k) == declared.value(s, k));
        CHECK(scripted.visits(s, k) == declared.visits(s, k));
      }
  }
}

TEST_CASE("a semi-MDP transition pays the rewards since its decision and discounts the bootstrap", "[learning]") {
  // A's state changes once, at tick 10 (0.2 s); the goal converges at tick 20. The greedy choice
  // is action 0 throughout, so there are two decisions: at tick 0 and at tick 10.
  auto a = std::make_shared<Scripted>("A", piecewise({0, 10}, {G(1), G(2)}));
  auto b = std::make_shared<Scripted>("B", [](uint64_t) { return Gamma::kNotConv; });
  auto goal = std::make_shared<Scripted>("goal", piecewise({0, 20}, {G(1), G(2)}));
  const std::vector<ControllerPtr> psi = {a, b};
  PredicatePtr absorbing = converged(goal);
  const int s0 = gamma_state_index({Gamma::kNotConv, Gamma::kNotConv});
  const int s1 = gamma_state_index({Gamma::kConv, Gamma::kNotConv});
  const double gamma = 0.95, alpha = 0.1;
  auto run = [&](double discount_seconds, QTable& q) {
    q.set(s1, 0, 10.0);
    Agent agent;
    Rng rng(0);
    LearningEpisodeOptions options;
    options.time_limit = 2.0;
    options.step_reward = -1.0;
    options.discount_seconds = discount_seconds;
    return run_learning_episode(agent, open_world(false), 0, psi, *absorbing, q, 0.0, rng, options, true);
  };
  SECTION("one discount step per decision") {
    QTable q(controller_names(psi));
    const TrainingEpisode ep = run(0.0, q);
    CHECK(ep.success);
    CHECK(ep.ticks == 20);
    CHECK(ep.decisions == 2);
    CHECK(ep.reward == -20.0 + 100.0);
    // Ten ticks at -1, then the next decision one step away: Q(s0) = alpha (-10 + gamma 10).
    CHECK(q.value(s0, 0) == Approx(alpha * (-10.0 + gamma * 10.0)));
    // Ten more ticks at -1 and the +100 of the absorbing state, terminal.
    CHECK(q.value(s1, 0) == Approx(10.0 + alpha * (-10.0 + 100.0 - 10.0)));
  }
  SECTION("discount by elapsed time") {
    QTable q(controller_names(psi));
    const double unit = 0.1;  // gamma per 0.1 s
    const TrainingEpisode ep = run(unit, q);
    CHECK(ep.success);
    double first = 0.0, second = 0.0;
    for (int k = 0; k < 10; ++k) {
      first -= std::pow(gamma, 0.02 * k / unit);
      second -= std::pow(gamma, 0.02 * k / unit);
    }
    CHECK(q.value(s0, 0) == Approx(alpha * (first + std::pow(gamma, 0.2 / unit) * 10.0)));
    CHECK(q.value(s1, 0) == Approx(10.0 + alpha * (second + std::pow(gamma, 0.2 / unit) * 100.0 - 10.0)));
  }
}

TEST_CASE("run_learning_episode checks psi against the table", "[learning]") {
  PrimitivePtr search = make_primitive("search"), phi0 = make_primitive("phi0");
  PredicatePtr goal = converged(phi0);
  Agent agent;
  Rng rng(0);
  QTable q({"search", "phi0"});
  CHECK(throws_with([&] { run_learning_episode(agent, open_world(), 0, {phi0, search}, *goal, q, 0.0, rng, {}, true); },
                    {"search", "phi0"}));
  CHECK_THROWS_AS(run_learning_episode(agent, open_world(), 0, {search}, *goal, q, 0.0, rng, {}, true), Error);
  LearningEpisodeOptions bad;
  bad.time_limit = 0.0;
  CHECK(throws_with([&] { run_learning_episode(agent, open_world(), 0, {search, phi0}, *goal, q, 0.0, rng, bad, true); },
                    {"time_limit"}));
  CHECK_THROWS_AS(make_policy_skill("S", {search, phi0}, q, nullptr), Error);
}

TEST_CASE("a learned skill is CONV exactly when its absorbing predicate holds", "[learning]") {
  // Actions A and B (commands marked 1 and 2); the goal G is CONV on ticks [30, 40) and [60, 65).
  auto a = std::make_shared<Scripted>("A", piecewise({0, 20, 50}, {G(0), G(1), G(2)}), 1.0);
  auto b = std::make_shared<Scripted>("B", piecewise({0, 10, 80, 90}, {G(0), G(2), G(0), G(1)}), 2.0);
  auto goal = std::make_shared<Scripted>(
      "G", piecewise({0, 30, 40, 60, 65}, {G(1), G(2), G(1), G(2), G(0)}));
  const std::vector<ControllerPtr> psi = {a, b};
  QTable q(controller_names(psi));
  // Learned: in (!CONV, CONV) and (CONV, CONV) prefer B; elsewhere A (ties to the lowest index).
  const int nc_c = gamma_state_index({Gamma::kNotConv, Gamma::kConv});
  const int c_c = gamma_state_index({Gamma::kConv, Gamma::kConv});
  q.update(nc_c, 1, 50.0, nc_c, true, 0.9);
  q.update(c_c, 1, 50.0, c_c, true, 0.9);
  q.update(0, 0, 50.0, 0, true, 0.9);
  const QTable snapshot = q;
  ControllerPtr skill = make_policy_skill("Phi_X", psi, q, converged(goal));
  CHECK(std::string(skill->kind()) == "learned");
  CHECK(skill->name() == "Phi_X");
  CHECK(skill->children().size() == 3);  // A, B and the goal's controller
  // Training the table further does not change the skill.
  q.update(c_c, 0, 1000.0, c_c, true, 0.9);
  CHECK(q.greedy(c_c) == 0);
  PredicatePtr check = converged(goal);  // an independent view of the absorbing condition
  skill->reset(1);
  goal->reset(1);
  int conv_ticks = 0, noref_ticks = 0;
  for (uint64_t t = 0; t < 100; ++t) {
    ControlInput in;
    in.tick = t;
    in.time = 0.02 * double(t);
    // The cheap state first, then the full output, as a stage reading states and then running an
    // action does: both agree.
    const Gamma cheap = skill->state(in);
    const ControlOutput& out = skill->evaluate(in);
    const bool holds = check->holds(in);
    const Gamma ga = a->state(in), gb = b->state(in);
    const Gamma expected = holds ? Gamma::kConv
                           : (ga == Gamma::kNoRef && gb == Gamma::kNoRef) ? Gamma::kNoRef
                                                                           : Gamma::kNotConv;
    INFO("tick " << t);
    CHECK(cheap == expected);
    CHECK(out.gamma == expected);
    conv_ticks += out.gamma == Gamma::kConv;
    noref_ticks += out.gamma == Gamma::kNoRef;
    // The policy action of the table as it was when the skill was made runs: B (marker 2) where
    // the table learned it and in unvisited states nearest to those, A (marker 1) otherwise.
    const int s = gamma_state_index({ga, gb});
    CHECK(out.command[0] == (snapshot.policy_action(s) == 1 ? 2.0 : 1.0));
    // The rule spelled out: (NOREF, CONV) on ticks 10-19 is nearest (!CONV, CONV): B; (CONV,
    // NOREF) on 80-89 is as near (NOREF, NOREF) as (CONV, CONV): the lower index, A; the retrained
    // (CONV, CONV) on 50-79 still runs B.
    if (t < 10 || (t >= 80 && t < 90)) CHECK(out.command[0] == 1.0);
    else CHECK(out.command[0] == 2.0);
  }
  CHECK(conv_ticks == 15);
  CHECK(noref_ticks == 10);
}

namespace {

// The search-and-track stage: psi = {search, phi0}, absorbing when phi0 converges.
struct TrackStage {
  PrimitivePtr search = make_primitive("search"), phi0 = make_primitive("phi0");
  std::vector<ControllerPtr> psi{search, phi0};
  PredicatePtr absorbing = converged(phi0);
  QTable q{controller_names(psi)};
  LearningEpisodeOptions options;
  TrackStage() { options.time_limit = 3.0; }
};

// Trains `episodes` episodes on seeds 1000, 1001, ... with exploration falling over `budget`.
std::vector<TrainingEpisode> train(TrackStage& stage, Scenario& scenario, int episodes, int budget,
                                   uint64_t trial_seed) {
  Agent agent;
  Rng rng(trial_seed);
  const ExplorationSchedule schedule = ExplorationSchedule::episodes(stage.q.params(), budget);
  std::vector<TrainingEpisode> curve;
  for (int e = 0; e < episodes; ++e) {
    const uint64_t seed = 1000 + uint64_t(e);
    curve.push_back(run_learning_episode(agent, scenario.generate(seed), seed, stage.psi,
                                         *stage.absorbing, stage.q, schedule.epsilon(e), rng,
                                         stage.options, true));
  }
  return curve;
}

// Greedy successes on the held-out seeds 0..n-1.
int greedy_successes(TrackStage& stage, Scenario& scenario, int n) {
  Agent agent;
  Rng rng(0);
  int ok = 0;
  for (int seed = 0; seed < n; ++seed)
    ok += run_learning_episode(agent, scenario.generate(uint64_t(seed)), uint64_t(seed), stage.psi,
                               *stage.absorbing, stage.q, 0.0, rng, stage.options, false)
              .success;
  return ok;
}

}  // namespace

TEST_CASE("the same seeds give the same learning curve, and learning helps", "[learning]") {
  Scenario scenario = Scenario::load("unobstructed");
  TrackStage first, second;
  const std::vector<TrainingEpisode> c1 = train(first, scenario, 20, 15, 42);
  const std::vector<TrainingEpisode> c2 = train(second, scenario, 20, 15, 42);
  REQUIRE(c1.size() == c2.size());
  for (size_t e = 0; e < c1.size(); ++e) {
    INFO("episode " << e);
    CHECK(c1[e].reward == c2[e].reward);
    CHECK(c1[e].ticks == c2[e].ticks);
    CHECK(c1[e].actions_taken == c2[e].actions_taken);
  }
  int differing = 0;
  for (int s = 0; s < first.q.states(); ++s)
    for (int a = 0; a < first.q.actions(); ++a)
      differing += !same_bits(first.q.value(s, a), second.q.value(s, a)) ||
                   first.q.visits(s, a) != second.q.visits(s, a);
  CHECK(differing == 0);

  // Learning improves the greedy policy: before any training it searches forever (action 0 in
  // every state); after training it tracks once the ball is in view.
  TrackStage fresh;
  const int held_out = 10;
  const int before = greedy_successes(fresh, scenario, held_out);
  const std::vector<TrainingEpisode> curve = train(fresh, scenario, 30, 20, 7);
  const int after = greedy_successes(fresh, scenario, held_out);
  INFO("greedy successes before " << before << ", after " << after << " of " << held_out);
  CHECK(after >= before);
  CHECK(after >= 8);
  // The learned skill runs the same policy: as one action it succeeds where the greedy evaluation
  // does.
  ControllerPtr skill = make_policy_skill("Phi6_learned", fresh.psi, fresh.q, fresh.absorbing);
  PredicatePtr skill_done = converged(skill);
  Agent agent;
  int skill_ok = 0;
  for (int seed = 0; seed < held_out; ++seed) {
    skill->reset(uint64_t(seed));
    agent.reset(scenario.generate(uint64_t(seed)));
    for (int t = 0; t < 150; ++t) {
      agent.step(*skill);
      if (skill_done->holds(agent.input())) {
        ++skill_ok;
        break;
      }
    }
  }
  CHECK(skill_ok == after);
}

TEST_CASE("a truncated, empty or foreign policy file is refused naming the file, never read as zeros", "[learning][faults]") {
  QTable q({"search", "phi0", "phi4 <| phi2"}, QParams{});
  Rng rng(7);
  for (int i = 0; i < 100; ++i)
    q.update(int(rng.integer(0, 26)), int(rng.integer(0, 2)), rng.uniform(-100, 100), int(rng.integer(0, 26)), false, 0.9);
  PolicyMetadata meta;
  meta.stage = "SG";
  meta.context = "DC2";
  const std::string path = temp_path("faults_policy.json");
  q.save(path, meta);
  std::ifstream in(path, std::ios::binary);
  const std::string whole((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string damaged = temp_path("faults_damaged.json");
  auto refused = [&](const std::string& text, const std::vector<std::string>& says) {
    std::ofstream(damaged, std::ios::binary | std::ios::trunc) << text;
    std::vector<std::string> parts{damaged};
    parts.insert(parts.end(), says.begin(), says.end());
    return throws_with([&] { QTable::load(damaged, q.action_names()); }, parts);
  };
  // Cut at 40 seeded points (a write cut short): every one refused, none read as a table.
  Rng cuts(2026);
  for (int k = 0; k < 40; ++k) {
    const size_t at = size_t(cuts.integer(0, int64_t(whole.size()) - 2));
    INFO("cut at " << at << " of " << whole.size());
    CHECK(refused(whole.substr(0, at), {}));
  }
  CHECK(refused("", {"JSON", "empty"}));
  // A number out of range, as a hand edit might leave: an error with the path, not a bare exception.
  CHECK(refused(std::regex_replace(whole, std::regex("\"alpha\": [0-9.e+-]+"), "\"alpha\": 1e999"), {"number overflow"}));
  // An action rule that is not a boolean: refused with the field and what it holds.
  for (const char* rule : {"referenced_only", "unconverged_first"}) {
    const std::string field = std::string("\"") + rule + "\": false";
    REQUIRE(whole.find(field) != std::string::npos);
    CHECK(refused(std::regex_replace(whole, std::regex(field), std::string("\"") + rule + "\": \"yes\""),
                  {std::string("params.") + rule, "true or false", "\"yes\""}));
  }
  // Foreign files: another JSON document where a policy belongs.
  CHECK(refused("[1, 2, 3]", {"JSON object"}));
  CHECK(refused("42", {"JSON object"}));
  // A trial's summary.json given for its policy.json: said to be no policy (found by a probe).
  CHECK(refused("{\"id\": \"SG/B1/000\", \"success_rate\": 1.0}",
                {"not a policy written by roger train (it has no field \"format\")", "policy.json in its folder"}));
  CHECK(refused("{\"format\": \"roger-results/1\", \"config\": {}}", {"format"}));
  std::filesystem::remove(damaged);
  std::filesystem::remove(path);
}

TEST_CASE("a cycle of decisions is found at the end of an episode, whatever its phase", "[learning][explain]") {
  // states 7, 3, 7, 3, ... with actions 1, 0, ...: a turn of two decisions, three turns.
  const DecisionCycle c = find_decision_cycle({5, 7, 3, 7, 3, 7, 3}, {2, 1, 0, 1, 0, 1, 0});
  CHECK(c.turns == 3);
  CHECK(c.first == 1);
  CHECK(c.states == std::vector<int>{3, 7});  // rotated to its least (state, action)
  CHECK(c.actions == std::vector<int>{0, 1});
  // Entered at the other point of its turn, the same cycle.
  const DecisionCycle d = find_decision_cycle({3, 7, 3, 7}, {0, 1, 0, 1});
  CHECK(d.states == c.states);
  CHECK(d.actions == c.actions);
  CHECK(d.turns == 2);
  // A longer turn, and the shortest period wins.
  const DecisionCycle e = find_decision_cycle({1, 2, 4, 1, 2, 4}, {0, 0, 1, 0, 0, 1});
  CHECK(e.states == std::vector<int>{1, 2, 4});
  CHECK(e.turns == 2);
  // No repetition up to the end, or one turn only: no cycle.
  CHECK(find_decision_cycle({1, 2, 3, 4}, {0, 1, 0, 1}).turns == 0);
  CHECK(find_decision_cycle({1, 2, 1, 2, 9}, {0, 1, 0, 1, 0}).turns == 0);
  CHECK(find_decision_cycle({3, 7, 3, 7}, {0, 1, 0, 0}).turns == 0);  // same states, other actions
  CHECK(find_decision_cycle({}, {}).turns == 0);
}

TEST_CASE("decisions given from outside, one tick at a time, replay the driver's own episode bit for bit", "[learning]") {
  // What an environment stepped from Python does (batch/environment.h): EpisodeRun paused at
  // each decision point by a driver in external mode, given QTable::policy_action of the state.
  Scenario scenario = Scenario::load("unobstructed");
  TrackStage stage;
  train(stage, scenario, 30, 20, 7);
  Agent agent;
  Rng unused(0);
  for (uint64_t seed = 0; seed < 6; ++seed) {
    INFO("seed " << seed);
    const WorldSpec spec = scenario.generate(seed);
    const TrainingEpisode own =
        run_learning_episode(agent, spec, seed, stage.psi, *stage.absorbing, stage.q, 0.0, unused, stage.options, false);
    const uint64_t own_hash = agent.world().state_hash();

    SemiMdpDriver driver(stage.psi, stage.absorbing.get(), stage.q, 0.0, unused, stage.options, false);
    driver.choose_externally(true);
    EpisodeRun run(agent, spec, seed, driver, stage.options.time_limit);
    CHECK_THROWS_WITH(driver.act(0), Catch::Contains("no decision is pending"));
    int pauses = 0;
    double rewards = 0.0;
    for (;;) {
      while (run.tick()) {
      }
      if (!run.paused()) break;
      ++pauses;
      rewards += driver.transition_reward();
      CHECK_THROWS_WITH(driver.act(2), Catch::Contains("action index 2 is not in [0, 2)"));
      driver.act(stage.q.policy_action(gamma_state_index(driver.gammas())));
    }
    const EpisodeOutcome out = run.finish();
    rewards += driver.transition_reward();
    const TrainingEpisode& ep = driver.episode();
    CHECK(pauses == own.decisions);
    CHECK(ep.decision_states == own.decision_states);
    CHECK(ep.actions_taken == own.actions_taken);
    CHECK(ep.ticks == own.ticks);
    CHECK(out.ticks == own.ticks);
    CHECK(out.success == own.success);
    CHECK(same_bits(ep.sim_seconds, own.sim_seconds));
    CHECK(ep.reward == own.reward);
    CHECK(rewards == own.reward);  // the steps' rewards add up to the episode's
    CHECK(agent.world().state_hash() == own_hash);
  }
}

// roger train --init: a table starts from one learned earlier, over the actions the two share.
TEST_CASE("a warm-started table carries the shared actions' values and visits", "[learning]") {
  QTable small({"b", "c"});  // state = 3 * gamma(b) + gamma(c)
  for (int s = 0; s < 9; ++s) {
    small.set(s, 0, 10.0 + s);
    small.set(s, 1, 20.0 + s);
  }
  for (int i = 0; i < 3; ++i) small.update(4, 0, small.value(4, 0), 4, true, 1.0);  // 3 visits, value kept
  // More actions (a new one first): each new state takes the one earlier state it projects onto.
  QParams p;
  p.initial_q = -1.0;
  WarmStart w;
  const QTable big = warm_start_table({"a", "b", "c"}, p, small, "small.json", &w);
  CHECK(w.shared == std::vector<std::string>{"b", "c"});
  CHECK(w.fresh == std::vector<std::string>{"a"});
  CHECK(w.dropped.empty());
  CHECK(w.states_with_values == 3);  // a's three gammas times the one visited state (b, c) = (1, 1)
  for (int a = 0; a < 3; ++a)
    for (int s = 0; s < 9; ++s) {
      const int state = 9 * a + s;
      CHECK(big.value(state, 0) == -1.0);  // a: initial_q
      CHECK(big.value(state, 1) == 10.0 + s);
      CHECK(big.value(state, 2) == 20.0 + s);
      CHECK(big.visits(state, 1) == (s == 4 ? 3u : 0u));
    }
  // Fewer actions: a state of c alone takes the visit-weighted mean over b's gammas (the plain mean
  // when none was visited).
  small.set(1, 1, 30.0);
  for (int i = 0; i < 2; ++i) small.update(1, 1, small.value(1, 1), 1, true, 1.0);  // (b, c) = (0, 1): 2 visits
  for (int i = 0; i < 2; ++i) small.update(7, 1, small.value(7, 1), 7, true, 1.0);  // (2, 1): 2 visits, 27
  const QTable c_only = warm_start_table({"c"}, {}, small, "small.json", &w);
  CHECK(w.dropped == std::vector<std::string>{"b"});
  CHECK(c_only.value(1, 0) == Approx((30.0 * 2 + 27.0 * 2) / 4));
  CHECK(c_only.visits(1, 0) == 4u);
  CHECK(c_only.value(0, 0) == Approx((20.0 + 23.0 + 26.0) / 3));  // c = 0: never visited
  CHECK_THROWS_WITH(warm_start_table({"x"}, {}, small, "small.json"),
                    "small.json: its table shares no action with this context's (its actions: b, c; this "
                    "context's: x), so nothing of it could be carried over");
}
