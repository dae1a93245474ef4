// task_space.cpp: task spaces over scenario parameters, their unit-cube coordinates and the text
// values a scenario takes.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>

#include "core/error.h"
#include "core/text.h"
#include "teach/teach.h"

namespace roger {
namespace {

// An int axis's value as text, "3".
std::string int_text(double v) { return std::to_string(int64_t(std::llround(v))); }

// The number of the text, or nullopt when it is not a whole finite number.
std::optional<double> parse_number(const std::string& text) {
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

void check_dim(const TaskDim& d) {
  const std::string at = d.name.empty() ? d.text() : "'" + d.name + "' (" + d.text() + ")";
  switch (d.kind) {
    case TaskDim::Kind::kInt:
      if (d.lo != std::floor(d.lo) || d.hi != std::floor(d.hi) || !std::isfinite(d.lo) || !std::isfinite(d.hi))
        throw Error("task axis " + at + ": the bounds of roger.int must be integers");
      if (d.lo > d.hi) throw Error("task axis " + at + ": the range is reversed (lo must not exceed hi)");
      break;
    case TaskDim::Kind::kReal:
      if (!std::isfinite(d.lo) || !std::isfinite(d.hi)) throw Error("task axis " + at + ": the bounds must be finite");
      if (d.lo > d.hi) throw Error("task axis " + at + ": the range is reversed (lo must not exceed hi)");
      if (d.lo == d.hi) throw Error("task axis " + at + ": the range is a single value (lo equals hi); give the value itself");
      break;
    case TaskDim::Kind::kChoice: {
      if (d.choices.empty()) throw Error("task axis " + at + ": roger.choice needs at least one value");
      std::set<std::string> seen;
      for (const auto& c : d.choices)
        if (!seen.insert(c).second) throw Error("task axis " + at + ": the value '" + c + "' is listed twice");
      break;
    }
  }
}

}  // namespace

std::string TaskDim::text() const {
  switch (kind) {
    case Kind::kInt: return "roger.int(" + int_text(lo) + ", " + int_text(hi) + ")";
    case Kind::kReal: return "roger.real(" + format_number(lo) + ", " + format_number(hi) + ")";
    case Kind::kChoice: return choices.size() == 1 ? choices[0] : "roger.choice{" + join(choices) + "}";  // a value
  }
  return "";
}

size_t TaskDim::cells() const {
  if (kind == Kind::kInt) return size_t(hi - lo) + 1;
  if (kind == Kind::kChoice) return choices.size();
  return 0;
}

TaskSpace::TaskSpace(std::vector<TaskDim> dims) : dims_(std::move(dims)) {
  std::sort(dims_.begin(), dims_.end(), [](const TaskDim& a, const TaskDim& b) { return a.name < b.name; });
  for (size_t i = 0; i < dims_.size(); ++i) {
    check_dim(dims_[i]);
    if (i > 0 && dims_[i].name == dims_[i - 1].name)
      throw Error("task space: the parameter '" + dims_[i].name + "' has two axes");
  }
}

int TaskSpace::index(const std::string& name) const {
  for (size_t i = 0; i < dims_.size(); ++i)
    if (dims_[i].name == name) return int(i);
  return -1;
}

TaskPoint TaskSpace::sample(Rng& rng) const {
  TaskPoint t(dims_.size());
  for (size_t i = 0; i < dims_.size(); ++i) {
    const TaskDim& d = dims_[i];
    if (d.kind == TaskDim::Kind::kReal) t[i] = rng.uniform(d.lo, d.hi);
    else t[i] = double(rng.integer(d.kind == TaskDim::Kind::kInt ? int64_t(d.lo) : 0,
                                   d.kind == TaskDim::Kind::kInt ? int64_t(d.hi) : int64_t(d.choices.size()) - 1));
  }
  return t;
}

std::vector<double> TaskSpace::to_unit(const TaskPoint& task) const {
  std::vector<double> u(dims_.size());
  for (size_t i = 0; i < dims_.size(); ++i) {
    const TaskDim& d = dims_[i];
    if (d.kind == TaskDim::Kind::kReal) u[i] = (task[i] - d.lo) / (d.hi - d.lo);
    else u[i] = ((d.kind == TaskDim::Kind::kInt ? task[i] - d.lo : task[i]) + 0.5) / double(d.cells());
  }
  return u;
}

TaskPoint TaskSpace::from_unit(const std::vector<double>& unit) const {
  TaskPoint t(dims_.size());
  for (size_t i = 0; i < dims_.size(); ++i) {
    const TaskDim& d = dims_[i];
    const double u = std::clamp(std::isfinite(unit[i]) ? unit[i] : 0.5, 0.0, 1.0);
    if (d.kind == TaskDim::Kind::kReal) {
      t[i] = std::min(d.hi, d.lo + u * (d.hi - d.lo));
    } else {
      const double n = double(d.cells());
      const double k = std::min(n - 1.0, std::floor(u * n));  // u = 1 belongs to the last slice
      t[i] = d.kind == TaskDim::Kind::kInt ? d.lo + k : k;
    }
  }
  return t;
}

ParamList TaskSpace::params(const TaskPoint& task) const {
  ParamList out;
  for (size_t i = 0; i < dims_.size(); ++i) {
    const TaskDim& d = dims_[i];
    const std::string v = d.kind == TaskDim::Kind::kInt    ? int_text(task[i])
                          : d.kind == TaskDim::Kind::kReal ? format_number(task[i])
                                                           : d.choices[size_t(task[i])];
    out.emplace_back(d.name, v);
  }
  return out;
}

nlohmann::json TaskSpace::to_json(const TaskPoint& task) const {
  nlohmann::json j = nlohmann::json::object();
  for (size_t i = 0; i < dims_.size(); ++i) {
    const TaskDim& d = dims_[i];
    if (d.kind == TaskDim::Kind::kInt) j[d.name] = int64_t(std::llround(task[i]));
    else if (d.kind == TaskDim::Kind::kReal) j[d.name] = task[i];
    // A choice as the records write a parameter (found by a probe: roger.choice{0, 200} was
    // recorded as "0" and "200", where an int axis records numbers).
    else j[d.name] = param_value_json(d.choices[size_t(task[i])]);
  }
  return j;
}

std::optional<double> TaskSpace::value_of(size_t dim, const std::string& text, std::string* why) const {
  const TaskDim& d = dims_.at(dim);
  if (d.kind == TaskDim::Kind::kChoice) {
    const auto it = std::find(d.choices.begin(), d.choices.end(), text);
    if (it != d.choices.end()) return double(it - d.choices.begin());
    // A number written another way ("2.0" for "2") is the same value.
    const std::optional<double> v = parse_number(text);
    for (size_t k = 0; v && k < d.choices.size(); ++k)
      if (parse_number(d.choices[k]) == v) return double(k);
  } else {
    const std::optional<double> v = parse_number(text);
    const bool integral = v && *v == std::floor(*v);
    if (v && *v >= d.lo && *v <= d.hi && (d.kind == TaskDim::Kind::kReal || integral)) return *v;
  }
  if (why)
    *why = d.kind == TaskDim::Kind::kInt                                  ? "an integer in " + d.text()
           : d.kind == TaskDim::Kind::kChoice && d.choices.size() == 1 ? "the one value " + d.text()
                                                                         : "a value of " + d.text();
  return std::nullopt;
}

std::optional<TaskPoint> TaskSpace::task_of(const ParamList& params, std::string* why) const {
  TaskPoint t(dims_.size(), 0.0);
  std::vector<bool> seen(dims_.size(), false);
  for (const auto& [k, v] : params) {
    const int i = index(k);
    if (i < 0) {
      std::vector<std::string> names;
      for (const TaskDim& d : dims_) names.push_back(d.name);
      if (why) *why = "'" + k + "' is not a parameter of the task space" + suggestion(k, names) + " (" + describe() + ")";
      return std::nullopt;
    }
    std::string allowed;
    const std::optional<double> x = value_of(size_t(i), v, &allowed);
    if (!x) {
      // A choice in another case (shape = "Spade") gets its nearest, as a name does.
      const TaskDim& d = dims_[size_t(i)];
      const std::string near = d.kind == TaskDim::Kind::kChoice ? suggestion(v, d.choices) : "";
      if (why) *why = k + " = " + v + " is outside the task space" + near + ": " + k + " takes " + allowed;
      return std::nullopt;
    }
    t[size_t(i)] = *x;
    seen[size_t(i)] = true;
  }
  for (size_t i = 0; i < dims_.size(); ++i)
    if (!seen[i]) {
      if (why) *why = "no value for '" + dims_[i].name + "' (" + dims_[i].text() + ")";
      return std::nullopt;
    }
  return t;
}

bool TaskSpace::covers(const TaskDim& sub) const {
  const int i = index(sub.name);
  if (i < 0) return false;
  const TaskDim& d = dims_[size_t(i)];
  if (sub.kind == TaskDim::Kind::kChoice) {
    for (size_t k = 0; k < sub.choices.size(); ++k)
      if (!value_of(size_t(i), sub.choices[k])) return false;
    return true;
  }
  if (d.kind == TaskDim::Kind::kChoice) return false;
  if (d.kind == TaskDim::Kind::kInt && sub.kind == TaskDim::Kind::kReal) return false;
  return sub.lo >= d.lo && sub.hi <= d.hi;
}

nlohmann::json param_value_json(const std::string& text) {
  char* end = nullptr;
  const long long i = std::strtoll(text.c_str(), &end, 10);
  if (!text.empty() && *end == '\0' && std::to_string(i) == text) return int64_t(i);
  // Only a number written as the engine writes it: "007", "1e3" or "0x1A" are names a script gave
  // (a choice of them recorded as 7, 1000 and 26 would lose them).
  const double v = std::strtod(text.c_str(), &end);
  if (!text.empty() && *end == '\0' && std::isfinite(v) && format_number(v) == text) return v;
  return text;
}

std::string params_text(const ParamList& params) {
  std::string out;
  for (const auto& [k, v] : params) out += (out.empty() ? "" : ", ") + k + " = " + v;
  return out;
}

TaskSpace TaskSpace::without(const std::vector<std::string>& names) const {
  std::vector<TaskDim> kept, fixed_dims = fixed_dims_;
  std::vector<std::string> fixed = fixed_;
  for (const auto& d : dims_) {
    if (std::find(names.begin(), names.end(), d.name) == names.end()) {
      kept.push_back(d);
    } else {
      fixed.push_back(d.name);
      fixed_dims.push_back(d);
    }
  }
  TaskSpace out(std::move(kept));
  std::sort(fixed.begin(), fixed.end());
  out.fixed_ = std::move(fixed);
  out.fixed_dims_ = std::move(fixed_dims);
  return out;
}

bool TaskSpace::is_fixed(const std::string& name) const {
  return std::binary_search(fixed_.begin(), fixed_.end(), name);
}

std::string TaskSpace::describe() const {
  std::vector<std::string> parts;
  for (const auto& d : dims_) parts.push_back(d.name + " = " + d.text());
  return parts.empty() ? "no parameters" : join(parts);
}

// Why a step's restriction r of axis i is refused: a value the axis does not take says what the
// axis takes (of 2.5 over an int axis: that it takes an integer), a range its ends.
static std::string not_covered(const TaskSpace& space, size_t i, const TaskDim& r) {
  const TaskDim& whole = space.dims()[i];
  if (r.kind == TaskDim::Kind::kChoice)
    for (const std::string& c : r.choices) {
      std::string allowed;
      if (!space.value_of(i, c, &allowed)) return r.name + " = " + c + " is outside the task space: " + r.name + " takes " + allowed;
    }
  if (whole.kind == TaskDim::Kind::kInt && r.kind == TaskDim::Kind::kReal)
    return r.name + " = " + r.text() + " is a real range, but " + r.name + " takes an integer in " + whole.text();
  return r.name + " = " + r.text() + " is outside the task space's " + whole.text();
}

TaskSpace restrict_space(const TaskSpace& space, const std::vector<TaskDim>& restrict) {
  std::vector<TaskDim> dims = space.dims();
  for (const TaskDim& r : restrict) {
    if (space.is_fixed(r.name)) continue;  // the run's value stands (checked at load against the whole space)
    const int i = space.index(r.name);
    if (i < 0) {  // a misspelt setting of the step reads as a parameter
      std::vector<std::string> known{"promote", "demote", "window"};
      for (const auto& d : space.dims()) known.push_back(d.name);
      throw Error("'" + r.name + "' is neither a step's setting (promote, demote, window) nor a parameter of the "
                  "task space (" + space.describe() + ")" + suggestion(r.name, known));
    }
    if (!space.covers(r)) throw Error(not_covered(space, size_t(i), r));
    TaskDim d = r;
    // A choice of a choice axis keeps the space's spelling of its values, so that its tasks
    // read back through the space (a single value of any axis is a one-value choice).
    const TaskDim& whole = space.dims()[size_t(i)];
    if (d.kind == TaskDim::Kind::kChoice && whole.kind == TaskDim::Kind::kChoice)
      for (auto& c : d.choices) c = whole.choices[size_t(*space.value_of(size_t(i), c))];
    dims[size_t(i)] = d;
  }
  return TaskSpace(std::move(dims));
}

std::vector<TaskPoint> draw_test_tasks(const TaskSpace& space, int count, uint64_t seed) {
  Rng rng(seed);
  std::vector<TaskPoint> out;
  out.reserve(size_t(std::max(0, count)));
  for (int i = 0; i < count; ++i) out.push_back(space.sample(rng));
  return out;
}

}  // namespace roger
