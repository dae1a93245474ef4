// report_teachers.cpp: the tables that compare across runs (report_internal.h): one context under
// several teachers against the first (time to the threshold of % mastered, Mann-Whitney tests),
// and the final evaluations' success split by what each episode's world or task held.
#include "report/report_internal.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "core/json_input.h"
#include "core/error.h"
#include "core/fileio.h"
#include "core/text.h"
#include "report/plot.h"
#include "teach/teach.h"

namespace roger::report_detail {
namespace {

Results rows_results(const BatchScript& b, const BatchRow& row, const Folder& folder) {
  return folder.run(*b.run(row.run), row.context);
}

// The rows a table is about: its comparison's, or every context of its run.
std::vector<BatchRow> rows_of(const BatchScript& b, const BatchTable& t) {
  if (!t.compare.empty()) return t.compare;
  std::vector<BatchRow> rows;
  for (const auto& c : b.run(t.run)->contexts) rows.push_back({t.run, c});
  return rows;
}

// The value of `feature` in a final-evaluation record (final.jsonl): a task parameter when the
// task has it, else what the world held ("obstacles", "objects", "shape": the first object's).
std::string feature_of(const json& record, const std::string& feature) {
  const json none;
  const json& task = record.contains("task") ? record["task"] : none;
  const json& world = record.contains("world") ? record["world"] : none;
  const json* v = nullptr;
  if (task.is_object() && task.contains(feature)) v = &task[feature];
  else if (world.is_object() && world.contains(feature)) v = &world[feature];
  else if (feature == "shape" && world.is_object() && world.contains("shapes") && !world["shapes"].empty())
    v = &world["shapes"][0];
  if (!v) return "";
  if (v->is_string()) return v->get<std::string>();
  if (v->is_number_integer()) return std::to_string(v->get<int64_t>());
  // A short fraction as written (a choice's 0.125), a long one (a real axis's draw) to two decimals.
  if (v->is_number()) {
    const std::string exact = format_number(v->get<double>());
    return exact.size() <= 6 ? exact : fmt("%.2f", v->get<double>());
  }
  return v->dump();
}

// A value's number, or a bin's lower edge ("3.47 to 8.43"): false when it reads as neither.
bool leading_number(const std::string& s, double& x) {
  char* end = nullptr;
  x = std::strtod(s.c_str(), &end);
  return !s.empty() && end != s.c_str() && std::isfinite(x) && (*end == '\0' || std::strncmp(end, " to ", 4) == 0);
}

// Sorts feature values as numbers when both read as numbers, else as text; bins too, by their
// lower edges (found by a probe: "13.39 to 18.35" came before "3.47 to 8.43", a false trend read
// left to right).
bool value_less(const std::string& a, const std::string& b) {
  double x = 0.0, y = 0.0;
  if (leading_number(a, x) && leading_number(b, y) && x != y) return x < y;
  return a < b;
}

// "T_alp/DC3: 3 tasks in 2 trials; ...": the training tasks each row's trials skipped because the
// scenario could not place their worlds (result.json "skipped_tasks"), or "" when none did.
std::string skipped_text(const BatchScript& b, const std::vector<BatchRow>& rows, const Folder& folder, json& rep) {
  std::string text;
  for (const BatchRow& row : rows) {
    size_t tasks = 0, trials = 0;
    for (const json& j : rows_results(b, row, folder).ok) {
      const size_t n = j.value("skipped_tasks", json::array()).size();  // a list: checked on reading
      tasks += n, trials += n > 0;
    }
    if (tasks == 0) continue;
    rep.push_back({{"row", row.label()}, {"tasks", tasks}, {"trials", trials}});
    text += (text.empty() ? "" : "; ") + row.label() + ": " + counted(tasks, "task") + " in " + counted(trials, "trial");
  }
  return text;
}

// A line per finished trial of the rows whose teacher kept a state: "- T_seq/DC3 trial 0: at step
// 3 of 3; moved at episodes 41, 97" (describe_teacher_state, as roger train prints it), or "" when
// none did (found by a probe: the report said nothing of what the teachers did; each trial's
// result.json had it).
std::string teachers_text(const BatchScript& b, const std::vector<BatchRow>& rows, const Folder& folder, json& rep) {
  std::string text;
  for (const BatchRow& row : rows)
    for (const json& j : rows_results(b, row, folder).ok) {
      const json state = j.contains("teacher") && j["teacher"].is_object() ? j["teacher"].value("state", json()) : json();
      const std::string did = describe_teacher_state(state);
      if (did.empty()) continue;
      const json trial = j.value("trial", json());
      // Named by its kind (found by a probe: "Look/Gaze trial 0: 6 fits" said not which teacher).
      const std::string kind = j["teacher"].value("kind", std::string());
      rep.push_back({{"row", row.label()}, {"trial", trial}, {"kind", kind}, {"did", did}});
      text += "- " + row.label() + " trial " + trial.dump() + (kind.empty() ? "" : " (" + kind + ")") + ": " + did + "\n";
    }
  return text;
}

// "; run `SG_M`: stage SG with noise_image=10": the stage and the parameters of each run the rows
// come from that its name does not say (another stage's name, or parameters), in their order
// (found by a probe: a row trained under noise stood beside a noise-free one with nothing to tell
// them apart), or "" when none; every run into report.json's "runs".
std::string runs_text(const BatchScript& b, const std::vector<BatchRow>& rows, json& rep) {
  std::vector<std::string> said, parts;
  for (const BatchRow& row : rows) {
    if (std::find(said.begin(), said.end(), row.run) != said.end()) continue;
    said.push_back(row.run);
    const BatchRun& run = *b.run(row.run);
    json params = json::object();
    for (const auto& [k, v] : run.params) params[k] = v;
    rep.push_back({{"run", run.name}, {"stage", run.stage}, {"params", params}});
    if (run.name != run.stage || !run.params.empty())
      parts.push_back("run `" + run.name + "`: stage " + run.stage + with_params(run.params));
  }
  return parts.empty() ? "" : "; " + join(parts, "; ");
}

}  // namespace

void compare_table(const BatchScript& b, const BatchTable& t, const Folder& folder, std::ostringstream& md, json& rep) {
  if (!t.by.empty()) {
    by_table(b, t, folder, md, rep);
    return;
  }
  json rep_runs = json::array();
  const Results base = rows_results(b, t.compare.front(), folder);
  const std::vector<CensoredTime> base_times = times_of(base);
  const double base_mean = base_times.empty() ? 0.0 : mean(censored_values(base_times));
  md << "## " << t.title << "\n\nRows: a context of a run each, against `" << t.baseline << "`"
     << runs_text(b, t.compare, rep_runs) << ".\n\n";
  md << "| Approach | Train time (min:sec) | % Improvement | Avg. reward ± std | Success rate | Median time | "
        "IQM time [95% CI] | Reached | p (Mann-Whitney vs "
     << t.baseline << ") | P(faster than " << t.baseline << ") | Trials |\n";
  md << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  json rows = json::array();
  bool any_censored = false;
  for (const BatchRow& row : t.compare)
    any_censored |= run_table_row(row.label(), rows_results(b, row, folder), t, base_times, base_mean, md, rows);
  run_table_notes(any_censored, md);
  json table = {{"title", t.title}, {"compare", rows.size()}, {"baseline", t.baseline}, {"rows", rows}, {"runs", rep_runs}};
  teaching_notes(b, t.compare, folder, md, table);
  rep.push_back(table);
}

// Under a table of rows whose stages teach (a trial's result.json has a "teacher"; nothing when
// none does): what success means with a test set, the training tasks skipped, and what each
// trial's teacher did, into the table's "skipped_tasks" and "teachers". Found by a probe: a run's
// own table, the one a batch writes by default, said none of it; only a comparison did.
void teaching_notes(const BatchScript& b, const std::vector<BatchRow>& rows, const Folder& folder,
                    std::ostringstream& md, json& table) {
  bool teaches = false;
  for (const BatchRow& row : rows)
    for (const json& j : rows_results(b, row, folder).ok) teaches = teaches || j.contains("teacher");
  if (!teaches) return;
  md << "With a test set (a stage that teaches), the success rate is the share of its tasks the final greedy "
        "policies master, and train time runs to the first checkpoint from which that share stays at or above "
        "the threshold.\n\n";
  json skipped = json::array();
  const std::string skips = skipped_text(b, rows, folder, skipped);
  if (!skips.empty())
    md << "Training tasks skipped because the scenario could not place their worlds (each replaced by the "
          "teacher's next draw; the trial's result.json, \"skipped_tasks\"): "
       << skips << ".\n\n";
  json teachers = json::array();
  const std::string did = teachers_text(b, rows, folder, teachers);
  if (!did.empty()) md << "What each trial's teacher did (its result.json, \"teacher\"):\n\n" << did << "\n";
  table["skipped_tasks"] = skipped;
  table["teachers"] = teachers;
}

namespace {

using FeatureSeen = std::vector<std::vector<std::pair<std::string, bool>>>;  // (value, success) per row

// What the final evaluations' records (final.jsonl) of each row's trials say of one feature.
struct FeatureRecords {
  FeatureSeen seen;
  int64_t records = 0;             // read, with or without the feature
  std::set<std::string> features;  // what the records have, for a feature none has
  std::vector<std::string> missing;  // per row: file:line of its first record without the feature
};

// Line line_no of `file`, checked to be a final-evaluation record; roger::Error at file:line if not.
json final_record(const std::string& line, const fs::path& file, int line_no) {
  json record;
  try {
    record = parse_json(line);
  } catch (const std::exception& e) {
    throw Error(file.string() + ":" + std::to_string(line_no) + ": not JSON: " + json_error_text(e.what()));
  }
  const std::string where = file.string() + ":" + std::to_string(line_no) + ": ";
  if (!record.is_object()) throw Error(where + "a final-evaluation record must be a JSON object");
  if (!record.contains("success") || !record["success"].is_boolean())
    throw Error(where + "field \"success\" must be true or false, got " +
                (record.contains("success") ? record["success"].dump() : std::string("nothing")));
  // What the world held, as roger writes it (found by a probe: "obstacles": "many", edited in, made a
  // column of its own in a --by table).
  if (record.contains("world")) {
    const json& world = record["world"];
    if (!world.is_object()) throw Error(where + "field \"world\" must be an object, got " + world.dump());
    for (const char* count : {"obstacles", "objects"})
      if (world.contains(count) && !(world[count].is_number_unsigned() ||
                                     (world[count].is_number_integer() && world[count].get<int64_t>() >= 0)))
        throw Error(where + "field \"world\": \"" + count + "\" must be a count, got " + world[count].dump());
    if (world.contains("shapes") && !(world["shapes"].is_array() &&
                                      std::all_of(world["shapes"].begin(), world["shapes"].end(),
                                                  [](const json& v) { return v.is_string(); })))
      throw Error(where + "field \"world\": \"shapes\" must be a list of shape names, got " + world["shapes"].dump());
  }
  return record;
}

FeatureRecords read_feature(const BatchScript& b, const std::vector<BatchRow>& rows, const std::string& by,
                            const Folder& folder) {
  FeatureRecords r;
  r.seen.resize(rows.size());
  r.missing.resize(rows.size());
  for (size_t k = 0; k < rows.size(); ++k) {
    const BatchRun& run = *b.run(rows[k].run);
    for (int i = 0; i < run.trials; ++i) {
      const fs::path file = fs::path(trial_dir(folder.dir(), batch_trial_id(run.name, rows[k].context, i))) / "final.jsonl";
      std::ifstream in(file);
      if (!in) continue;  // pending or failed, or written before final.jsonl existed
      int line_no = 0;
      for (std::string line; std::getline(in, line);) {
        ++line_no;
        if (line.empty()) continue;
        const json record = final_record(line, file, line_no);
        ++r.records;
        for (const char* part : {"task", "world"})
          if (record.contains(part) && record[part].is_object())
            for (const auto& [name, value] : record[part].items()) r.features.insert(name == "shapes" ? "shape" : name);
        const std::string v = feature_of(record, by);
        if (!v.empty()) r.seen[k].push_back({v, record["success"].get<bool>()});
        else if (r.missing[k].empty()) r.missing[k] = file.string() + ":" + std::to_string(line_no);
      }
    }
  }
  return r;
}

// The table's columns: each value, or five equal bins of the range when the values are many
// fractions (a real axis of a task space).
class FeatureColumns {
 public:
  explicit FeatureColumns(const FeatureSeen& seen) {
    std::set<std::string, decltype(&value_less)> distinct(&value_less);
    bool fractions = true;
    for (const auto& row : seen)
      for (const auto& [v, ok] : row) {
        distinct.insert(v);
        char* end = nullptr;
        const double x = std::strtod(v.c_str(), &end);
        fractions = fractions && *end == '\0' && !v.empty();
        if (fractions) lo_ = std::min(lo_, x), hi_ = std::max(hi_, x);
      }
    binned_ = fractions && distinct.size() > 8 && hi_ > lo_;
  }
  // The column of value v.
  std::string of(const std::string& v) const {
    if (!binned_) return v;
    const int bin = std::min(4, int((std::strtod(v.c_str(), nullptr) - lo_) / (hi_ - lo_) * 5));
    return bin_label(lo_, hi_, bin, 5);
  }
  // The columns with no value yet: every bin, an empty one too ("five equal bins" with one left
  // out read as four, found by a probe).
  std::vector<std::string> always() const {
    std::vector<std::string> bins;
    if (binned_)
      for (int bin = 0; bin < 5; ++bin) bins.push_back(of(fmt("%.17g", lo_ + (hi_ - lo_) * (bin + 0.5) / 5)));
    return bins;
  }

 private:
  bool binned_ = false;
  double lo_ = 1e300, hi_ = -1e300;
};

}  // namespace

ByFound by_table(const BatchScript& b, const BatchTable& t, const Folder& folder, std::ostringstream& md, json& rep) {
  struct Cell {
    int64_t episodes = 0, successes = 0;
  };
  const std::vector<BatchRow> rows = rows_of(b, t);
  const FeatureRecords found = read_feature(b, rows, t.by, folder);
  // A record without the feature the others of its row hold (the row's trials record the same
  // fields) was left out of every cell, unsaid (found by a probe: a line edited by hand, and a row
  // read 11 episodes of 12). Rows apart may differ: a run without a teacher records no task.
  for (size_t k = 0; k < rows.size(); ++k)
    if (!found.missing[k].empty() && !found.seen[k].empty())
      throw Error(found.missing[k] + ": a final-evaluation record without '" + t.by + "', which the others of " +
                  rows[k].label() + " hold");
  const FeatureColumns columns(found.seen);
  std::vector<std::map<std::string, Cell>> cells(rows.size());
  std::set<std::string, decltype(&value_less)> values(&value_less);
  for (const std::string& col : columns.always()) values.insert(col);
  for (size_t k = 0; k < rows.size(); ++k)
    for (const auto& [v, ok] : found.seen[k]) {
      const std::string col = columns.of(v);
      values.insert(col);
      ++cells[k][col].episodes;
      cells[k][col].successes += ok;
    }
  // Each row says the trials it pools, and those failed or pending, as the other tables do (found by
  // a probe: a row pooling 2 of 4 trials read as all 4, and one with none as a row of "-").
  md << "## " << t.title << "\n\nSuccess rate of the final greedy evaluations (every trial's episodes pooled) by `" << t.by
     << "`, with the episodes in each cell; Trials: the trials pooled, of those asked for.\n\n| Approach |";
  for (const auto& v : values) md << " " << t.by << " = " << v << " |";
  md << " Trials |\n|---|";
  for (size_t i = 0; i <= values.size(); ++i) md << "---|";
  md << "\n";
  json out = json::array();
  for (size_t k = 0; k < rows.size(); ++k) {
    const Results pooled = folder.run(*b.run(rows[k].run), rows[k].context);
    md << "| " << (t.compare.empty() ? rows[k].context : rows[k].label()) << " |";
    json row = {{"run", rows[k].run},       {"context", rows[k].context},  {"cells", json::object()},
                {"trials", pooled.ok.size()}, {"failed", pooled.failed}, {"pending", pooled.pending}};
    for (const auto& v : values) {
      const auto it = cells[k].find(v);
      if (it == cells[k].end() || it->second.episodes == 0) {
        md << " - |";
        continue;
      }
      const double rate = double(it->second.successes) / double(it->second.episodes);
      md << " " << rate_pct(rate) << " (" << it->second.episodes << ") |";
      row["cells"][v] = {{"success_rate", rate}, {"episodes", it->second.episodes}};
    }
    md << " " << trials_note(pooled) << " |\n";
    out.push_back(row);
  }
  if (values.empty() && found.records == 0) md << "\nNo trial has recorded its final evaluation's episodes (final.jsonl) yet.\n";
  else if (values.empty())
    md << "\nNone of the " << counted(found.records, "final-evaluation episode") << " has a feature '" << t.by
       << "'; they have: " << join(std::vector<std::string>(found.features.begin(), found.features.end())) << ".\n";
  md << "\n";
  rep.push_back({{"title", t.title}, {"by", t.by}, {"rows", out}});
  return {found.records, !values.empty(), found.features};
}

namespace {

// The values of `param` the training episodes of a run's context drew, by episode index, over its
// finished trials (episodes.jsonl); numbers as numbers, other values as text.
struct Drawn {
  std::string space;                        // the trials' task space as result.json records it
  std::vector<std::pair<int, json>> draws;  // (episode index, value)
  int episodes = 0;                         // the longest trial's training episodes
  int trials = 0;                           // trials whose draws these are
  std::vector<std::string> missing;         // finished trials without episodes.jsonl (deleted?)
};

// A trial's task space as its result.json records it ("obstacles = roger.int(0, 6), shape =
// roger.choice{circle, spade}"), or "" (an unreadable record is the tables' to report).
std::string recorded_space(const fs::path& result) {
  try {
    const json r = parse_json(read_file_text(result.string()));
    return r.is_object() && r.contains("tasks") && r["tasks"].is_string() ? r["tasks"].get<std::string>() : "";
  } catch (const std::exception&) {
    return "";
  }
}

// The axis of `param` in a recorded task space, so that the map shows the whole axis (values
// never drawn included) rather than the range the draws happened to cover.
struct Axis {
  enum class Kind { kInt, kReal, kChoice } kind = Kind::kReal;
  double lo = 0.0, hi = 0.0;
  std::vector<std::string> choices;
};

// Where `name = roger.` begins an axis of a space's text (at its start or after ", "), from `from`;
// npos when nowhere. Read by hand, not by std::regex, whose matcher recurses once per character:
// a choice of a 100 KB string overflowed the stack (found by a probe).
size_t axis_head(const std::string& space, const std::string& name, size_t from) {
  const std::string head = name + " = roger.";
  for (size_t at = space.find(head, from); at != std::string::npos; at = space.find(head, at + 1))
    if (at == 0 || (at >= 2 && space.compare(at - 2, 2, ", ") == 0)) return at + head.size();
  return std::string::npos;
}

// A number as the text of a range's end writes it ([-+0-9.eE]+), consumed from `at`; "" if none.
std::string range_end(const std::string& s, size_t& at) {
  const size_t from = at;
  while (at < s.size() && s[at] != '\0' && std::strchr("-+0123456789.eE", s[at])) ++at;
  return s.substr(from, at - from);
}

std::optional<Axis> range_axis(const std::string& space, const std::string& name) {
  for (size_t at = axis_head(space, name, 0); at != std::string::npos; at = axis_head(space, name, at)) {
    Axis a;
    size_t i = at;
    if (space.compare(i, 4, "int(") == 0) a.kind = Axis::Kind::kInt, i += 4;
    else if (space.compare(i, 5, "real(") == 0) a.kind = Axis::Kind::kReal, i += 5;
    else continue;
    const std::string lo = range_end(space, i);
    if (lo.empty() || space.compare(i, 2, ", ") != 0) continue;
    i += 2;
    const std::string hi = range_end(space, i);
    if (hi.empty() || space.compare(i, 1, ")") != 0) continue;
    a.lo = std::strtod(lo.c_str(), nullptr);
    a.hi = std::strtod(hi.c_str(), nullptr);
    return a;
  }
  return std::nullopt;
}

std::optional<Axis> choice_axis(const std::string& space, const std::string& name) {
  for (size_t at = axis_head(space, name, 0); at != std::string::npos; at = axis_head(space, name, at)) {
    if (space.compare(at, 7, "choice{") != 0) continue;
    const size_t close = space.find('}', at + 7);
    if (close == std::string::npos) continue;
    Axis a;
    a.kind = Axis::Kind::kChoice;
    const std::string list = space.substr(at + 7, close - at - 7);  // "circle, triangle, spade", as TaskDim::text() joins them
    for (size_t from = 0; from <= list.size();) {
      const size_t comma = list.find(", ", from);
      a.choices.push_back(list.substr(from, comma == std::string::npos ? std::string::npos : comma - from));
      if (comma == std::string::npos) break;
      from = comma + 2;
    }
    return a;
  }
  return std::nullopt;
}

std::optional<Axis> axis_of(const std::string& space, const std::string& param) {
  if (param.empty() || !std::all_of(param.begin(), param.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
      }))
    return std::nullopt;
  if (const std::optional<Axis> a = range_axis(space, param)) {
    if (!(a->hi > a->lo) || (a->kind == Axis::Kind::kInt && a->hi - a->lo > 40)) return std::nullopt;
    return a;
  }
  return choice_axis(space, param);
}

Drawn drawn_values(const BatchRun& run, const std::string& context, const std::string& param, const Folder& folder) {
  Drawn d;
  for (int i = 0; i < run.trials; ++i) {
    const std::string id = batch_trial_id(run.name, context, i);
    const fs::path file = fs::path(trial_dir(folder.dir(), id)) / "episodes.jsonl";
    // A trial still running or pending has none yet, and a failed one's are what it did before
    // its fault, not a trial's draws; a finished one without them lost them, and the figure says
    // so rather than silently drawing fewer trials.
    std::error_code ec;
    if (!fs::exists(file.parent_path() / "result.json", ec)) continue;
    if (d.space.empty()) d.space = recorded_space(file.parent_path() / "result.json");
    std::ifstream in(file);
    if (!in) d.missing.push_back(id);
    if (!in) continue;
    ++d.trials;
    int line_no = 0;
    for (std::string line; std::getline(in, line);) {
      ++line_no;
      if (line.empty()) continue;
      json e;
      try {
        e = parse_json(line);
      } catch (const std::exception& ex) {
        throw Error(file.string() + ":" + std::to_string(line_no) + ": not JSON: " + ex.what());
      }
      const int index = e.value("index", line_no - 1);
      d.episodes = std::max(d.episodes, index + 1);
      if (e.contains("task") && e["task"].is_object() && e["task"].contains(param))
        d.draws.push_back({index, e["task"][param]});
    }
  }
  return d;
}

// A drawn value as its axis's text has it ("3", "0.25", "spade", "true"): rows are matched by it.
std::string drawn_text(const json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number_integer()) return std::to_string(v.get<int64_t>());
  if (v.is_number()) return format_number(v.get<double>());
  return v.dump();
}

// The heat map of the draws: 25 columns of episodes; a row per value drawn (integers and text),
// or 10 bins over the range drawn (other numbers).
HeatMap heat_of(const Drawn& d, const std::optional<Axis>& axis) {
  HeatMap m;
  const int columns = std::max(1, std::min(25, d.episodes));
  for (int c = 0; c <= columns; ++c) m.x_edges.push_back(double(d.episodes) * c / columns);
  bool reals = false;
  double lo = 1e300, hi = -1e300;
  std::set<std::string, decltype(&value_less)> values(&value_less);
  const bool choice = axis && axis->kind == Axis::Kind::kChoice;  // its fractions are values, not a range
  for (const auto& [i, v] : d.draws) {
    if (!choice && v.is_number() && !v.is_number_integer() && v.get<double>() != std::floor(v.get<double>())) reals = true;
    if (v.is_number()) lo = std::min(lo, v.get<double>()), hi = std::max(hi, v.get<double>());
    values.insert(drawn_text(v));
  }
  const int bins = 10;
  std::vector<std::string> rows = reals ? std::vector<std::string>{} : std::vector<std::string>(values.begin(), values.end());
  // The whole axis when the space records it: a value never drawn is a row of its own, and a real
  // axis's bins span its range, not the draws' (a teacher that never went past 1.8 of 2 shows it).
  if (axis && axis->kind == Axis::Kind::kReal && lo >= axis->lo && hi <= axis->hi) {
    reals = true;
    lo = axis->lo, hi = axis->hi;
  } else if (axis && !reals) {
    std::vector<std::string> whole = axis->choices;
    if (axis->kind == Axis::Kind::kInt)
      for (double x = axis->lo; x <= axis->hi; x += 1.0) whole.push_back(format_number(x));
    const bool covers = std::all_of(values.begin(), values.end(), [&](const std::string& v) {
      return std::find(whole.begin(), whole.end(), v) != whole.end();
    });
    if (covers && !whole.empty()) rows = whole;
  }
  if (reals)
    for (int b = 0; b < bins; ++b) rows.push_back(bin_label(lo, hi, b, bins));
  std::vector<std::vector<double>> count(rows.size(), std::vector<double>(size_t(columns), 0.0));
  std::vector<double> total(size_t(columns), 0.0);
  for (const auto& [i, v] : d.draws) {
    const size_t c = std::min<size_t>(size_t(columns) - 1, size_t(double(i) * columns / std::max(1, d.episodes)));
    size_t r = 0;
    if (reals) {
      r = hi > lo ? std::min<size_t>(bins - 1, size_t((v.get<double>() - lo) / (hi - lo) * bins)) : 0;
    } else {
      r = size_t(std::find(rows.begin(), rows.end(), drawn_text(v)) - rows.begin());
    }
    count[r][c] += 1.0;
    total[c] += 1.0;
  }
  for (auto& row : count)
    for (size_t c = 0; c < row.size(); ++c) row[c] = total[c] > 0 ? row[c] / total[c] : 0.0;
  m.rows = std::move(rows);
  m.share = std::move(count);
  return m;
}

}  // namespace

bool tasks_figure(const BatchScript& b, const BatchFigure& f, const Folder& folder, std::vector<std::string>& written,
                  json& page) {
  const Drawn d = drawn_values(*b.run(f.run), f.context, f.param, folder);
  const std::string title = f.title.empty() ? "Tasks drawn: " + f.param + ", " + f.run + "/" + f.context : f.title;
  json fig = {{"kind", "tasks"}, {"file", f.file}, {"run", f.run}, {"context", f.context}, {"param", f.param},
              {"title", title}, {"trials", d.trials}, {"missing", d.missing}};
  if (d.draws.empty()) {
    page.push_back(fig);
    return false;
  }
  const HeatMap m = heat_of(d, axis_of(d.space, f.param));
  fig["x_edges"] = m.x_edges;
  fig["rows"] = m.rows;
  json share = json::array();
  for (const auto& row : m.share) {
    json r = json::array();
    for (double v : row) r.push_back(std::round(v * 1e4) / 1e4);
    share.push_back(r);
  }
  fig["share"] = share;
  page.push_back(fig);
  HeatOptions o;
  o.y_label = f.param;
  const std::vector<std::string> paths = {(fs::path(folder.out()) / (f.file + ".png")).string(),
                                          (fs::path(folder.out()) / (f.file + ".svg")).string()};
  std::string trials = counted(d.trials, "trial");
  if (!d.missing.empty()) trials += "; " + std::to_string(d.missing.size()) + " finished without episodes.jsonl";
  plot_heat_map(paths, title + " (" + trials + ")", m, o);
  written.insert(written.end(), paths.begin(), paths.end());
  return true;
}

}  // namespace roger::report_detail
