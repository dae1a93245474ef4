// qtable.cpp: the action-value table of a stage, its backups and its policy file.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/json_input.h"
#include "core/error.h"
#include "core/fileio.h"
#include "core/text.h"
#include "learn/learning.h"
#include "learn/learning_internal.h"

namespace roger {

using namespace learning_detail;

namespace {

// Field access with messages naming the source and the field.
const nlohmann::json& field(const nlohmann::json& j, const char* name, const std::string& source) {
  auto it = j.find(name);
  if (it == j.end()) throw Error(source + ": missing field \"" + name + "\"");
  return *it;
}

double number(const nlohmann::json& j, const std::string& what, const std::string& source) {
  if (!j.is_number()) throw Error(source + ": " + what + " must be a number, got " + j.dump());
  const double v = j.get<double>();
  if (!finite(v)) throw Error(source + ": " + what + " must be finite");
  return v;
}

// The format and version fields of a policy file.
void check_format(const nlohmann::json& j, const std::string& source) {
  if (!j.contains("format"))  // another JSON file given for a policy, such as a trial's summary.json
    throw Error(source + ": not a policy written by roger train (it has no field \"format\"); a trial's policy is "
                "policy.json in its folder");
  const auto& format = field(j, "format", source);
  if (!format.is_string() || format.get<std::string>() != kFormat)
    throw Error(source + ": field \"format\" must be \"" + kFormat + "\", got " + format.dump());
  const auto& version = field(j, "version", source);
  if (!version.is_number_integer() || version.get<int64_t>() != kVersion)
    throw Error(source + ": field \"version\" must be " + std::to_string(kVersion) + ", got " +
                version.dump());
}

// The action names, checked against the caller's Psi (when `expected` is not empty).
std::vector<std::string> read_action_names(const nlohmann::json& j, const std::vector<std::string>& expected,
                                           const std::string& source) {
  const auto& jactions = field(j, "actions", source);
  if (!jactions.is_array()) throw Error(source + ": field \"actions\" must be a list of names");
  std::vector<std::string> names;
  for (const auto& n : jactions) {
    if (!n.is_string()) throw Error(source + ": field \"actions\" must be a list of names, got " + n.dump());
    names.push_back(n.get<std::string>());
  }
  if (!expected.empty() && names != expected)
    throw Error(source + ": field \"actions\" is " + list_names(names) +
                " but this stage's actions are " + list_names(expected) +
                " (a policy is tied to its action set and order)");
  return names;
}

// The learning parameters, validated.
QParams read_params(const nlohmann::json& j, const std::string& source) {
  const auto& jp = field(j, "params", source);
  if (!jp.is_object()) throw Error(source + ": field \"params\" must be an object");
  QParams p;
  auto param = [&](const char* name) {
    return number(field(jp, name, source + ": params"), std::string("params.") + name, source);
  };
  p.alpha = param("alpha");
  p.discount = param("discount");
  p.epsilon_start = param("epsilon_start");
  p.epsilon_end = param("epsilon_end");
  p.initial_q = param("initial_q");
  // A rule of which actions may be chosen: false when absent, since policies written before the
  // field existed were learned choosing every action.
  auto rule = [&](const char* name) {
    if (!jp.contains(name)) return false;
    if (!jp[name].is_boolean())
      throw Error(source + ": field \"params." + name + "\" must be true or false, got " + jp[name].dump());
    return jp[name].get<bool>();
  };
  p.referenced_only = rule("referenced_only");
  p.unconverged_first = rule("unconverged_first");
  p.validate(source + ": params");
  return p;
}

// A states x actions table field ("q" or "visits"), its shape checked: a list of every state's row,
// or (a table past kDenseStates states) an object of the rows that hold something, keyed by state;
// the rows with their states, in order.
std::vector<std::pair<int, const nlohmann::json*>> table_rows(const nlohmann::json& j, const char* name, int states,
                                                              int actions, const std::string& source) {
  const auto& r = field(j, name, source);
  std::vector<std::pair<int, const nlohmann::json*>> rows;
  if (r.is_object()) {
    for (auto it = r.begin(); it != r.end(); ++it) {
      const std::string& key = it.key();
      char* end = nullptr;
      const long s = key.empty() || key.size() > 9 ? -1 : std::strtol(key.c_str(), &end, 10);
      if (s < 0 || s >= states || *end != '\0' || std::to_string(s) != key)
        throw Error(source + ": field \"" + name + "\" is keyed by state (0 to " + std::to_string(states - 1) +
                    ", 3^" + std::to_string(actions) + " states), got the key \"" + key + "\"");
      rows.push_back({int(s), &it.value()});
    }
    std::sort(rows.begin(), rows.end());
  } else if (r.is_array() && int(r.size()) == states) {
    for (size_t s = 0; s < r.size(); ++s) rows.push_back({int(s), &r[s]});
  } else {
    throw Error(source + ": field \"" + name + "\" must have " + std::to_string(states) + " rows (3^" +
                std::to_string(actions) + " states), or be an object of rows keyed by state, got " +
                (r.is_array() ? std::to_string(r.size()) + " rows" : std::string(r.type_name())));
  }
  for (const auto& [s, row] : rows)
    if (!row->is_array() || int(row->size()) != actions)
      throw Error(source + ": field \"" + name + "\" row " + std::to_string(s) + " must have " +
                  std::to_string(actions) + " entries (one per action)");
  return rows;
}

// The caller's metadata: stage, context, seed and extra.
PolicyMetadata read_metadata(const nlohmann::json& j, const std::string& source) {
  PolicyMetadata m;
  const auto& stage = field(j, "stage", source);
  const auto& context = field(j, "context", source);
  const auto& seed = field(j, "seed", source);
  if (!stage.is_string()) throw Error(source + ": field \"stage\" must be a string");
  if (!context.is_string()) throw Error(source + ": field \"context\" must be a string");
  if (!seed.is_number_unsigned() && !(seed.is_number_integer() && seed.get<int64_t>() >= 0))
    throw Error(source + ": field \"seed\" must be an integer >= 0");
  m.stage = stage.get<std::string>();
  m.context = context.get<std::string>();
  m.seed = seed.get<uint64_t>();
  if (auto it = j.find("extra"); it != j.end()) m.extra = *it;
  return m;
}

}  // namespace

namespace learning_detail {

// "[a, b, c]" for messages.
std::string list_names(const std::vector<std::string>& names) {
  std::string s = "[";
  for (size_t i = 0; i < names.size(); ++i) s += (i ? ", \"" : "\"") + names[i] + "\"";
  return s + "]";
}

}  // namespace learning_detail

std::string QParams::problem() const {
  auto outside = [](double v, bool open_below) { return !finite(v) || v > 1.0 || v < 0.0 || (open_below && v == 0.0); };
  auto range = [](const char* name, double v, const char* r) {
    return std::string(name) + " must be in " + r + ", got " + format_number(v);
  };
  if (outside(alpha, true)) return range("alpha", alpha, "(0, 1]");
  if (outside(discount, false)) return range("discount", discount, "[0, 1]");
  if (outside(epsilon_start, false)) return range("epsilon_start", epsilon_start, "[0, 1]");
  if (outside(epsilon_end, false)) return range("epsilon_end", epsilon_end, "[0, 1]");
  if (!finite(initial_q)) return "initial_q must be finite, got " + format_number(initial_q);
  return "";
}

void QParams::validate(const std::string& where) const {
  const std::string why = problem();
  if (!why.empty()) throw Error(where + ": " + why);
}

QTable::QTable(std::vector<std::string> action_names, const QParams& params)
    : names_(std::move(action_names)), params_(params) {
  params_.validate();
  if (names_.empty() || int(names_.size()) > kMaxActions)
    throw Error("q-table: needs 1 to " + std::to_string(kMaxActions) + " actions (3^n states), got " +
                std::to_string(names_.size()));
  for (size_t i = 0; i < names_.size(); ++i) {
    if (names_[i].empty()) throw Error("q-table: action " + std::to_string(i) + " has no name");
    for (size_t k = 0; k < i; ++k)
      if (names_[k] == names_[i])
        throw Error("q-table: two actions are named \"" + names_[i] +
                    "\"; names identify actions in policy files");
  }
  actions_ = int(names_.size());
  states_ = 1;
  for (int i = 0; i < actions_; ++i) states_ *= 3;
  q_.assign(size_t(states_) * size_t(actions_), params_.initial_q);
  visits_.assign(q_.size(), 0);
  state_seen_.assign(size_t(states_), 0);
}

void QTable::check(int s, int a, const char* what) const {
  if (s < 0 || s >= states_ || a < 0 || a >= actions_)
    throw Error(std::string("q-table: ") + what + "(" + std::to_string(s) + ", " + std::to_string(a) +
                ") outside " + std::to_string(states_) + " states x " + std::to_string(actions_) +
                " actions");
}

double QTable::value(int s, int a) const {
  check(s, a, "value");
  return q_[size_t(s) * size_t(actions_) + size_t(a)];
}

void QTable::set(int s, int a, double v) {
  check(s, a, "set");
  if (!finite(v)) throw Error("q-table: set() needs a finite value");
  q_[size_t(s) * size_t(actions_) + size_t(a)] = v;
}

uint64_t QTable::visits(int s, int a) const {
  check(s, a, "visits");
  return visits_[size_t(s) * size_t(actions_) + size_t(a)];
}

bool QTable::visited(int s) const {
  check(s, 0, "visited");
  return state_seen_[size_t(s)] != 0;
}

int QTable::visited_states() const {
  return int(std::count(state_seen_.begin(), state_seen_.end(), uint8_t(1)));
}

uint32_t QTable::engageable_mask(int s) const {
  const uint32_t all = (1u << actions_) - 1u;
  if (!params_.referenced_only && !params_.unconverged_first) return all;
  // The first action is the most significant base-3 digit (gamma_state_index); NOREF is 0,
  // !CONV 1, CONV 2.
  uint32_t referenced = 0, unconverged = 0;
  for (int a = actions_ - 1; a >= 0; --a, s /= 3) {
    if (s % 3 != 0) referenced |= 1u << a;
    if (s % 3 == 1) unconverged |= 1u << a;
  }
  if (params_.unconverged_first && unconverged != 0) return unconverged;
  if (params_.referenced_only && referenced != 0) return referenced;
  return all;
}

bool QTable::engageable(int s, int a) const {
  check(s, a, "engageable");
  return (engageable_mask(s) >> a) & 1u;
}

int QTable::best_in(int row_state, uint32_t mask) const {
  const double* row = &q_[size_t(row_state) * size_t(actions_)];
  int best = -1;
  for (int a = 0; a < actions_; ++a)
    if (((mask >> a) & 1u) && (best < 0 || row[a] > row[best])) best = a;  // strict: ties keep the lowest index
  return best;
}

int QTable::greedy(int s) const {
  check(s, 0, "greedy");
  return best_in(s, engageable_mask(s));
}

double QTable::max_value(int s) const {
  return q_[size_t(s) * size_t(actions_) + size_t(greedy(s))];
}

int QTable::policy_action(int s) const {
  if (visited(s)) return greedy(s);
  const int t = nearest_visited_state(s, states_, actions_,
                                      [this](int k) { return state_seen_[size_t(k)] != 0; });
  // The nearest visited state's values, among the actions that may run here.
  return best_in(t >= 0 ? t : s, engageable_mask(s));
}

int QTable::choose(int s, double epsilon, Rng& rng) {
  check(s, 0, "choose");
  if (!(epsilon >= 0.0 && epsilon <= 1.0)) throw Error("q-table: epsilon must be in [0, 1]");
  if (epsilon > 0.0 && rng.uniform() < epsilon) return explore(s, rng);
  return greedy(s);
}

int QTable::explore(int s, Rng& rng) const {
  check(s, 0, "explore");
  const uint32_t mask = engageable_mask(s);
  // The k-th engageable action, k uniform (with every action engageable, the k-th action).
  int k = int(rng.integer(0, __builtin_popcount(mask) - 1));
  for (int a = 0; a < actions_; ++a)
    if (((mask >> a) & 1u) && k-- == 0) return a;
  return 0;  // not reached: the mask has popcount bits
}

double QTable::update(int s, int a, double reward, int s_next, bool terminal, double discount_power) {
  check(s, a, "update");
  check(s_next, 0, "update");
  if (!finite(reward)) throw Error("q-table: update() needs a finite reward");
  if (!(discount_power >= 0.0 && discount_power <= 1.0))
    throw Error("q-table: update() needs a discount in [0, 1]");
  double& v = q_[size_t(s) * size_t(actions_) + size_t(a)];
  const double target = reward + (terminal ? 0.0 : discount_power * max_value(s_next));
  const double td = target - v;
  v += params_.alpha * td;
  ++visits_[size_t(s) * size_t(actions_) + size_t(a)];
  state_seen_[size_t(s)] = 1;
  return td;
}

nlohmann::json QTable::to_json(const PolicyMetadata& meta) const {
  nlohmann::json j;
  j["format"] = kFormat;
  j["version"] = kVersion;
  j["stage"] = meta.stage;
  j["context"] = meta.context;
  j["seed"] = meta.seed;
  j["actions"] = names_;
  j["params"] = {{"alpha", params_.alpha},
                 {"discount", params_.discount},
                 {"epsilon_start", params_.epsilon_start},
                 {"epsilon_end", params_.epsilon_end},
                 {"initial_q", params_.initial_q}, {"referenced_only", params_.referenced_only},
                 {"unconverged_first", params_.unconverged_first}};
  // A row per state; past kDenseStates only the rows that hold something (a value other than
  // initial_q, or a visit), keyed by state: a context of 12 actions has 531441 states, and its
  // file, which every later stage embeds, was 98 MB of default rows (found by a probe).
  const bool sparse = states_ > kDenseStates;
  nlohmann::json q = sparse ? nlohmann::json::object() : nlohmann::json::array();
  nlohmann::json visits = sparse ? nlohmann::json::object() : nlohmann::json::array();
  for (int s = 0; s < states_; ++s) {
    nlohmann::json qrow = nlohmann::json::array(), vrow = nlohmann::json::array();
    bool holds = false;
    for (int a = 0; a < actions_; ++a) {
      const size_t k = size_t(s) * size_t(actions_) + size_t(a);
      qrow.push_back(q_[k]);
      vrow.push_back(visits_[k]);
      holds = holds || visits_[k] > 0 || q_[k] != params_.initial_q;
    }
    if (!sparse) {
      q.push_back(std::move(qrow));
      visits.push_back(std::move(vrow));
    } else if (holds) {
      q[std::to_string(s)] = std::move(qrow);
      visits[std::to_string(s)] = std::move(vrow);
    }
  }
  j["q"] = std::move(q);
  j["visits"] = std::move(visits);
  if (!meta.extra.is_null()) j["extra"] = meta.extra;
  return j;
}

QTable QTable::from_json(const nlohmann::json& j, const std::vector<std::string>& expected,
                         const std::string& source, PolicyMetadata* meta) {
  if (!j.is_object()) throw Error(source + ": a policy file must hold a JSON object");
  check_format(j, source);
  const std::vector<std::string> names = read_action_names(j, expected, source);
  const QParams p = read_params(j, source);
  QTable t = [&] {
    try {
      return QTable(names, p);
    } catch (const Error& e) {
      throw Error(source + ": field \"actions\": " + e.what());
    }
  }();
  const std::vector<std::pair<int, const nlohmann::json*>> qrows = table_rows(j, "q", t.states_, t.actions_, source);
  const std::vector<std::pair<int, const nlohmann::json*>> vrows =
      table_rows(j, "visits", t.states_, t.actions_, source);
  if (qrows.size() != vrows.size() ||
      !std::equal(qrows.begin(), qrows.end(), vrows.begin(), [](const auto& a, const auto& b) { return a.first == b.first; }))
    throw Error(source + ": fields \"q\" and \"visits\" must hold the same states");
  for (size_t r = 0; r < qrows.size(); ++r) {
    const int s = qrows[r].first;
    for (int a = 0; a < t.actions_; ++a) {
      const size_t k = size_t(s) * size_t(t.actions_) + size_t(a);
      t.q_[k] = number((*qrows[r].second)[size_t(a)],
                       "field \"q\" [" + std::to_string(s) + "][" + std::to_string(a) + "]", source);
      const auto& v = (*vrows[r].second)[size_t(a)];
      if (!v.is_number_unsigned() && !(v.is_number_integer() && v.get<int64_t>() >= 0))
        throw Error(source + ": field \"visits\" [" + std::to_string(s) + "][" + std::to_string(a) +
                    "] must be a count (an integer >= 0), got " + v.dump());
      t.visits_[k] = v.get<uint64_t>();
      if (t.visits_[k] > 0) t.state_seen_[size_t(s)] = 1;
    }
  }
  PolicyMetadata m = read_metadata(j, source);
  if (meta) *meta = std::move(m);
  return t;
}

void QTable::save(const std::string& path, const PolicyMetadata& meta) const {
  write_file_atomic(path, to_json(meta).dump(1) + "\n", "cannot write the policy file");
}

QTable QTable::load(const std::string& path, const std::vector<std::string>& expected,
                    PolicyMetadata* meta) {
  const std::string text = read_file_text(path);  // refuses a device or a pipe, which never ends
  if (text.empty() && !std::ifstream(path, std::ios::binary)) {
    std::error_code ec;  // which of the two (found by a probe: a missing file was only "cannot read")
    throw Error(path + (std::filesystem::exists(path, ec) ? ": cannot read the policy file" : ": no such file"));
  }
  nlohmann::json j;
  try {
    j = parse_json(text);
  } catch (const nlohmann::json::exception& e) {  // parse_error, or out_of_range for 1e999
    throw Error(path + ": not valid JSON" + (text.empty() ? std::string(" (an empty file)") : "") + ": " + json_error_text(e.what()));
  }
  return from_json(j, expected, path, meta);
}

std::vector<std::string> controller_names(const std::vector<ControllerPtr>& psi) {
  std::vector<std::string> names;
  for (size_t i = 0; i < psi.size(); ++i) {
    if (!psi[i]) throw Error("psi[" + std::to_string(i) + "] is not a controller");
    names.push_back(psi[i]->name());
  }
  return names;
}

}  // namespace roger
