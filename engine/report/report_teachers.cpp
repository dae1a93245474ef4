// report_teachers.cpp: the tables that compare across runs (report_internal.h): one context under
// several teachers against the first (time to the threshold of % mastered, Mann-Whitney tests),
// and the final evaluations' success split by what each episode's world or task held.
#include "report/report_internal.h"

#include <algorithm>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "core/error.h"

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
  if (v->is_number()) return fmt("%.2f", v->get<double>());
  return v->dump();
}

// Sorts feature values as numbers when they all read as numbers, else as text.
bool value_less(const std::string& a, const std::string& b) {
  char* ea = nullptr;
  char* eb = nullptr;
  const double x = std::strtod(a.c_str(), &ea), y = std::strtod(b.c_str(), &eb);
  if (!a.empty() && !b.empty() && *ea == '\0' && *eb == '\0') return x < y;
  return a < b;
}

}  // namespace

void compare_table(const BatchScript& b, const BatchTable& t, const Folder& folder, std::ostringstream& md, json& rep) {
  if (!t.by.empty()) return by_table(b, t, folder, md, rep);
  const Results base = rows_results(b, t.compare.front(), folder);
  const std::vector<CensoredTime> base_times = times_of(base);
  const double base_mean = base_times.empty() ? 0.0 : mean(censored_values(base_times));
  md << "## " << t.title << "\n\nRows: a context of a run each, against `" << t.baseline << "`.\n\n";
  md << "| Approach | Train time (min:sec) | % Improvement | Avg. reward ± std | Success rate | Median time | "
        "IQM time [95% CI] | Reached | p (Mann-Whitney vs "
     << t.baseline << ") | P(faster than " << t.baseline << ") | Trials |\n";
  md << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  json rows = json::array();
  bool any_censored = false;
  for (const BatchRow& row : t.compare)
    any_censored |= run_table_row(row.label(), rows_results(b, row, folder), t, base_times, base_mean, md, rows);
  run_table_notes(any_censored, md);
  md << "With a test set (a stage that teaches), the success rate is the share of its tasks the final greedy "
        "policies master, and train time runs to the first checkpoint from which that share stays at or above "
        "the threshold.\n\n";
  rep.push_back({{"title", t.title}, {"compare", rows.size()}, {"baseline", t.baseline}, {"rows", rows}});
}

void by_table(const BatchScript& b, const BatchTable& t, const Folder& folder, std::ostringstream& md, json& rep) {
  struct Cell {
    int64_t episodes = 0, successes = 0;
  };
  std::vector<BatchRow> rows = rows_of(b, t);
  std::vector<std::map<std::string, Cell>> cells(rows.size());
  std::set<std::string, decltype(&value_less)> values(&value_less);
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
        json record;
        try {
          record = json::parse(line);
        } catch (const std::exception& e) {
          throw Error(file.string() + ":" + std::to_string(line_no) + ": not JSON: " + e.what());
        }
        const std::string v = feature_of(record, t.by);
        if (v.empty()) continue;
        values.insert(v);
        Cell& c = cells[k][v];
        ++c.episodes;
        c.successes += record.value("success", false);
      }
    }
  }
  md << "## " << t.title << "\n\nSuccess rate of the final greedy evaluations (every trial's episodes pooled) by `" << t.by
     << "`, with the episodes in each cell.\n\n| Approach |";
  for (const auto& v : values) md << " " << t.by << " = " << v << " |";
  md << "\n|---|";
  for (size_t i = 0; i < values.size(); ++i) md << "---|";
  md << "\n";
  json out = json::array();
  for (size_t k = 0; k < rows.size(); ++k) {
    md << "| " << (t.compare.empty() ? rows[k].context : rows[k].label()) << " |";
    json row = {{"run", rows[k].run}, {"context", rows[k].context}, {"cells", json::object()}};
    for (const auto& v : values) {
      const auto it = cells[k].find(v);
      if (it == cells[k].end() || it->second.episodes == 0) {
        md << " - |";
        continue;
      }
      const double rate = double(it->second.successes) / double(it->second.episodes);
      md << " " << pct(rate) << " (" << it->second.episodes << ") |";
      row["cells"][v] = {{"success_rate", rate}, {"episodes", it->second.episodes}};
    }
    md << "\n";
    out.push_back(row);
  }
  if (values.empty()) md << "\nNo trial has recorded its final evaluation's episodes (final.jsonl) yet.\n";
  md << "\n";
  rep.push_back({{"title", t.title}, {"by", t.by}, {"rows", out}});
}

bool tasks_figure(const BatchScript&, const BatchFigure&, const Folder&, std::vector<std::string>&, json&) {
  return false;  // drawn below, once written
}

}  // namespace roger::report_detail
