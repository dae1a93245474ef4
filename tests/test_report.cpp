// Tests of engine/commands and engine/report: a tiny batch (a copy of the paper's curriculum with
// 20-episode budgets, 2 trials) writes every file of a results folder; the tables agree with the
// per-trial records; --jobs 1 and --jobs 2 give the same results apart from wall times; a run cut
// short resumes to exactly the trials of an uninterrupted run; a folder made by other parameters
// is refused; a failing trial is recorded without losing the others.
#include <catch2/catch.hpp>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <stdexcept>
#include <sstream>
#include <tuple>
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "batch/batch.h"
#include "cli/cli_internal.h"
#include "cli/commands.h"
#include "core/interrupt.h"
#include "core/text.h"
#include "learn/learning.h"
#include "report/report.h"
#include "report/report_internal.h"
#include "report/stats.h"
#include "temp_dir.h"
#include "test_files.h"

using namespace roger;
namespace fs = std::filesystem;
using json = nlohmann::json;
using Catch::Matchers::Contains;
using roger::test::slurp;

namespace {

void spit(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

// A scratch folder with a small-budget copy of the paper's curriculum and a batch script using it.
struct Fixture {
  fs::path root;
  explicit Fixture(const std::string& tag, const std::string& evaluation_params = "obstacles = 3",
                   const std::string& evaluation_scenario = "cluttered") {
    root = fs::temp_directory_path() / ("roger_report_" + tag + "_" + std::to_string(::getpid()));
    fs::remove_all(root);
    fs::create_directories(root);
    std::string cur = slurp("curricula/paper.lua");
    cur = std::regex_replace(cur, std::regex("budget = \\{ episodes = [0-9]+ \\}"), "budget = { episodes = 20 }");
    cur = std::regex_replace(cur, std::regex("final = 50"), "final = 10");
    spit(root / "curriculum.lua", cur);
    spit(root / "batch.lua",
         "return {\n"
         "  name = \"tiny\", curriculum = \"curriculum.lua\", trials = 2, seed = 5,\n"
         "  runs = {\n"
         "    { name = \"SG\", stage = \"SG\", contexts = { \"B1\", \"DC2\" } },\n"
         "    { name = \"T\", stage = \"T\", contexts = { \"DC6\" },\n"
         "      skills = { Phi_SG = { run = \"SG\", context = \"DC2\" } } },\n"
         "  },\n"
         "  evaluations = { { name = \"gen\", run = \"T\", context = \"DC6\", scenario = \"" + evaluation_scenario + "\",\n"
         "                    params = { " + evaluation_params + " }, shapes = { \"circle\", \"spade\" }, episodes = 3 } },\n"
         "  tables = {\n"
         "    { title = \"Table I\", run = \"SG\", baseline = \"B1\" },\n"
         "    { title = \"Table II\", run = \"T\" },\n"
         "    { title = \"Table III\", evaluation = \"gen\" },\n"
         "  },\n"
         "  figures = {\n"
         "    { file = \"figure3\", run = \"SG\" },\n"
         "    { file = \"figure4\", run = \"T\", log_x = true },\n"
         "    { file = \"figure5\", run = \"T\", kind = \"cumulative\" },\n"
         "  },\n"
         "}\n");
  }
  ~Fixture() { fs::remove_all(root); }
  // The arguments of `roger run batch.lua --out ROOT/out --jobs J [--only ...]`.
  RunArgs args(const std::string& out, int jobs, std::vector<std::string> only = {}) const {
    RunArgs a;
    a.script = (root / "batch.lua").string();
    a.out = (root / out).string();
    a.jobs = jobs;
    a.only = std::move(only);
    return a;
  }
  int run(const std::string& out, int jobs, int max_trials = 0, std::string* log = nullptr) const {
    RunArgs a = args(out, jobs);
    a.max_trials = max_trials;
    std::ostringstream os;
    a.progress = &os;
    const int status = command_run(a);
    if (log) *log = os.str();
    return status;
  }
};

const std::vector<std::string> kIds = {
    "SG/B1/000", "SG/B1/001", "SG/DC2/000", "SG/DC2/001", "T/DC6/000", "T/DC6/001",
    "eval/gen/circle/000", "eval/gen/circle/001", "eval/gen/spade/000", "eval/gen/spade/001"};

// A result without its wall-clock fields (the only ones that may differ between runs).
json without_wall(json j) {
  if (j.is_object()) {
    json out = json::object();
    for (auto it = j.begin(); it != j.end(); ++it)
      if (it.key().find("wall") == std::string::npos) out[it.key()] = without_wall(*it);
    return out;
  }
  if (j.is_array()) {
    json out = json::array();
    for (auto& e : j) out.push_back(without_wall(e));
    return out;
  }
  return j;
}

// summary.csv without its wall_s column.
std::string csv_without_wall(const std::string& csv) {
  std::istringstream in(csv);
  std::string line, out;
  int wall = -1;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) cells.push_back(c);
    if (wall < 0)
      for (size_t i = 0; i < cells.size(); ++i)
        if (cells[i] == "wall_s") wall = int(i);
    for (size_t i = 0; i < cells.size(); ++i)
      if (int(i) != wall) out += cells[i] + ",";
    out += "\n";
  }
  return out;
}

void same_results(const fs::path& a, const fs::path& b) {
  for (const auto& id : kIds) {
    INFO(id);
    REQUIRE(fs::exists(fs::path(trial_dir(a.string(), id)) / "result.json"));
    REQUIRE(fs::exists(fs::path(trial_dir(b.string(), id)) / "result.json"));
    CHECK(without_wall(json::parse(slurp(fs::path(trial_dir(a.string(), id)) / "result.json"))) ==
          without_wall(json::parse(slurp(fs::path(trial_dir(b.string(), id)) / "result.json"))));
  }
  CHECK(csv_without_wall(slurp(a / "summary.csv")) == csv_without_wall(slurp(b / "summary.csv")));
  CHECK(slurp(a / "tables.md") == slurp(b / "tables.md"));
  CHECK(slurp(a / "report.json") == slurp(b / "report.json"));
}

std::vector<std::string> finished_ids(const fs::path& out) {
  std::vector<std::string> ids;
  for (const auto& id : kIds)
    if (fs::exists(fs::path(trial_dir(out.string(), id)) / "result.json")) ids.push_back(id);
  return ids;
}

// The object a generated script assigns ("window.NAME = {...};"), parsed.
json script_data(const fs::path& p, const std::string& name) {
  const std::string text = slurp(p);
  const std::string head = "window." + name + " = ";
  const size_t at = text.find(head);
  REQUIRE(at != std::string::npos);
  const size_t end = text.rfind(';');
  return json::parse(text.substr(at + head.size(), end - at - head.size()));
}

// The dashboard of a finished folder: a page that needs no network, the report's own numbers in
// dashboard.js (the tables of report.json, every table cell of tables.md, curves whose IQM lies in
// its interval), every trial linked, and the run's final status.
void check_dashboard(const fs::path& dir, const std::string& tables, const json& rep) {
  // No address but the SVG namespace's (a name, never fetched).
  const std::string page =
      std::regex_replace(slurp(dir / "index.html"), std::regex("\"http://www.w3.org/2000/svg\""), "SVGNS");
  REQUIRE(!page.empty());
  CHECK(!std::regex_search(page, std::regex("https?:")));
  CHECK(page.find("status.js") != std::string::npos);
  CHECK(page.find("dashboard.js") != std::string::npos);
  const json d = script_data(dir / "dashboard.js", "ROGER_REPORT");
  // report.json's tables, and for the usage chart each context's actions as tables.md lists them.
  json page_tables = d["tables"];
  for (json& t : page_tables) {
    if (!t.contains("usage")) continue;
    REQUIRE(t.contains("usage_order"));
    for (const auto& [context, shares] : t["usage"].items()) {
      std::vector<std::string> listed = t["usage_order"][context], named;
      for (const auto& [action, share] : shares.items()) named.push_back(action);
      std::sort(listed.begin(), listed.end());
      CHECK(listed == named);
    }
    t.erase("usage_order");
  }
  CHECK(page_tables == rep["tables"]);
  std::vector<std::string> md_rows, page_rows;
  std::istringstream lines(tables);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("|", 0) == 0 && line.rfind("|---", 0) != 0) md_rows.push_back(line);
  for (const json& b : d["blocks"]) {
    if (b["kind"] != "table") continue;
    for (const json& row : std::vector<json>{b["header"]}) {
      std::string line = "|";
      for (const auto& c : row) line += " " + c.get<std::string>() + " |";
      page_rows.push_back(line);
    }
    for (const json& row : b["rows"]) {
      std::string line = "|";
      for (const auto& c : row) line += " " + c.get<std::string>() + " |";
      page_rows.push_back(line);
    }
  }
  CHECK(page_rows == md_rows);
  int curves = 0;
  for (const json& fig : d["figures"]) {
    if (fig["kind"] != "curves") continue;
    for (const json& s : fig["series"]) {
      ++curves;
      REQUIRE(s["iqm"].size() == s["minutes"].size());
      for (size_t k = 0; k < s["iqm"].size(); ++k) {
        CHECK(s["iqm_low"][k].get<double>() <= s["iqm"][k].get<double>() + 1e-9);
        CHECK(s["iqm"][k].get<double>() <= s["iqm_high"][k].get<double>() + 1e-9);
      }
    }
  }
  CHECK(curves == 3);  // SG: B1, DC2; T: DC6
  size_t linked = 0;
  for (const json& run : d["trials"]["runs"])
    for (const json& c : run["contexts"])
      for (const json& t : c["trials"]) {
        CHECK(t["state"] == "ok");
        CHECK(fs::is_directory(dir / t["folder"].get<std::string>()));
        ++linked;
      }
  for (const json& ev : d["trials"]["evaluations"])
    for (const json& g : ev["groups"]) linked += g["trials"].size();
  CHECK(linked == kIds.size());
  const json status = json::parse(slurp(dir / "status.json"));
  CHECK(status["running"] == false);
  CHECK(status["done"] == kIds.size());
  CHECK(script_data(dir / "status.js", "ROGER_STATUS") == status);
}

// Table III of a finished tiny run (2 policies, 3 episodes per shape), each policy in worlds of its
// own and each shape in layouts of its own: the circle's trials start at the first seed and 3 past
// it, the spade's (the second shape) at 6 and 9, so each shape's row holds 6 distinct layouts and the
// Total 12. The interval resamples the two policies, never narrower than Wilson's over the layouts.
// Rewritten as if both policies had met the same layouts of each shape, each shape holds 3, the
// interval resamples policies and layouts, and it is never narrower than Wilson's over 3.
void check_own_worlds(const fs::path& dir, const std::string& tables, const json& rep) {
  auto result = [&](const fs::path& d, const char* id) {
    return json::parse(slurp(fs::path(trial_dir(d.string(), id)) / "result.json"));
  };
  const json c0 = result(dir, "eval/gen/circle/000"), s0 = result(dir, "eval/gen/spade/000");
  const int64_t first = c0["first_seed"].get<int64_t>();
  CHECK(result(dir, "eval/gen/circle/001")["first_seed"].get<int64_t>() == first + 3);
  CHECK(s0["first_seed"].get<int64_t>() == first + 6);
  CHECK(result(dir, "eval/gen/spade/001")["first_seed"].get<int64_t>() == first + 9);
  const std::string outcomes = s0["outcomes"];
  CHECK(outcomes.size() == 3);
  CHECK(std::count(outcomes.begin(), outcomes.end(), '1') == s0["successes"].get<int>());
  CHECK(tables.find("each policy in worlds of its own") != std::string::npos);
  CHECK(tables.find("| Layouts |") != std::string::npos);
  const json& rows = rep["tables"][2]["rows"];
  REQUIRE(rows.size() == 3);
  for (const auto& [row, layouts] : {std::pair<int, double>{0, 6}, {1, 6}, {2, 12}}) {
    INFO("row " << row);
    CHECK(rows[row]["layouts"] == layouts);
    // Two policies in every row; the Total's evaluations are each on each shape (it counted them
    // as policies).
    CHECK(rows[row]["policies"] == 2);
    CHECK(rows[row]["evaluations"] == (row == 2 ? 4 : 2));
    CHECK(rows[row]["interval"] == "policies");
    const double rate = rows[row]["success_rate"].get<double>();
    CHECK(rows[row]["success_low"].get<double>() <= wilson_interval(rate * layouts, layouts).low);
    CHECK(rows[row]["success_high"].get<double>() >= wilson_interval(rate * layouts, layouts).high);
  }
  CHECK(tables.find("| 12 |\n") != std::string::npos);
  // The per-policy column is in report.json too (found by a probe: only tables.md had it).
  const double c1 = result(dir, "eval/gen/circle/001")["successes"].get<int>() / 3.0,
               c0_rate = c0["successes"].get<int>() / 3.0;
  CHECK(rows[0]["per_policy_success_mean"].get<double>() == Approx((c0_rate + c1) / 2));
  CHECK(rows[0]["per_policy_success_std"].get<double>() == Approx(std::abs(c0_rate - c1) / 2));

  const fs::path shared = dir.string() + "_shared";
  fs::remove_all(shared);
  fs::copy(dir, shared, fs::copy_options::recursive);
  json manifest = json::parse(slurp(shared / "manifest.json"));
  manifest["config"]["evaluations"][0]["worlds"] = "shared";
  spit(shared / "manifest.json", manifest.dump(1));
  for (const char* shape : {"circle", "spade"}) {
    const fs::path p = fs::path(trial_dir(shared.string(), std::string("eval/gen/") + shape + "/001")) / "result.json";
    json r = json::parse(slurp(p));
    r["first_seed"] = result(dir, (std::string("eval/gen/") + shape + "/000").c_str())["first_seed"];
    spit(p, r.dump());
  }
  write_report(shared.string());
  const json srep = json::parse(slurp(shared / "report.json"));
  const json& srows = srep["tables"][2]["rows"];
  CHECK(srows[0]["layouts"] == 3);
  CHECK(srows[2]["layouts"] == 6);
  CHECK(srows[2]["interval"] == "policies and layouts");
  CHECK(srows[2]["success_low"].get<double>() <= wilson_interval(srows[2]["success_rate"].get<double>() * 6, 6).low);
  CHECK(slurp(shared / "tables.md").find("every policy in the same worlds") != std::string::npos);
  fs::remove_all(shared);
}

}  // namespace

TEST_CASE("curve_grid interpolates checkpoints onto a common grid", "[report]") {
  const CurveGrid g = curve_grid({{{10, 0}, {20, 100}}, {{15, 50}, {30, 100}}}, 4, false);
  REQUIRE(g.t.size() == 4);
  CHECK(g.t.front() == Approx(15));
  CHECK(g.t.back() == Approx(30));
  CHECK(g.values[0][0] == Approx(50));   // halfway between its checkpoints
  CHECK(g.values[0][3] == Approx(100));  // stopped at 20: holds its last value
  CHECK(g.values[1][0] == Approx(50));
  const CurveGrid l = curve_grid({{{10, 0}, {1000, 100}}}, 3, true);
  CHECK(l.t[1] == Approx(100));
}

TEST_CASE("curve_bands: mean, std and the IQM with its bootstrap interval at each grid point", "[report]") {
  // Five trials, three grid points; point 1 has an outlier the IQM ignores and the mean does not.
  const std::vector<std::vector<double>> values{
      {0, 10, 100}, {0, 20, 100}, {0, 30, 100}, {0, 40, 100}, {0, -1000, 100}};
  const CurveBands b = curve_bands(values, 7, 500);
  REQUIRE(b.mean.size() == 3);
  REQUIRE(b.iqm_high.size() == 3);
  CHECK(b.mean[1] == Approx(-180));
  CHECK(b.std[1] == Approx(population_std({10, 20, 30, 40, -1000})));
  CHECK(b.iqm[1] == Approx(interquartile_mean({10, 20, 30, 40, -1000})));
  CHECK(b.iqm[1] > 0.0);
  // Every point is bootstrap_ci of interquartile_mean with the same seed: one set of resampled
  // trials for the whole curve.
  const ConfidenceInterval ci = bootstrap_ci({10, 20, 30, 40, -1000}, interquartile_mean, 7, 500);
  CHECK(b.iqm_low[1] == ci.low);
  CHECK(b.iqm_high[1] == ci.high);
  CHECK(b.iqm_low[1] < b.iqm[1]);
  // Where every trial agrees the band is a line.
  CHECK(b.iqm_low[0] == 0.0);
  CHECK(b.iqm_high[2] == 100.0);
  CHECK(curve_bands(values, 7, 500).iqm_low == b.iqm_low);  // the same curves, the same bands
  // Found by a probe: with a seed per point, three trials' band notched where the curves were
  // straight. Curves that are one shape shifted give a band shifted by the same amount.
  std::vector<std::vector<double>> lines;
  for (double start : {3.0, 10.0, 4.0}) {
    lines.push_back({});
    for (int k = 0; k < 40; ++k) lines.back().push_back(start + k);
  }
  const CurveBands straight = curve_bands(lines, 7, 1000);
  for (size_t k = 1; k < 40; ++k) {
    CHECK(straight.iqm_low[k] - straight.iqm_low[k - 1] == Approx(1.0));
    CHECK(straight.iqm_high[k] - straight.iqm_high[k - 1] == Approx(1.0));
  }
  CHECK(straight.iqm_low[0] < straight.iqm[0]);
  CHECK_THROWS_WITH(curve_bands({}, 7, 500), Contains("at least one trial"));
  CHECK_THROWS_WITH(curve_bands({{1, 2}, {1}}, 7, 500), Contains("trial 1 has 1 points but trial 0 has 2"));
}

TEST_CASE("a tiny batch writes every file, with tables that match the trials, whatever --jobs", "[report][run]") {
  Fixture f("jobs");
  std::string log;
  REQUIRE(f.run("one", 1, 0, &log) == 0);
  INFO(log);
  const fs::path one = f.root / "one";
  for (const char* file : {"manifest.json", "summary.csv", "tables.md", "report.json", "figure3.png", "figure3.svg",
                           "figure4.png", "figure4.svg", "figure5.png", "figure5.svg", "iqm_SG.png", "iqm_SG.svg",
                           "iqm_T.png", "iqm_T.svg"})
    CHECK(fs::is_regular_file(one / file));
  for (const char* file : {"result.json", "policy.json", "curve.csv", "episodes.jsonl", "checkpoints.jsonl", "summary.json"})
    CHECK(fs::is_regular_file(one / "trials/T/DC6/001" / file));
  const json manifest = json::parse(slurp(one / "manifest.json"));
  CHECK(manifest["version"] == ROGER_VERSION);
  CHECK(manifest["trials"].size() == kIds.size());
  CHECK(manifest["seeds"]["SG/B1/001"] == 6);
  // T trial i used the Phi_SG policy of SG/DC2 trial i.
  const json t1 = json::parse(slurp(one / "trials/T/DC6/001/result.json"));
  CHECK(t1["skills"]["Phi_SG"]["trial"] == "SG/DC2/001");
  CHECK(t1["seed"] == 6);

  // Table I's DC2 row: the mean time-to-threshold and the pooled final reward, from the trials.
  std::vector<double> times, rewards;
  for (const char* id : {"SG/DC2/000", "SG/DC2/001"}) {
    const json r = json::parse(slurp(one / "trials" / id / "result.json"));
    times.push_back(r["time_to_threshold_s"]);
    rewards.push_back(r["reward_mean"]);
  }
  const std::string tables = slurp(one / "tables.md");
  INFO(tables);
  char reward[32];
  std::snprintf(reward, sizeof reward, "%.1f ± ", mean(rewards));
  std::smatch m;
  REQUIRE(std::regex_search(tables, m, std::regex("\\| DC2 \\| (≥ )?([0-9]+:[0-9]{2}) \\| [^|]+ \\| ([^|]+) \\|")));
  CHECK(m[2].str() == format_min_sec(mean(times)));
  CHECK(m[3].str().rfind(reward, 0) == 0);
  const json rep = json::parse(slurp(one / "report.json"));
  CHECK(rep["tables"][0]["rows"][1]["time_mean_s"].get<double>() == Approx(mean(times)));
  CHECK(tables.find("| **Total** |") != std::string::npos);
  // One IQM figure per stage, in the figure list.
  CHECK(tables.find("- `iqm_SG.png` / `iqm_SG.svg`: IQM learning curves: stage SG\n") != std::string::npos);
  CHECK(tables.find("- `iqm_T.png` / `iqm_T.svg`: IQM learning curves: stage T\n") != std::string::npos);

  check_dashboard(one, tables, rep);
  check_own_worlds(one, tables, rep);

  REQUIRE(f.run("two", 2) == 0);
  same_results(one, f.root / "two");
  // A stop that came before the report began (every trial had ended: here, before the command
  // started) is said so, not as one "during the report" (found by a probe); the report is written.
  {
    catch_interrupts();
    std::raise(SIGTERM);
    REQUIRE(interrupt_requested());
    std::string log;
    const int status = f.run("two", 1, 0, &log);
    clear_interrupt();
    CHECK(status == 143);
    CHECK_THAT(log, Catch::Matchers::EndsWith("roger run: stopped on request after its trials had ended, before the "
                                              "report, which was written all the same\n"));
    same_results(one, f.root / "two");
  }

  // The report alone rewrites the same tables.
  const std::string before = slurp(one / "tables.md");
  fs::remove(one / "tables.md");
  ReportArgs r;
  r.dir = one.string();
  std::ostringstream os;
  r.progress = &os;
  CHECK(command_report(r) == 0);
  CHECK(slurp(one / "tables.md") == before);
  r.dir = f.root.string();
  CHECK(command_report(r) == 1);
  CHECK(os.str().find("no manifest.json") != std::string::npos);

  // A run cut short (here: after 3 new trials) resumes to exactly the uninterrupted run's trials.
  REQUIRE(f.run("cut", 2, 3) == 0);
  CHECK(finished_ids(f.root / "cut").size() == 3);
  {  // the run's last status says so, for the dashboard of a run that stopped early
    const json status = json::parse(slurp(f.root / "cut/status.json"));
    CHECK(status["running"] == false);
    CHECK(status["done"] == 3);
    CHECK(status["trials"] == kIds.size());
    CHECK(slurp(f.root / "cut/status.js").find("window.ROGER_STATUS = {") != std::string::npos);
  }
  CHECK(slurp(f.root / "cut/summary.csv").find(",pending,") != std::string::npos);
  // roger report alone refuses a folder with trials still to run, naming them, and writes nothing;
  // --partial reports what is there.
  {
    const std::string tables_before = slurp(f.root / "cut/tables.md");
    fs::remove(f.root / "cut/tables.md");
    ReportArgs cut;
    cut.dir = (f.root / "cut").string();
    std::ostringstream said;
    cut.progress = &said;
    CHECK(command_report(cut) == 1);
    CHECK(said.str().find("have no result yet, so no report was written") != std::string::npos);
    CHECK(said.str().find("--partial") != std::string::npos);
    CHECK_FALSE(fs::exists(f.root / "cut/tables.md"));
    cut.partial = true;
    CHECK(command_report(cut) == 0);
    CHECK(slurp(f.root / "cut/tables.md") == tables_before);
    // A context none of whose trials finished says so in the usage, rather than listing nothing
    // under the heading (or, for a skill's share, that no trial used it).
    CHECK_THAT(tables_before, Catch::Matchers::Contains(": no finished trial\n"));
    // Copied to a folder a shell would split, and reported there: the commands it prints are quoted
    // to paste whole, and the status (whence the page's commands) names where the folder is now
    // (found by a probe: the page continued and reported the folder it was copied from).
    const fs::path moved = f.root / "cut 'copy'";
    fs::copy(f.root / "cut", moved, fs::copy_options::recursive);
    ReportArgs again;
    again.dir = moved.string();
    std::ostringstream quoted;
    again.progress = &quoted;
    CHECK(command_report(again) == 1);
    const std::string shell = "'" + (f.root / "cut '\\''copy'\\''").string() + "'";
    CHECK_THAT(quoted.str(), Catch::Matchers::Contains(" --out " + shell + ", with the same options") &&
                                 Catch::Matchers::Contains("roger report --partial " + shell + " to report"));
    // The script by where it is, not as it was typed (found by a probe: `roger run quick.lua` of a
    // lab's own script, pasted in another folder, ran the project's scripts/quick.lua there).
    json typed = json::parse(slurp(moved / "manifest.json"));
    typed["script"] = "batch.lua";
    spit(moved / "manifest.json", typed.dump(1) + "\n");
    std::ostringstream placed;
    again.progress = &placed;
    CHECK(command_report(again) == 1);
    CHECK_THAT(placed.str(), Catch::Matchers::Contains("(roger run " + (f.root / "batch.lua").string() + " --out " + shell));
    again.progress = &quoted;
    again.partial = true;
    CHECK(command_report(again) == 0);
    json status = json::parse(slurp(moved / "status.json"));
    CHECK(status["folder"] == fs::absolute(moved).lexically_normal().string());
    CHECK(status["dashboard"] == true);
    CHECK(script_data(moved / "status.js", "ROGER_STATUS") == status);
    // The counts are the folders' as they are now (found by a probe: a killed run's last status,
    // one trial behind, said so above the partial report of one trial more).
    const int done = status["done"].get<int>();
    status["done"] = done - 1;
    status["groups"][0]["done"] = status["groups"][0]["done"].get<int>() - 1;
    std::ofstream(moved / "status.json") << status.dump();
    CHECK(command_report(again) == 0);
    status = json::parse(slurp(moved / "status.json"));
    CHECK(status["done"] == done);
    int grouped = 0;
    for (const json& g : status["groups"]) grouped += g["done"].get<int>();
    CHECK(grouped == done);
    CHECK(script_data(moved / "status.js", "ROGER_STATUS") == status);
    fs::remove_all(moved);
  }
  std::string resumed;
  REQUIRE(f.run("cut", 2, 0, &resumed) == 0);
  CHECK(resumed.find("resuming") != std::string::npos);
  CHECK(resumed.find("3 from an earlier run") != std::string::npos);
  // Found by a probe: the last line said "N of N trials done in 1 s" as if this run had done them all.
  CHECK(resumed.find(" trials done in ") != std::string::npos);
  CHECK(resumed.find("(3 of them by earlier runs)") != std::string::npos);
  CHECK(finished_ids(f.root / "cut") == kIds);
  same_results(one, f.root / "cut");

  // A folder made by other parameters is refused: fewer trials would leave trials in the folder
  // that its manifest does not plan.
  RunArgs other;
  other.script = (f.root / "batch.lua").string();
  other.out = one.string();
  other.trials = 1;
  std::ostringstream refused;
  other.progress = &refused;
  CHECK(command_run(other) == 1);
  CHECK(refused.str().find("made by this batch script as it was then, with other contents or other parameters (a command's --set, --trials, --lua-instructions and --lua-memory are parameters too)") != std::string::npos);
  CHECK(refused.str().find("runs[1].trials: 2 in the folder, 1 now") != std::string::npos);
  CHECK(finished_ids(one) == kIds);  // nothing lost
  // Found by a probe: a --set the folder was not made with was named by its place in a list
  // ("params[1]: absent in the folder, [\"mass\",\"0.7\"] now"); it is named by its parameter.
  other.trials = 0;
  other.sets = {"mass=0.7"};
  std::ostringstream set_refused;
  other.progress = &set_refused;
  CHECK(command_run(other) == 1);
  INFO(set_refused.str());
  CHECK_THAT(set_refused.str(), Catch::Matchers::Contains("runs[1].params.mass: absent in the folder, \"0.7\" now"));
  CHECK(set_refused.str().find("params[") == std::string::npos);
  CHECK(finished_ids(one) == kIds);

  // A folder made by another build of the engine is refused, naming both builds.
  const json cut_manifest = json::parse(slurp(f.root / "cut/manifest.json"));
  REQUIRE(cut_manifest["engine"].is_string());
  CHECK(std::regex_match(cut_manifest["engine"].get<std::string>(), std::regex("[0-9a-f]{16}")));
  json edited = cut_manifest;
  edited["engine"] = "0123456789abcdef";
  spit(f.root / "cut/manifest.json", edited.dump(1));
  std::string other_engine;
  CHECK(f.run("cut", 2, 0, &other_engine) == 1);
  CHECK(other_engine.find("another build of the engine (engine 0123456789abcdef)") != std::string::npos);
  CHECK(other_engine.find(cut_manifest["engine"].get<std::string>()) != std::string::npos);
  CHECK(finished_ids(f.root / "cut") == kIds);  // nothing lost
}

// Found by a probe: renaming a table's title, or asking for more trials, refused the folder, and the
// only way on was to train every trial again. Neither changes a trial the folder holds.
TEST_CASE("a folder takes a script that changes only its report or adds trials, and keeps its trials", "[report][run]") {
  Fixture f("extend");
  REQUIRE(f.run("out", 2) == 0);
  const fs::path out = f.root / "out";
  std::map<std::string, std::string> before;
  for (const auto& id : kIds) before[id] = slurp(fs::path(trial_dir(out.string(), id)) / "result.json");
  // A new title and a new figure: the report is drawn again, nothing trains.
  std::string script = slurp(f.root / "batch.lua");
  script = std::regex_replace(script, std::regex("title = \"Table I\""), "title = \"Table I, renamed\"");
  script = std::regex_replace(script, std::regex("figures = \\{\n"),
                              "figures = {\n    { file = \"figure6\", run = \"SG\", title = \"added\" },\n");
  spit(f.root / "batch.lua", script);
  std::string log;
  REQUIRE(f.run("out", 2, 0, &log) == 0);
  INFO(log);
  CHECK_THAT(log, Catch::Matchers::Contains("only in what trains nothing again: its tables and its figures changed. "
                                            "The manifest now holds this script; the trials there are kept."));
  CHECK_THAT(log, Catch::Matchers::Contains("trials: 4/4 done (4 from an earlier run)"));
  CHECK_THAT(slurp(out / "tables.md"), Catch::Matchers::Contains("Table I, renamed"));
  CHECK(fs::is_regular_file(out / "figure6.png"));
  for (const auto& id : kIds) CHECK(slurp(fs::path(trial_dir(out.string(), id)) / "result.json") == before[id]);
  // roger report alone draws from the manifest, which now holds the new script.
  CHECK(json::parse(slurp(out / "manifest.json"))["config"]["tables"][0]["title"] == "Table I, renamed");
  // A third trial of every run and evaluation (--trials 3): the evaluation has two shapes on worlds
  // of its own, where shape k's trial i starts at (k x trials + i) x episodes, so more trials
  // would move the worlds of those it holds. Refused, saying so, and nothing is lost.
  RunArgs more;
  more.script = (f.root / "batch.lua").string();
  more.out = out.string();
  more.jobs = 2;
  more.trials = 3;
  std::ostringstream moved;
  more.progress = &moved;
  CHECK(command_run(more) == 1);
  CHECK_THAT(moved.str(), Catch::Matchers::Contains("evaluations[1].trials: 2 in the folder, 3 now"));
  CHECK_THAT(moved.str(), Catch::Matchers::Contains("move the worlds of the trials it has"));
  for (const auto& id : kIds) CHECK(slurp(fs::path(trial_dir(out.string(), id)) / "result.json") == before[id]);
  // A third trial of every run, the evaluation keeping its two: only the new trials run, each as
  // a fresh run of the same script gives it.
  script = std::regex_replace(script, std::regex("trials = 2, seed = 5"), "trials = 3, seed = 5");
  script = std::regex_replace(script, std::regex("episodes = 3 \\}"), "episodes = 3, trials = 2 }");
  spit(f.root / "batch.lua", script);
  more.trials = 0;
  std::ostringstream said;
  more.progress = &said;
  REQUIRE(command_run(more) == 0);
  INFO(said.str());
  CHECK_THAT(said.str(), Catch::Matchers::Contains("it plans more trials. The manifest now holds this script; the "
                                                   "trials there are kept, and the new ones run."));
  CHECK_THAT(said.str(), Catch::Matchers::Contains("trials: 6/6 done (4 from an earlier run)"));
  for (const auto& id : kIds) CHECK(slurp(fs::path(trial_dir(out.string(), id)) / "result.json") == before[id]);
  const json manifest = json::parse(slurp(out / "manifest.json"));
  CHECK(manifest["trials"].size() == 13);
  CHECK(manifest["seeds"]["SG/DC2/002"] == 7);
  more.out = (f.root / "fresh").string();
  std::ostringstream fresh_log;
  more.progress = &fresh_log;
  REQUIRE(command_run(more) == 0);
  std::vector<std::string> ids = kIds;
  for (const char* id : {"SG/B1/002", "SG/DC2/002", "T/DC6/002"}) ids.push_back(id);
  for (const auto& id : ids) {
    INFO(id);
    CHECK(without_wall(json::parse(slurp(fs::path(trial_dir(out.string(), id)) / "result.json"))) ==
          without_wall(json::parse(slurp(fs::path(trial_dir((f.root / "fresh").string(), id)) / "result.json"))));
  }
  CHECK(slurp(out / "tables.md") == slurp(f.root / "fresh" / "tables.md"));
  CHECK(slurp(out / "report.json") == slurp(f.root / "fresh" / "report.json"));
  // Fewer trials than the folder holds is still refused.
  more.out = out.string();
  more.trials = 2;
  std::ostringstream fewer;
  more.progress = &fewer;
  CHECK(command_run(more) == 1);
  CHECK_THAT(fewer.str(), Catch::Matchers::Contains("runs[1].trials: 3 in the folder, 2 now"));
}

// What `roger run` with `a` said (its log) and its exit status.
struct Said {
  int status = 0;
  std::string log;
};
Said run_saying(RunArgs a) {
  std::ostringstream log;
  a.progress = &log;
  const int status = command_run(a);
  return {status, log.str()};
}

// Found by a probe: after `roger run ... --only SG/DC2`, the last line said the other trials were
// "not run yet (run the same command again to continue)", and the same command ran none of them.
TEST_CASE("the trials outside --only or the shard are not said to wait for the same command", "[report][run]") {
  Fixture f("only");
  RunArgs a = f.args("out", 2, {"SG/DC2"});
  const Said said = run_saying(a);
  REQUIRE(said.status == 0);
  INFO(said.log);
  CHECK_THAT(said.log, Catch::Matchers::Contains("roger run: 2 of 10 trials done in "));
  CHECK_THAT(said.log, Catch::Matchers::EndsWith(
                             ", 8 outside --only not run (run the command without --only, or with an --only that "
                             "names them, to run them)\n"));
  CHECK(said.log.find("run the same command again to continue") == std::string::npos);
  // A shard and --only: a shard counts its own trials (the other shards run theirs), and among
  // them those outside --only.
  a.only = {"SG"};
  a.shard = "1/2";
  const Said shard = run_saying(a);
  REQUIRE(shard.status == 0);
  INFO(shard.log);
  CHECK_THAT(shard.log, Catch::Matchers::Contains("roger run: 2 of 5 trials done in "));
  CHECK_THAT(shard.log, Catch::Matchers::EndsWith(
                              ", 3 outside --only not run (run the command without --only, or with an --only that "
                              "names them, to run them)\n"));
}

// Found by a probe: `--only SG/B1` after an `--only eval/...` run that failed exited 1 and listed
// the evaluation's failures as its own; two disjoint --only runs at once listed each other's.
TEST_CASE("an --only run answers for its own trials; failures outside it are a count apart", "[report][run]") {
  Fixture f("only_failed");
  RunArgs a = f.args("out", 2, {"SG/B1"});
  a.no_report = true;
  const Said first = run_saying(a);
  REQUIRE(first.status == 0);
  // The evaluation's trials failed in another run (as they do when run before their policies).
  for (const char* id : {"eval/gen/circle/000", "eval/gen/circle/001"}) {
    fs::create_directories(trial_dir(a.out, id));
    spit(fs::path(trial_dir(a.out, id)) / "error.json",
         json({{"error", "needs the policy of trial T/DC6/000, which has not run yet"}, {"trial", id}}).dump());
  }
  const Said said = run_saying(a);
  CHECK(said.status == 0);
  INFO(said.log);
  CHECK(said.log.find("failed (their error.json") == std::string::npos);
  CHECK(said.log.find("needs the policy") == std::string::npos);
  // The counts add up to the plan's 10: 2 done, 6 not run and 2 failed outside --only.
  CHECK_THAT(said.log, Catch::Matchers::Contains("roger run: 2 of 10 trials done in ") &&
                             Catch::Matchers::EndsWith(", 6 outside --only not run, 2 outside --only failed earlier (run "
                                                       "the command without --only, or with an --only that names "
                                                       "them, to run them)\n"));
}

// Found by a probe: `roger run ... --explain` on a folder whose trials had finished without it said
// nothing, and their result.json had no diagnosis.
TEST_CASE("--explain says which finished trials keep their result without a diagnosis", "[report][run][explain]") {
  Fixture f("explain_note");
  RunArgs a = f.args("out", 2, {"SG/B1"});
  a.no_report = true;
  const Said first = run_saying(a);
  REQUIRE(first.status == 0);
  CHECK(first.log.find("--explain:") == std::string::npos);
  a.explain = true;
  const Said said = run_saying(a);
  REQUIRE(said.status == 0);
  INFO(said.log);
  CHECK_THAT(said.log, Catch::Matchers::Contains(
                             "roger run: --explain: 2 training trials finished earlier keep their result.json without "
                             "a diagnosis (--explain adds one to the trials it runs; a run that missed its threshold "
                             "has one either way). For a diagnosis of every trial, run the command with --explain "
                             "into a new --out\n"));
  // roger run says it wrote summary.csv, as roger report does.
  CHECK_THAT(said.log, Catch::Matchers::Contains("roger run: wrote " + (f.root / "out" / "summary.csv").string() + "\n"));
}

namespace {

// What roger report says of the folder `a` leaves, after running it (exit status 1 expected: it
// leaves trials without a result).
std::string report_after_run(RunArgs a) {
  std::ostringstream ran;
  a.progress = &ran;
  REQUIRE(command_run(a) == 0);
  ReportArgs r;
  r.dir = a.out;
  std::ostringstream said;
  r.progress = &said;
  CHECK(command_report(r) == 1);
  return said.str();
}

}  // namespace

// Found by a probe: a folder of 823 trials without a result was 823 lines of roger report.
TEST_CASE("roger report names the first 20 trials without a result and counts the rest", "[report][run]") {
  Fixture f("many_missing");
  RunArgs a = f.args("out", 1);
  a.trials = 12;  // 60 trials
  a.max_trials = 1;
  const std::string text = report_after_run(a);
  INFO(text);
  CHECK_THAT(text, Catch::Matchers::Contains("roger report: 59 trials of ") &&
                       Catch::Matchers::Contains("  SG/B1/001 (run SG, context B1, trial 1)\n") &&
                       Catch::Matchers::Contains("\n  ... and 39 more without a result: ") &&
                       Catch::Matchers::Contains("eval/gen (24 trials)\n"));
  CHECK(std::count(text.begin(), text.end(), '\n') == 1 + 20 + 1 + 2);
}

// Found by a probe: of a 50-shard run's 568 trials past the 20 listed, the shards went unsaid, and
// the advice to submit again "each shard K named above" named only the first 21.
TEST_CASE("roger report names the shards of the pending trials it does not list", "[report][run]") {
  Fixture f("report_shards");
  RunArgs a = f.args("out", 1);
  a.trials = 12;  // 60 trials, shard 7 of 10 running the 5 of index 7
  a.shard = "7/10";
  const std::string text = report_after_run(a);
  INFO(text);
  CHECK_THAT(text, Catch::Matchers::Contains("\n  ... and 35 more without a result: ") &&
                       Catch::Matchers::Contains("; of shards 0-6, 8-9\n"));
}

// Found by a probe: `--only T/DC6` in a fresh folder ran its trials, each recorded as failed for the
// policy of an SG/DC2 trial that had not run.
TEST_CASE("an --only that needs policies outside it that have no result is refused before any trial", "[report][run]") {
  Fixture f("only_needs");
  RunArgs a = f.args("out", 2, {"T/DC6"});
  const Said said = run_saying(a);
  CHECK(said.status == 1);
  INFO(said.log);
  CHECK_THAT(said.log, Catch::Matchers::Contains(
                             "roger run: error: --only T/DC6: its trials need the policies of trials outside it that have no "
                             "result yet (not run, or failed): SG/DC2/000, SG/DC2/001, for T/DC6/000, T/DC6/001. "
                             "Nothing was run: add --only SG/DC2 to this command, or run it first"));
  CHECK_FALSE(fs::exists(trial_dir(a.out, "T/DC6/000")));
  // Found by a probe: the refused command made the folder and its manifest, which then refused the
  // corrected command's other --trials. A new folder is not made.
  CHECK_FALSE(fs::exists(a.out));
  // With the runs it needs in its --only, it runs.
  a.only = {"eval"};
  const Said eval = run_saying(a);
  CHECK(eval.status == 1);
  // What T/DC6 needs in turn is named too (found by a probe: the advice to add --only T/DC6 was
  // refused again, for T/DC6's own skill).
  CHECK_THAT(eval.log, Catch::Matchers::Contains("T/DC6/000, T/DC6/001, for eval/gen/circle/000") &&
                           Catch::Matchers::Contains("; and those need SG/DC2/000, SG/DC2/001. Nothing was run: add "
                                                     "--only T/DC6 --only SG/DC2 to this command, or run those first"));
  CHECK_FALSE(fs::exists(trial_dir(a.out, "eval/gen/circle/000")));
  // Found by a probe: the refused run said "resuming" first, though it resumed nothing.
  CHECK(eval.log.find("resuming") == std::string::npos);
}

// Found by a probe: with manifest.json deleted, a run with other parameters took the trials there
// ("4 from an earlier run"), made with the old ones; --out into a folder of notes wrote over them.
TEST_CASE("roger run refuses a folder with files but no manifest, before touching it", "[report][run]") {
  Fixture f("foreign");
  REQUIRE(f.run("out", 2, 2) == 0);
  fs::remove(f.root / "out" / "manifest.json");
  const auto entries = [](const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  };
  const std::vector<std::string> before = entries(f.root / "out");
  std::string log;
  CHECK(f.run("out", 2) == 1);
  CHECK(f.run("out", 2, 0, &log) == 1);
  INFO(log);
  CHECK_THAT(log, Catch::Matchers::Contains("roger run: error: the folder '" + (f.root / "out").string() +
                                            "' holds results of roger run (") &&
                      Catch::Matchers::Contains(") but no manifest.json, so nothing tells which script and parameters "
                                                "made them, and the trials of this run would mix with them. Move them "
                                                "aside (or put back the folder's manifest.json), or give another --out"));
  CHECK(entries(f.root / "out") == before);
  // A folder of one's own files: named, and left as it was.
  fs::create_directories(f.root / "notes");
  spit(f.root / "notes" / "tables.md", "x\n");
  CHECK(f.run("notes", 2, 0, &log) == 1);
  CHECK_THAT(log, Catch::Matchers::Contains("roger run: error: the folder '" + (f.root / "notes").string() +
                                            "' is not a results folder of roger run (it has no manifest.json) and is "
                                            "not empty: it holds tables.md. roger run would write its trials, report "
                                            "and dashboard (index.html, tables.md) over or among them: give --out a "
                                            "new or empty folder"));
  CHECK(entries(f.root / "notes") == std::vector<std::string>{"tables.md"});
  CHECK(slurp(f.root / "notes" / "tables.md") == "x\n");
  // The folder of the user's scripts.
  CHECK(f.run(".", 2, 0, &log) == 1);
  CHECK_THAT(log, Catch::Matchers::Contains("it holds batch.lua, curriculum.lua"));
}

// Found by a probe: roger report on a read-only folder advised "give another with --out" (it has no
// --out) and said it "resumes where this one stopped" (it resumes nothing).
TEST_CASE("roger report into a read-only folder gives advice that fits roger report", "[report][run]") {
  // The line roger report prints for such a FileError (a read-only mount is what a user has; the
  // tests cannot count on making one, and root writes through a folder's permissions).
  for (const int error : {EROFS, EACCES}) {
    const std::string said = report_file_error_line(FileError("cannot write into 'ro': " + std::string(std::strerror(error)),
                                                              "ro", error));
    INFO(said);
    CHECK_THAT(said, Catch::Matchers::EndsWith(". roger report writes its report into the results folder: make the "
                                               "folder writable (or copy it somewhere writable and report the copy), "
                                               "then run the same command again"));
    CHECK(said.find("--out") == std::string::npos);
    CHECK(said.find("resumes") == std::string::npos);
  }
}

// Found by a probe: a folder that took no dashboard page left "roger run: open " unfinished on the
// progress line before the error. The page is written before the line names it. (A directory where
// the page goes refuses it even to root, which writes through permissions.)
TEST_CASE("a dashboard that cannot be written leaves no half line", "[report][run]") {
  Fixture f("dashboard_refused");
  REQUIRE(f.run("out", 1, 1) == 0);
  fs::remove(f.root / "out/index.html");
  fs::create_directories(f.root / "out/index.html/kept");
  std::string log;
  CHECK(f.run("out", 1, 1, &log) != 0);
  INFO(log);
  CHECK(log.find("roger run: open") == std::string::npos);
}

TEST_CASE("a results folder is not resumed after a module the curriculum requires changed", "[report][run]") {
  // The fixture's curriculum requires lib.skills; a copy beside it is found first.
  Fixture f("module");
  fs::create_directories(f.root / "lib");
  spit(f.root / "lib/skills.lua", slurp("curricula/lib/skills.lua"));
  REQUIRE(f.run("out", 2, 1) == 0);
  const json manifest = json::parse(slurp(f.root / "out/manifest.json"));
  const json& sources = manifest["config"]["sources"];
  INFO(sources.dump());
  // The curriculum, the module it requires and the scenarios of its stages are all fingerprinted.
  for (const char* file : {"curriculum.lua", "lib/skills.lua", "scenarios/unobstructed.lua"}) {
    bool found = false;
    for (auto it = sources.begin(); it != sources.end(); ++it)
      found = found || it.key().size() >= std::string(file).size() &&
                           it.key().compare(it.key().size() - std::string(file).size(), std::string::npos, file) == 0;
    CHECK(found);
  }
  spit(f.root / "lib/skills.lua", slurp("curricula/lib/skills.lua") + "\n-- edited\n");
  std::string log;
  CHECK(f.run("out", 2, 0, &log) == 1);
  INFO(log);
  CHECK(log.find("was made before a Lua file its trials read changed") != std::string::npos);
  CHECK(log.find("lib/skills.lua") != std::string::npos);
  CHECK(log.find("To resume the folder, put the files listed back as they were") != std::string::npos);
  CHECK(finished_ids(f.root / "out").size() == 1);  // the finished trial is kept
}

TEST_CASE("a failing trial is recorded and does not lose the others", "[report][run]") {
  // The evaluation's worlds cannot be made: its scenario raises when it generates one after its
  // first (a wrong parameter, or a scenario that builds no world at all, is refused when the
  // script loads, which builds one world with the evaluation's parameters, before any trial).
  Fixture f("fail", "obstacles = 3", "failing.lua");
  spit(f.root / "failing.lua",
       "local base = require(\"cluttered\")\n"
       "local built = 0\n"
       "return { name = \"failing\", params = base.params,\n"
       "         generate = function(world, rng, p)\n"
       "           built = built + 1\n"
       "           if built > 1 then error(\"no world for this evaluation\") end\n"
       "           return base.generate(world, rng, p)\n"
       "         end }\n");
  // Run as `roger run roger_report_fail_PID/batch.lua` from the folder above.
  const fs::path project = fs::current_path();
  fs::current_path(f.root.parent_path());
  struct Back {
    fs::path to;
    ~Back() { fs::current_path(to); }
  } back{project};
  RunArgs a = f.args("out", 2);
  a.script = (f.root.filename() / "batch.lua").string();
  std::ostringstream progress;
  a.progress = &progress;
  CHECK(command_run(a) == 1);
  const std::string log = progress.str();
  INFO(log);
  const fs::path out = f.root / "out";
  CHECK(finished_ids(out).size() == 6);  // every training trial
  CHECK(fs::exists(fs::path(trial_dir(out.string(), "eval/gen/circle/000")) / "error.json"));
  CHECK(log.find("4 trials failed") != std::string::npos);
  // The progress line counts them among those done (found by a probe: "4/4 done" read as success).
  CHECK(log.find("trials: 4/4 done (4 failed), 0 running, 0 left") != std::string::npos);
  CHECK(log.find("eval/gen/spade/001") != std::string::npos);
  CHECK(slurp(out / "summary.csv").find(",failed,") != std::string::npos);
  CHECK(fs::is_regular_file(out / "tables.md"));
  // Per shape: 2 failed each; the Total counts the 4, as the shape rows count theirs (a Total
  // row of the counts alone, no evaluation having a result), and so does the opening line.
  CHECK(std::regex_search(slurp(out / "tables.md"),
                          std::regex("\\| \\*\\*Total\\*\\* \\| - \\| - \\| - \\| 0/4 of 2 policies × 2 objects \\(4 failed\\) \\| 0 \\| 0 \\|\\n")));
  CHECK(std::regex_search(slurp(out / "tables.md"), std::regex("\\| [A-Z][a-z]+ \\|[^\\n]*\\(2 failed\\)")));
  CHECK_THAT(slurp(out / "tables.md"), Contains("**Partial report:** 6 of 10 trials have results (4 failed);"));
  CHECK(slurp(out / "tables.md").find("(2 failed)") != std::string::npos);
  // Found by an earlier probe: the scenario beside the script was named by its absolute path, where the
  // script is named as the command named it: a published table carried one machine's folders.
  CHECK_THAT(slurp(out / "tables.md"), Contains("in scenario `" + (f.root.filename() / "failing.lua").string() + "`"));
}

TEST_CASE("roger run killed with SIGKILL resumes to exactly an uninterrupted run's trials", "[report][run][cli]") {
  Fixture f("kill");
  const fs::path whole = f.root / "whole", killed = f.root / "killed";
  REQUIRE(f.run("whole", 2) == 0);
  const std::string script = (f.root / "batch.lua").string();
  // The real program, in a child process, killed without warning once some trials are done.
  const pid_t child = ::fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    const int devnull = ::open("/dev/null", O_WRONLY);
    ::dup2(devnull, 1);
    ::dup2(devnull, 2);
    ::execl(ROGER_BINARY, ROGER_BINARY, "run", script.c_str(), "--jobs", "2", "--out",
            killed.string().c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  size_t finished_at_kill = 0;
  for (int i = 0; i < 3000; ++i) {  // up to 60 s
    finished_at_kill = finished_ids(killed).size();
    if (finished_at_kill >= 2) break;
    ::usleep(20000);
  }
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  INFO(finished_at_kill << " trials had finished when the run was killed");
  CHECK(finished_at_kill >= 2);
  CHECK(finished_at_kill < kIds.size());  // it really was cut short
  // No half-written result anywhere: every result.json that exists parses.
  for (const auto& id : finished_ids(killed))
    CHECK_NOTHROW(json::parse(slurp(fs::path(trial_dir(killed.string(), id)) / "result.json")));
  // The same command again completes the run.
  const std::string again = std::string(ROGER_BINARY) + " run " + script + " --jobs 2 --out " +
                            killed.string() + " >/dev/null 2>&1";
  CHECK(std::system(again.c_str()) == 0);
  CHECK(finished_ids(killed) == kIds);
  same_results(whole, killed);
}

TEST_CASE("a damaged trial result is a roger::Error naming its file, never an abort", "[report]") {
  // Found by tests/fuzz/fuzz_result: a result.json without "usage" aborted `roger report` (an
  // assertion inside nlohmann's operator[]), other wrong types escaped as json type_errors, and an
  // episode count of 1e300 was converted to int (undefined behaviour). Every record is now checked,
  // every field the report reads, before the report reads it (engine/batch/records.cpp); the
  // report checks only the numbers it takes (num).
  const fs::path dir = fs::temp_directory_path() / ("roger_report_damaged_" + std::to_string(::getpid()));
  // The fuzzer's seed result, completed with what a finished training trial also records.
  json good = json::parse(slurp("tests/fuzz/corpus/result/training.json"));
  good["train_episodes"] = 40;
  good["first_seed"] = 2000000;  // an evaluation's first world
  good["success_rate"] = 1.0 / 3;  // its 1 success in 3 episodes: a rate that disagrees is refused
  for (auto& c : good["checkpoints"]) c["success_rate"] = 0.5;
  const std::string policy = QTable({"phi1", "Phi7"}).to_json().dump();
  // `marked` replaces the text "__MARK__" in each trial's record (a value json could not hold).
  auto report_with = [&](const json& result, const std::string& marked = "") {
    fs::remove_all(dir);
    fs::create_directories(dir);
    fs::copy_file("tests/fuzz/report_manifest.json", dir / "manifest.json");
    for (const auto& phase : read_results_plan(dir.string()).phases)
      for (const auto& t : phase) {
        const fs::path d = trial_dir(dir.string(), t.id);
        fs::create_directories(d);
        json r = result;
        if (r.is_object()) r["id"] = t.id, r["trial"] = t.index;  // each trial's own, as roger run writes
        std::string text = r.dump();
        if (const size_t at = text.find("\"__MARK__\""); at != std::string::npos) text.replace(at, 10, marked);
        spit(d / "result.json", text);
        if (t.run) spit(d / "policy.json", policy);
      }
    write_report(dir.string());
  };
  CHECK_NOTHROW(report_with(good));
  // Found by a probe: a seed past 2^53 (an evaluation's first_seed of 2^53 and its offsets) was
  // refused as "not a seed", so no report could read the folder; seeds are integers to 2^64 - 1.
  json big_seed = good;
  big_seed["first_seed"] = 18446744073709551615u;
  CHECK_NOTHROW(report_with(big_seed));
  const std::vector<std::pair<std::string, std::function<void(json&)>>> cases = {
      {"must be a JSON object", [](json& j) { j = json::array({1}); }},
      {"\"usage\" must be an object", [](json& j) { j.erase("usage"); }},
      {"\"usage\" must be an object", [](json& j) { j["usage"] = "phi1"; }},
      {"\"usage\" must map actions to shares", [](json& j) { j["usage"]["phi1"] = "x"; }},
      {"\"psi\" must hold action names", [](json& j) { j["psi"] = {1, 2}; }},
      {"\"reached\" must be true or false", [](json& j) { j["reached"] = "yes"; }},
      {"\"checkpoints\" must be a list", [](json& j) { j["checkpoints"] = 4; }},
      {"\"skipped_tasks\" must be a list", [](json& j) { j["skipped_tasks"] = 4; }},
      {"is not a count of episodes", [](json& j) { j["episodes"] = 1e300; }},
      {"'first_seed' is not a seed", [](json& j) { j["first_seed"] = -3; }},
      {"'first_seed' is not a seed (an integer from 0 to 2^64 - 1): 2.5", [](json& j) { j["first_seed"] = 2.5; }},
      {"\"outcomes\" must be a string of episode outcomes", [](json& j) { j["outcomes"] = "1x0"; }},
      {"\"outcomes\" must be a string of episode outcomes", [](json& j) { j["outcomes"] = 101; }},
      {"\"final_outcomes\" must be a string of episode outcomes", [](json& j) { j["final_outcomes"] = "yes"; }},
      {"\"diagnosis\" must be an object whose \"causes\"", [](json& j) { j["diagnosis"] = {{"causes", "x"}}; }},
      {"\"psi\" must be the list of the context's actions", [](json& j) { j["psi"] = "phi1"; }},
      {"field \"outcomes\" holds 2 outcomes for 3 episodes", [](json& j) { j["outcomes"] = "10"; }},
      {"ran 5 episodes; the evaluation asks for 3", [](json& j) { j["episodes"] = 5; }},
      // Numbers no trial gives: the tables printed a success of 750% and failed on a negative time.
      {"field \"success_rate\" must be within [0, 1], got 7.5", [](json& j) { j["success_rate"] = 7.5; }},
      {"field \"time_to_threshold_s\" must be at least 0, got -5", [](json& j) { j["time_to_threshold_s"] = -5; }},
      {"checkpoint 0: field \"success_rate\" must be within [0, 1], got -0.5",
       [](json& j) { j["checkpoints"][0]["success_rate"] = -0.5; }},
      {"field \"usage\" must map actions to shares, got 3", [](json& j) { j["usage"]["phi1"] = 3; }},
      // What a teacher did, told by the report: a wrong type there escaped as a json type_error.
      {"field \"teacher\" must be an object, got string", [](json& j) { j["teacher"] = "lcas"; }},
      {"field \"teacher\": \"kind\" must name the teacher, got 5", [](json& j) { j["teacher"] = {{"kind", 5}}; }},
      {"field \"teacher\": its \"state\" is not as roger train records it",
       [](json& j) { j["teacher"] = {{"kind", "alp_gmm"}, {"state", {{"kind", "alp_gmm"}, {"components", {{{"alp", "high"}}}}}}}; }},
      {"field \"teacher\": its \"state\" is not as roger train records it",
       [](json& j) { j["teacher"] = {{"kind", "sequence"}, {"state", {{"kind", "sequence"}, {"moves", {3}}, {"episodes", 1}}}}; }},
  };
  for (const auto& [what, spoil] : cases) {
    json bad = good;
    spoil(bad);
    INFO(bad.dump());
    try {
      report_with(bad);
      FAIL("reported a result with " << what);
    } catch (const Error& e) {
      CHECK_THAT(e.what(), Catch::Contains(what) && Catch::Contains("result.json"));
    }
  }
  // Found by a probe: a field nesting 100,000 brackets crashed roger report: nlohmann copies and
  // writes a value by recursion, a frame per level, and a message quoted the field.
  json marked = good;
  marked["psi"] = "__MARK__";
  try {
    report_with(marked, std::string(100000, '[') + std::string(100000, ']'));
    FAIL("reported a result nested 100,000 deep");
  } catch (const Error& e) {
    CHECK_THAT(e.what(), Catch::Contains("result.json") && Catch::Contains("nested more than 64 levels deep"));
  }
  fs::remove_all(dir);
}

// Found by a probe: a record the tables refused (a negative time to threshold, now refused with
// the records) made `roger report` fail after it had replaced summary.csv, beside the old tables;
// and a report that fails at its last file replaced the figures before it.
TEST_CASE("a report that fails halfway leaves the previous one whole", "[report]") {
  const fs::path dir = fs::temp_directory_path() / ("roger_report_staged_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::copy_file("tests/fuzz/report_manifest.json", dir / "manifest.json");
  json result = json::parse(slurp("tests/fuzz/corpus/result/training.json"));
  result["train_episodes"] = 40;
  result["first_seed"] = 2000000;
  result["success_rate"] = 1.0 / 3;  // an evaluation's 1 success in 3 episodes
  for (auto& c : result["checkpoints"]) c["success_rate"] = 0.5;
  std::vector<fs::path> results;
  for (const auto& phase : read_results_plan(dir.string()).phases)
    for (const auto& t : phase) {
      const fs::path d = trial_dir(dir.string(), t.id);
      fs::create_directories(d);
      json r = result;
      r["id"] = t.id, r["trial"] = t.index;
      results.push_back(d / "result.json");
      spit(results.back(), r.dump());
      if (t.run) spit(d / "policy.json", QTable({"phi1", "Phi7"}).to_json().dump());
    }
  const std::vector<std::string> written = write_report(dir.string());
  REQUIRE(written.size() >= 4);
  std::map<std::string, std::string> before;
  for (const auto& f : written) before[f] = slurp(f);
  const std::string first_record = slurp(results.front());
  json spoilt = json::parse(first_record);
  spoilt["reached"] = true;
  spoilt["time_to_threshold_s"] = -5;
  spit(results.front(), spoilt.dump());
  CHECK_THROWS_WITH(write_report(dir.string()), Catch::Contains("-5"));
  for (const auto& [file, text] : before) {
    INFO(file);
    CHECK(slurp(file) == text);
  }
  // Failing at the last file: new curves (other figures) and a folder where report.json goes.
  // Before, the figures and tables.md were replaced, and then the report stopped.
  spit(results.front(), first_record);
  json changed = result;
  for (auto& c : changed["checkpoints"]) c["reward_mean"] = -3.5;
  for (const auto& r : results) {
    json j = json::parse(slurp(r));
    j["checkpoints"] = changed["checkpoints"];
    spit(r, j.dump());
  }
  const fs::path report_json = dir / "report.json";
  fs::remove(report_json);
  fs::create_directories(report_json / "in_the_way");
  CHECK_THROWS_WITH(write_report(dir.string()), Catch::Contains("report.json"));
  for (const auto& [file, text] : before) {
    INFO(file);
    if (file != report_json.string()) CHECK(slurp(file) == text);
  }
  for (const auto& entry : fs::directory_iterator(dir))  // no staging folder left behind
    CHECK(entry.path().filename().string().rfind(".staged", 0) == std::string::npos);
  fs::remove_all(report_json);
  CHECK(write_report(dir.string()).size() == written.size());
  int changed_files = 0;  // the new curves did reach some figures
  for (const auto& [file, text] : before) changed_files += slurp(file) != text;
  CHECK(changed_files >= 2);
  fs::remove_all(dir);
}

TEST_CASE("the report says why the trials that missed the threshold missed it", "[report][explain]") {
  // tests/scripts/explain_batch.lua: a livelocked stage and one that never runs the action it needs.
  const fs::path out = fs::temp_directory_path() / ("roger_report_explain_" + std::to_string(::getpid()));
  fs::remove_all(out);
  RunArgs a;
  a.script = "tests/scripts/explain_batch.lua";
  a.out = out.string();
  a.jobs = 2;
  std::ostringstream log;
  a.progress = &log;
  REQUIRE(command_run(a) == 0);  // a trial that misses its threshold has not failed
  const json result = json::parse(slurp(out / "trials/L/A/000/result.json"));
  REQUIRE(result.contains("diagnosis"));
  CHECK(result["diagnosis"]["cycle"]["turns"].get<int>() >= 2);
  const std::string tables = slurp(out / "tables.md");
  CHECK(tables.find("### Why trials did not reach the threshold") != std::string::npos);
  CHECK(tables.find("- A, trial 0 (`trials/L/A/000`): greedy cycle: (go0=") != std::string::npos);
  CHECK(tables.find("- A, trial 0 (`trials/U/A/000`): state never left: (go0=CONV nowhere=NOREF)") != std::string::npos);
  CHECK_FALSE(json::parse(slurp(out / "trials/R/A/000/result.json")).contains("diagnosis"));  // it reached
  const json rep = json::parse(slurp(out / "report.json"));
  REQUIRE(rep["tables"].size() == 3);
  CHECK_FALSE(rep["tables"][2].contains("why_not_reached"));
  CHECK(rep["tables"][0]["why_not_reached"][0]["causes"][0].get<std::string>().rfind("greedy cycle:", 0) == 0);
  CHECK(rep["tables"][1]["why_not_reached"][0]["causes"][1] == "never able to run: nowhere (NOREF at every decision)");
  // The dashboard shows the same section (its blocks come from tables.md).
  CHECK(slurp(out / "dashboard.js").find("Why trials did not reach the threshold") != std::string::npos);
  // A hand-edited diagnosis is named, not read as something else.
  json edited = result;
  edited["diagnosis"]["causes"] = 3;
  spit(out / "trials/L/A/000/result.json", edited.dump());
  CHECK_THROWS_WITH(write_report(out.string()), Catch::Contains("result.json: field \"diagnosis\" must be an object"));
  fs::remove_all(out);

  // roger run --explain: every training result says what its data shows, and the report still
  // lists only the trials that missed the threshold.
  a.explain = true;
  REQUIRE(command_run(a) == 0);
  const json reached = json::parse(slurp(out / "trials/R/A/000/result.json"));
  CHECK(reached["reached"] == true);
  CHECK(reached.contains("diagnosis"));
  const std::string explained = slurp(out / "tables.md");
  CHECK(explained.find("(`trials/L/A/000`): greedy cycle") != std::string::npos);
  CHECK(explained.find("`trials/R/A/000`") == std::string::npos);
  fs::remove_all(out);
}

// The sorting report's own table (docs/batch.md, Sorting tables): one row per number of objects,
// its figures those of the trials' results.
TEST_CASE("a sorting table has one row per number of objects, from the trials' final evaluations", "[report][run]") {
  const fs::path root = fs::temp_directory_path() / ("roger_report_sorting_" + std::to_string(::getpid()));
  fs::remove_all(root);
  fs::create_directories(root);
  spit(root / "batch.lua",
       "return {\n"
       "  name = \"sorting table\", curriculum = \"" + fs::absolute("curricula/sorting.lua").string() + "\",\n"
       "  trials = 1, seed = 3,\n"
       "  runs = { { name = \"Hand2\", stage = \"Hand2\", contexts = { \"Scripted\" }, trials = 2, final_worlds = \"own\" },\n"
       "           { name = \"Hand4\", stage = \"Hand4\", contexts = { \"Scripted\" } } },\n"
       "  tables = { { title = \"Sorting\", sorting = { { objects = 2, hand = \"Hand2\" }, { objects = 4, hand = \"Hand4\" } } } },\n"
       "  figures = {},\n"
       "}\n");
  RunArgs a;
  a.script = (root / "batch.lua").string();
  a.out = (root / "out").string();
  a.jobs = 2;
  std::ostringstream os;
  a.progress = &os;
  REQUIRE(command_run(a) == 0);
  const std::string tables = slurp(root / "out" / "tables.md");
  INFO(tables);
  const json rep = json::parse(slurp(root / "out" / "report.json"));
  const json& rows = rep["tables"][0]["sorting"];
  REQUIRE(rows.size() == 2);
  for (const auto& [objects, run, trials] : {std::tuple<int, const char*, int>{2, "Hand2", 2}, {4, "Hand4", 1}}) {
    std::vector<json> results;
    for (int i = 0; i < trials; ++i)
      results.push_back(json::parse(slurp(root / "out" / "trials" / run / "Scripted" / ("00" + std::to_string(i)) / "result.json")));
    double s = 0.0, sorted = 0.0, seconds = 0.0;
    for (const json& r : results) {
      s += r["success_rate"].get<double>() / trials;
      sorted += r["final_sorted_mean"].get<double>() / trials;
      seconds += r["final_time_mean"].get<double>() / trials;
      CHECK(r["final_sortable"] == objects);
    }
    const json& row = rows[size_t(objects / 2 - 1)];
    CHECK(row["objects"] == objects);
    CHECK(row["hand"]["success_rate"].get<double>() == Approx(s));
    // Objects sorted per episode: the world's count at the end of each final-evaluation episode.
    CHECK(row["hand"]["sorted"].get<double>() == Approx(sorted));
    CHECK(sorted >= objects * s);  // every successful episode sorted them all
    CHECK(row["hand"]["sorted"].get<double>() <= objects);
    CHECK(row["hand"]["seconds_per_object"].get<double>() == Approx(seconds / sorted));
    CHECK(!row.contains("learned"));
    CHECK(tables.find("| " + std::to_string(objects) + " | ") != std::string::npos);
    // A hand-written run's trials are one policy: its layouts are what the interval resamples.
    CHECK(row["hand"]["interval"] == "layouts");
    const double layouts = row["hand"]["layouts"];
    CHECK(row["hand"]["success_low"].get<double>() <= wilson_interval(s * layouts, layouts).low);
  }
  // final_worlds = "own": Hand2's second trial met the 50 worlds after the first's, so its row holds
  // 100 layouts; Hand4, one trial on the held-out seeds, 50.
  const json h0 = json::parse(slurp(root / "out/trials/Hand2/Scripted/000/result.json"));
  const json h1 = json::parse(slurp(root / "out/trials/Hand2/Scripted/001/result.json"));
  CHECK(h1["final_first_seed"].get<int64_t>() == h0["final_first_seed"].get<int64_t>() + 50);
  CHECK(h0["final_outcomes"].get<std::string>().size() == 50);
  CHECK(rows[0]["hand"]["layouts"] == 100);
  CHECK(rows[1]["hand"]["layouts"] == 50);
  CHECK(rows[0]["hand"]["failed"] == 0);
  CHECK(rows[0]["hand"]["pending"] == 0);
  // Found by a probe: a run of the table not run yet read as a row of "-", and report.json's row
  // held its object count alone.
  a.out = (root / "only").string();
  a.only = {"Hand2"};
  command_run(a);
  const std::string partial = slurp(root / "only" / "tables.md");
  CHECK_THAT(partial, Contains("| 4 | - (1 pending of 1 trial) | - | - | - | - | - | - | - | - | - |"));
  const json pending_row = json::parse(slurp(root / "only" / "report.json"))["tables"][0]["sorting"][1];
  CHECK(pending_row["hand"]["pending"] == 1);
  CHECK_FALSE(pending_row["hand"].contains("success_rate"));
  CHECK_FALSE(pending_row.contains("learned"));
  fs::remove_all(root);
}

namespace {

// A finished results folder of tests/scripts/kill_batch.lua (training, training on a learned
// skill, evaluations; about 10 s), made once per process: the tests below damage copies of it.
const fs::path& kill_batch_folder() {
  static const struct Made {
    fs::path dir = fs::temp_directory_path() / ("roger_report_kill_batch_" + std::to_string(::getpid()));
    Made() {
      fs::remove_all(dir);
      RunArgs a;
      a.script = "tests/scripts/kill_batch.lua";
      a.out = dir.string();
      a.jobs = 2;
      std::ostringstream log;
      a.progress = &log;
      if (command_run(a) != 0) throw std::runtime_error("roger run tests/scripts/kill_batch.lua failed:\n" + log.str());
    }
    ~Made() { fs::remove_all(dir); }
  } made;
  return made.dir;
}

// A fresh copy of kill_batch_folder(), removed when it goes.
struct KillCopy {
  fs::path dir;
  explicit KillCopy(const std::string& tag) {
    dir = fs::temp_directory_path() / ("roger_report_" + tag + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::copy(kill_batch_folder(), dir, fs::copy_options::recursive);
  }
  ~KillCopy() { fs::remove_all(dir); }
  json read(const std::string& file) const { return json::parse(slurp(dir / file)); }
  void write(const std::string& file, const json& j) const { spit(dir / file, j.dump(1)); }
  // A training trial's result.json with its checkpoints written to checkpoints.jsonl as well, which
  // must hold them line for line.
  void write_training(const std::string& result_file, const json& j) const {
    write(result_file, j);
    std::string lines;
    for (const json& c : j["checkpoints"]) lines += c.dump() + "\n";
    spit((dir / result_file).parent_path() / "checkpoints.jsonl", lines);
  }
  // roger report on the copy: its exit status, and what it said.
  int report(std::string& said) const {
    ReportArgs r;
    r.dir = dir.string();
    std::ostringstream os;
    r.progress = &os;
    const int status = command_report(r);
    said = os.str();
    return status;
  }
  // The same roger run again on the copy (a resume): its exit status, and what it said.
  int resume(std::string& said, const std::string& script = "tests/scripts/kill_batch.lua") const {
    RunArgs a;
    a.script = script;
    a.out = dir.string();
    a.jobs = 2;
    std::ostringstream os;
    a.progress = &os;
    const int status = command_run(a);
    said = os.str();
    return status;
  }
};

struct ManifestDamage {
  std::function<void(json&)> spoil;
  std::string says;
};

}  // namespace

// Found by a researcher editing results folders by hand: a manifest whose trial list, seeds or
// sources were of the wrong type or another plan's was reported and resumed without a word, and
// a config field of the wrong type was named only by nlohmann's "cannot use at() with number".
TEST_CASE("a manifest field of the wrong type or not the plan's is refused by report and by a resumed run", "[report][run]") {
  const std::vector<ManifestDamage> damages = {
      {[](json& m) { m["trials"] = "x"; }, "field \"trials\" must be the list of the folder's trial ids, got string"},
      {[](json& m) { m["seeds"] = "x"; }, "field \"seeds\" must map the training trials to their seeds, got string"},
      {[](json& m) { m["trials"].erase(m["trials"].begin() + 5, m["trials"].end()); },
       "field \"trials\" lists 5 trial ids where the configuration plans 10; missing: T/DC6/001, eval/gen/circle/000"},
      {[](json& m) { m["seeds"]["T/DC6/000"] = 999; },
       "field \"seeds\" gives trial T/DC6/000 seed 999, but the plan gives it 7"},
      {[](json& m) { m["config"]["sources"] = "x"; }, "field \"config.sources\" must be an object, got string"},
      {[](json& m) { m["config"]["runs"] = 5; }, "field \"config.runs\" must be an array, got number"},
      {[](json& m) { m["config"]["figures"] = "f"; }, "field \"config.figures\" must be an array, got string"},
      {[](json& m) { m["config"]["name"] = 3; }, "field \"config.name\" must be a string, got number"},
      {[](json& m) { m["config"]["tables"][0]["title"] = 3; }, "field \"config.tables[0].title\" must be a string, got number"},
      {[](json& m) { m["config"]["runs"][1]["params"] = {{"obstacles"}}; },
       "field \"config.runs[1].params[0]\" must be a [name, value] pair of strings"},
  };
  const KillCopy folder("manifest_fields");
  const json good = folder.read("manifest.json");
  const std::string path = (folder.dir / "manifest.json").string();
  for (const ManifestDamage& d : damages) {
    json bad = good;
    d.spoil(bad);
    folder.write("manifest.json", bad);
    INFO(d.says);
    std::string said;
    CHECK(folder.report(said) == 1);
    CHECK_THAT(said, Contains(path + ": " + d.says));
    CHECK_THROWS_WITH(write_report(folder.dir.string()), Contains(path + ": " + d.says));
    CHECK(folder.resume(said) == 1);
    CHECK_THAT(said, Contains(path + ": " + d.says));
    CHECK(said.find("json.exception") == std::string::npos);
  }
  folder.write("manifest.json", good);
  std::string said;
  CHECK(folder.report(said) == 0);
}

// Found by hand-edited results: an evaluation whose success_rate said 0.25 while its outcomes were
// all successes was reported, its rate printed outside its own interval; a training result's
// final_outcomes of "1" for 50 episodes was read; and the report's message for an outcome count
// that disagrees named neither the file nor the trial.
TEST_CASE("a trial result whose summary disagrees with its own episodes is refused naming its file", "[report]") {
  struct Edit {
    const char* trial;
    std::function<void(json&)> spoil;
    std::string says;
  };
  const KillCopy folder("record_sums");
  // kill_batch's policies succeed in every episode; the final evaluation's count is its curriculum's.
  const std::string n = std::to_string(folder.read("trials/T/DC6/000/result.json")["final_episodes"].get<int>());
  // Found by a probe: a trial copied in from another folder of a sweep (--set mass=5) was reported.
  const json planned = folder.read("trials/T/DC6/000/result.json").at("set_params");
  json heavier = planned;
  heavier["mass"] = "5";
  const json eval_planned = folder.read("trials/eval/gen/circle/000/result.json").at("set_params");
  CHECK(eval_planned.at("shape") == "circle");
  const std::vector<Edit> edits = {
      {"T/DC6/000", [&](json& r) { r["set_params"] = heavier; },
       "it was run with the scenario parameters " + heavier.dump() + ", but the plan gives trial T/DC6/000 " +
           planned.dump() + " (copied from another results folder?)"},
      {"eval/gen/circle/000", [](json& r) { r["set_params"]["shape"] = "spade"; },
       "it was run with the scenario parameters {\"obstacles\":\"2\",\"shape\":\"spade\"}, but the plan gives trial "
       "eval/gen/circle/000 {\"obstacles\":\"2\",\"shape\":\"circle\"}"},
      {"eval/gen/circle/000", [](json& r) { r["success_rate"] = 0.25; },
       "field \"success_rate\" must be 1 (12 of 12 in field \"outcomes\"), got 0.25"},
      {"eval/gen/circle/000", [](json& r) { r["outcomes"] = "1"; },
       "field \"outcomes\" holds 1 outcome for 12 episodes (field \"episodes\")"},
      {"eval/gen/circle/000", [](json& r) { r["successes"] = 3; }, "field \"successes\" must be 12"},
      {"eval/gen/circle/000", [](json& r) { r["episodes"] = 13; },
       "field \"episodes\": it ran 13 episodes; the evaluation asks for 12"},
      {"T/DC6/000", [](json& r) { r["final_outcomes"] = "1"; },
       "field \"final_outcomes\" holds 1 outcome for " + n + " episodes (field \"final_episodes\")"},
      {"T/DC6/000", [](json& r) { r["success_rate"] = 0.25; },
       "field \"success_rate\" must be 1 (" + n + " of " + n + " in field \"final_outcomes\"), got 0.25"},
      {"T/DC6/000", [](json& r) { r["seed"] = 999; }, "field \"seed\" must be 7, the seed the plan gives trial T/DC6/000"},
      // Found by a probe: a time to threshold edited by hand was reported.
      {"T/DC6/000", [](json& r) { r["time_to_threshold_s"] = 1.0; },
       "field \"time_to_threshold_s\" is 1, but its checkpoints reached the threshold at "},
      {"T/DC6/000", [](json& r) { r["checkpoints"].back()["success_rate"] = 0.0; },
       "field \"reached\" is true, but its last checkpoint's success rate is below the threshold 0.9"},
      // Found by a probe: with no checkpoint at all it spoke of the last one's rate.
      {"T/DC6/000", [](json& r) { r["checkpoints"] = json::array(); },
       "field \"reached\" is true, but it has no checkpoint that could have reached the threshold"},
  };
  for (const Edit& e : edits) {
    const std::string file = "trials/" + std::string(e.trial) + "/result.json";
    const json good = folder.read(file);
    REQUIRE(good["success_rate"] == 1.0);  // kill_batch's policies succeed everywhere
    json bad = good;
    e.spoil(bad);
    folder.write(file, bad);
    INFO(e.says);
    std::string said;
    CHECK(folder.report(said) == 1);
    CHECK_THAT(said, Contains(std::string(e.trial) + " (") && Contains("CORRUPT: " + (folder.dir / file).string() + ": " + e.says));
    CHECK_THROWS_WITH(write_report(folder.dir.string()), Contains((folder.dir / file).string() + ": " + e.says));
    folder.write(file, good);
  }
}

// Found by a probe: an evaluation trial kept no episodes, so a reward mean edited by hand beside
// outcomes left alone was reported; a training trial's final.jsonl backed its outcomes only.
TEST_CASE("a trial's per-episode records back its reward, time and outcomes", "[report]") {
  const KillCopy folder("episode_records");
  const fs::path eval_dir = folder.dir / "trials" / "eval" / "gen" / "circle" / "000";
  const std::string eval_file = (eval_dir / "eval.jsonl").string(), final_file =
      (folder.dir / "trials" / "T" / "DC6" / "000" / "final.jsonl").string();
  const json eval_result = folder.read("trials/eval/gen/circle/000/result.json");
  CHECK(eval_result["episodes_file"] == "eval.jsonl");
  const std::string lines = slurp(eval_file);
  REQUIRE(std::count(lines.begin(), lines.end(), '\n') == 12);
  double sum = 0.0;
  std::istringstream in(lines);
  for (std::string line; std::getline(in, line);) {
    const json record = json::parse(line);
    CHECK(record["success"] == true);
    sum += record["reward"].get<double>();
  }
  CHECK(sum / 12 == Approx(eval_result["reward_mean"].get<double>()));
  auto refused = [&](const std::string& says, const std::string& ending = "") {
    INFO(says);
    std::string said;
    CHECK(folder.report(said) == 1);
    CHECK_THAT(said, Contains("CORRUPT: " + says) && Contains(ending));
    CHECK_THROWS_WITH(write_report(folder.dir.string()), Contains(says) && Contains(ending));
  };
  const double mean = eval_result["reward_mean"].get<double>();
  {  // the result's mean edited
    json bad = eval_result;
    bad["reward_mean"] = mean + 1.0;
    folder.write("trials/eval/gen/circle/000/result.json", bad);
    refused(eval_file + ": its episodes' \"reward\" give a mean of " + format_number(mean) +
            ", but the trial's result.json records " + bad["reward_mean"].dump() + " (\"reward_mean\"): edited?");
    folder.write("trials/eval/gen/circle/000/result.json", eval_result);
  }
  {  // a training trial's final std and time mean edited
    const json good = folder.read("trials/T/DC6/000/result.json");
    for (const char* field : {"reward_std", "final_time_mean"}) {
      json bad = good;
      bad[field] = good[field].get<double>() + 0.5;
      folder.write("trials/T/DC6/000/result.json", bad);
      refused(final_file + ": its episodes' \"" + (field == std::string("reward_std") ? "reward\" give a std" : "sim_s\" give a mean"),
              std::string("(\"") + field + "\"): edited?");
    }
    folder.write("trials/T/DC6/000/result.json", good);
  }
  {  // an episode's reward edited, a success flipped, a line lost, the file gone
    std::string one_reward = lines;
    const size_t at = one_reward.find("\"reward\":") + 9;
    one_reward.insert(at, "1");
    spit(eval_file, one_reward);
    refused(eval_file + ": its episodes' \"reward\" give a mean of ");
    std::string flipped = lines;
    const size_t third = flipped.find("\"success\":true", flipped.find('\n', flipped.find('\n') + 1));
    flipped.replace(third, 14, "\"success\":false");
    spit(eval_file, flipped);
    refused(eval_file + ":3: \"success\": false, but the trial's result.json records episode 3 a success (\"outcomes\")");
    spit(eval_file, lines.substr(0, lines.rfind('\n', lines.size() - 2) + 1));
    refused(eval_file + ": holds 11 evaluation episodes, but the trial's result.json records 12 (\"outcomes\")");
    fs::remove(eval_file);
    refused(eval_file + ": missing: the trial's result.json records 12 evaluation episodes (\"outcomes\")");
  }
  {  // a result from before eval.jsonl was written has no episodes_file, and is read as before
    json old = eval_result;
    old.erase("episodes_file");
    folder.write("trials/eval/gen/circle/000/result.json", old);
    std::string said;
    CHECK(folder.report(said) == 0);
  }
}

// Found by a probe: a report whose script no longer asks for a figure left that figure's files
// beside it, ready to be published with a report that does not name them.
TEST_CASE("a report removes the figures of the previous report that it no longer draws", "[report]") {
  const KillCopy folder("dropped_figure");
  REQUIRE(fs::exists(folder.dir / "figure5.png"));
  spit(folder.dir / "notes.png", "a file of the user's");  // in no report's list: never touched
  json manifest = folder.read("manifest.json");
  json& figures = manifest["config"]["figures"];
  figures.erase(std::remove_if(figures.begin(), figures.end(), [](const json& f) { return f["file"] == "figure5"; }),
                figures.end());
  folder.write("manifest.json", manifest);
  std::string said;
  REQUIRE(folder.report(said) == 0);
  CHECK_FALSE(fs::exists(folder.dir / "figure5.png"));
  CHECK_FALSE(fs::exists(folder.dir / "figure5.svg"));
  CHECK(fs::exists(folder.dir / "figure4.png"));
  CHECK(slurp(folder.dir / "notes.png") == "a file of the user's");
}

// Found by a probe: a task axis choosing among strings of 100,000 characters crashed roger run
// at its report: the figure of the teacher's draws read the axis from the recorded task space by
// std::regex, whose matcher recursed once per character and overflowed the stack.
TEST_CASE("the figure of a teacher's draws reads an axis of long choices", "[report][run]") {
  const test::TempDir dir("roger_report_long_choice");
  const std::string scenario = (dir.path / "scenario.lua").string(), curriculum = (dir.path / "curriculum.lua").string();
  spit(scenario, "local base = require('unobstructed')\nlocal params = {}\n"
                 "for k, v in pairs(base.params) do params[k] = v end\n"
                 "params.label = { default = 'a', choices = { 'a', string.rep('x', 100000) } }\n"
                 "return { params = params, generate = function(world, rng, p)\n"
                 "  local _ = p.label\n  base.generate(world, rng, p)\nend }\n");
  spit(curriculum, "local p = require('lib.skills').primitives()\n"
                   "return { name = 'c', stages = { roger.stage{ name = 'S', scenario = '" + scenario + "',\n"
                   "  time_limit = 1, absorbing = roger.converged(p.phi0), budget = { episodes = 4 },\n"
                   "  checkpoints = { every = 2, threshold = 0.9 }, test = { tasks = 2, seed = 1 },\n"
                   "  tasks = { label = roger.choice{ 'a', string.rep('x', 100000) } },\n"
                   "  contexts = { { name = 'A', actions = { p.search, p.phi0 } } } } } }\n");
  spit(dir.path / "batch.lua", "return { name = 'b', curriculum = '" + curriculum + "', trials = 1,\n"
                               "  runs = { { name = 'R', stage = 'S', contexts = { 'A' } } },\n"
                               "  figures = { { file = 'tasks_R', kind = 'tasks', run = 'R', param = 'label' } } }\n");
  const std::string out = (dir.path / "out").string();
  const int raw = std::system((std::string(ROGER_BINARY) + " run " + (dir.path / "batch.lua").string() + " --out " + out +
                               " > " + (dir.path / "log").string() + " 2>&1").c_str());
  INFO(slurp(dir.path / "log").substr(0, 2000));
  REQUIRE(WIFEXITED(raw));
  CHECK(WEXITSTATUS(raw) == 0);
  CHECK(fs::exists(fs::path(out) / "tasks_R.svg"));
}

// Found by deleting a training trial's final.jsonl: the report's table by obstacles silently
// counted 30 episodes of 40, and a resumed run took the trial as finished.
TEST_CASE("a training trial's final.jsonl missing or cut short is refused and the trial run again", "[report][run]") {
  const KillCopy folder("final_records");
  const fs::path final_file = folder.dir / "trials/T/DC6/000/final.jsonl";
  const std::string whole = slurp(final_file);
  const int n = folder.read("trials/T/DC6/000/result.json")["final_episodes"];
  REQUIRE(n >= 2);
  std::string said;
  fs::remove(final_file);
  CHECK(folder.report(said) == 1);
  CHECK_THAT(said, Contains("CORRUPT: " + final_file.string() + ": missing: the trial's result.json records " +
                            std::to_string(n) + " final-evaluation episodes"));
  CHECK_THAT(said, Contains("runs a trial with corrupt files again"));
  // Found by a probe: the refusal did not say that --partial cannot help, or what else does.
  CHECK_THAT(said, Contains("removing such a trial's folder under trials/ does the same). roger report --partial "
                            "cannot help: a report never reads a corrupt record, not even as pending."));
  CHECK_THROWS_WITH(write_report(folder.dir.string()), Contains(final_file.string() + ": missing"));
  // Cut at the end of a line, every line left parses: only the count shows the loss.
  size_t cut = 0;
  for (int k = 0; k < n - 1; ++k) cut = whole.find('\n', cut) + 1;
  spit(final_file, whole.substr(0, cut));
  const std::string says = final_file.string() + ": holds " + std::to_string(n - 1) +
                           " final-evaluation episodes, but the trial's result.json records " + std::to_string(n);
  CHECK_THROWS_WITH(write_report(folder.dir.string()), Contains(says));
  // Found by a probe: cut within its last line, it passed (only report --by, parsing the lines,
  // failed, for good, since the trial was kept).
  spit(final_file, whole.substr(0, whole.size() - 30));
  CHECK_THROWS_WITH(write_report(folder.dir.string()),
                    Contains(final_file.string() + ": its last line has no end, as a file cut short has"));
  std::string middle = whole;
  middle.erase(middle.find('\n') - 5, 5);  // the first line's end edited away
  spit(final_file, middle);
  CHECK_THROWS_WITH(write_report(folder.dir.string()),
                    Contains(final_file.string() + ":1: not a JSON object on one line"));
  // Found by a probe: successes flipped to failures passed, and one report gave the trial's
  // episodes 100% in its table and 75% split by obstacles.
  std::string flipped = whole;
  const size_t second = flipped.find('\n') + 1;
  const size_t at = flipped.find("\"success\":true", second);
  REQUIRE(at != std::string::npos);
  REQUIRE(at < flipped.find('\n', second));
  flipped.replace(at, 14, "\"success\":false");
  spit(final_file, flipped);
  CHECK_THROWS_WITH(write_report(folder.dir.string()),
                    Contains(final_file.string() + ":2: \"success\": false, but the trial's result.json records "
                             "episode 2 a success (\"final_outcomes\"): edited?"));
  // Found by a probe: a world's count edited to a word made a column of its own in a --by table, and
  // a record without the feature, edited out, was left out of every cell, unsaid.
  std::string worded = whole;
  const size_t count_at = worded.find("\"obstacles\":", worded.find("\"world\""));
  REQUIRE(count_at < worded.find('\n'));
  worded.replace(count_at, 12, "\"obstacles\":\"many\",\"was\":");
  spit(final_file, worded);
  CHECK_THROWS_WITH(write_report(folder.dir.string(), {"obstacles"}),
                    Contains(final_file.string() + ":1: field \"world\": \"obstacles\" must be a count, got \"many\""));
  std::string renamed = whole;
  renamed.replace(count_at, 12, "\"obstaclez\":");
  spit(final_file, renamed);
  CHECK_THROWS_WITH(write_report(folder.dir.string(), {"obstacles"}),
                    Contains(final_file.string() + ":1: a final-evaluation record without 'obstacles', which the "
                             "others of T/DC6 hold"));
  spit(final_file, whole.substr(0, cut));
  // A resumed run runs that trial again, which writes the same file.
  CHECK(folder.resume(said) == 0);
  CHECK_THAT(said, Contains(says) && Contains("running trial T/DC6/000 again"));
  CHECK(slurp(final_file) == whole);
  CHECK(folder.report(said) == 0);
}

// Found by a probe: trial 001's policy.json copied over trial 000's was taken, and a resumed run
// built the runs that take its skill on it.
TEST_CASE("a training trial's policy.json of another trial is refused and the trial run again", "[report][run]") {
  const KillCopy folder("foreign_policy");
  const fs::path mine = folder.dir / "trials/SG/DC2/000/policy.json";
  const std::string whole = slurp(mine);
  fs::copy_file(folder.dir / "trials/SG/DC2/001/policy.json", mine, fs::copy_options::overwrite_existing);
  std::string said;
  CHECK(folder.report(said) == 1);
  CHECK_THAT(said, Contains("CORRUPT: " + mine.string() + ": field \"seed\" is ") &&
                       Contains(", but the plan gives trial SG/DC2/000 ") && Contains(": the policy of another trial"));
  CHECK(folder.resume(said) == 0);
  CHECK_THAT(said, Contains("running trial SG/DC2/000 again"));
  CHECK(slurp(mine) == whole);
}

// Found by resuming with an edited script: both sides of the difference were the whole "runs"
// list cut at the same 77 characters, before the change.
TEST_CASE("a resumed run with another script names the first place the configurations differ", "[report][run]") {
  const KillCopy folder("changed_script");
  const fs::path script = folder.dir.string() + ".lua";
  std::string text = slurp("tests/scripts/kill_batch.lua");
  text = std::regex_replace(text, std::regex("curriculum = \"kill_curriculum.lua\""),
                            "curriculum = \"" + fs::absolute("tests/scripts/kill_curriculum.lua").string() + "\"");
  text = std::regex_replace(text, std::regex("contexts = \\{ \"DC6\" \\},"), "contexts = { \"DC6\" }, trials = 1,");
  spit(script, text);
  std::string said;
  CHECK(folder.resume(said, script.string()) == 1);
  fs::remove(script);
  INFO(said);
  CHECK_THAT(said, Contains("made by another batch script or other parameters"));
  // Counted from 1, as the Lua script's lists are.
  CHECK_THAT(said, Contains("\n  runs[2].trials: 2 in the folder, 1 now\n"));
  CHECK_THAT(said, Contains("\n  evaluations[1].trials: 2 in the folder, 1 now\n"));
  CHECK(said.find("\n  runs: ") == std::string::npos);
}

// Found by a probe: one trial of 24 censored marked the row's median and interquartile mean with ≥,
// though the censored trial (the slowest) lies outside their windows and they are exact.
TEST_CASE("a row's median and IQM are marked as bounds only when a censored trial enters them", "[report]") {
  const auto row_of = [](int censored) {
    report_detail::Results r;
    for (int i = 0; i < 24; ++i) {
      const bool reached = i < 24 - censored;
      r.ok.push_back({{"time_to_threshold_s", reached ? 100.0 + 10.0 * i : 1000.0}, {"reached", reached},
                      {"final_episodes", 50}, {"reward_mean", 10.0}, {"reward_std", 1.0}, {"success_rate", 0.9}});
    }
    BatchTable t;
    t.baseline = "B1";
    std::ostringstream md;
    json rows = json::array();
    report_detail::run_table_row("DC2", r, t, {}, 0.0, md, rows);
    return std::make_pair(md.str(), rows[0]);
  };
  const auto [one_md, one] = row_of(1);
  INFO(one_md);
  CHECK(one["time_lower_bound"] == true);  // the mean's
  CHECK(one["time_median_lower_bound"] == false);
  CHECK(one["time_iqm_lower_bound"] == false);
  // Its resamples would need the censored trial seven times over for the IQM to reach it.
  CHECK(one["time_iqm_ci_lower_bound"] == json{false, false});
  CHECK_THAT(one_md, Contains("| DC2 | ≥ 4:03 | - | 10.0 ± 1.0 | 90.0% | 3:35 | 3:35 [2:57, 4:13] | 95.8% |"));
  const auto [seven_md, seven] = row_of(7);
  INFO(seven_md);
  CHECK(seven["time_median_lower_bound"] == false);
  CHECK(seven["time_iqm_lower_bound"] == true);
  CHECK(seven["time_iqm_ci_lower_bound"] == json{false, true});
  CHECK_THAT(seven_md, Contains(" | 3:35 | ≥ "));
  const auto [none_md, none] = row_of(0);
  CHECK(none["time_lower_bound"] == false);
  CHECK(none["time_iqm_ci_lower_bound"] == json{false, false});
  CHECK(none_md.find("≥") == std::string::npos);
}

// Found by a probe: a baseline that never reached the threshold made "% Improvement" read as exact,
// and the cumulative figure labelled censored means without their "≥".
TEST_CASE("bounds from censored trials are marked in the improvement and the cumulative figure", "[report]") {
  KillCopy copy("censored");
  std::string said;
  json last_rate;  // of SG/DC2/001, put back below
  for (const char* id : {"trials/SG/B1/000/result.json", "trials/SG/DC2/001/result.json"}) {
    json j = copy.read(id);
    j["reached"] = false;  // its time is then its whole training time: a lower bound
    last_rate = j["checkpoints"].back()["success_rate"];
    j["checkpoints"].back()["success_rate"] = 0.5;  // as a trial that missed it ends (checked against reached)
    copy.write_training(id, j);
  }
  REQUIRE(copy.report(said) == 0);
  const std::string tables = slurp(copy.dir / "tables.md");
  INFO(tables);
  CHECK(std::regex_search(tables, std::regex("\\| DC2 \\| ≥ [0-9]+:[0-9]{2} \\| ~ -?[0-9.]+% \\|")));
  CHECK_THAT(tables, Contains("one marked ~ compares two lower bounds"));
  // Found by a probe: the interval's bounds of a censored row read as exact, and report.json said
  // nothing of its lower bounds; summary.csv gave the whole training as a time to the threshold.
  CHECK(std::regex_search(tables, std::regex("≥ [0-9]+:[0-9]{2} \\[≥ [0-9]+:[0-9]{2}, ≥ [0-9]+:[0-9]{2}\\]")));
  const json rows = json::parse(slurp(copy.dir / "report.json"));
  CHECK_THAT(rows.dump(), Contains("\"time_lower_bound\":true") && Contains("\"time_lower_bound\":false") &&
                             Contains("\"mann_whitney_exact\":"));
  const std::string csv = slurp(copy.dir / "summary.csv");
  CHECK_THAT(csv, Contains("\nSG/B1/000,train,SG,SG,B1,,,0,") && Contains(",ok,false,,,,"));
  // Figure 5 of kill_batch stacks trial i's Phi_SG (SG/DC2) under T: trial 1's never reached it.
  const std::string page = slurp(copy.dir / "dashboard.js");
  CHECK_THAT(page, Contains("\"lower_bound\":[true]") && Contains("\"lower_bound\":[false]"));
  // Only the baseline censored: the improvement over it is at least what it says.
  json dc2 = copy.read("trials/SG/DC2/001/result.json");
  dc2["reached"] = true;
  dc2["checkpoints"].back()["success_rate"] = last_rate;
  copy.write_training("trials/SG/DC2/001/result.json", dc2);
  REQUIRE(copy.report(said) == 0);
  CHECK(std::regex_search(slurp(copy.dir / "tables.md"), std::regex("\\| DC2 \\| [0-9]+:[0-9]{2} \\| ≥ -?[0-9.]+% \\|")));
}

// Found in a review: Figure 5 stacked SG's time under B2, whose actions hold no Phi_SG; the paper
// adds it "as appropriate". DC6 uses it inside Phi_STG (its record's "skills" names it).
TEST_CASE("the cumulative figure stacks a skill's time only under the contexts that use it", "[report]") {
  test::TempDir dir("roger_report_as_appropriate");
  fs::copy_file("tests/scripts/kill_curriculum.lua", dir.path / "kill_curriculum.lua");
  std::string batch = slurp("tests/scripts/kill_batch.lua");
  const std::string dc6 = "contexts = { \"DC6\" }, skills";
  REQUIRE(batch.find(dc6) != std::string::npos);
  batch.replace(batch.find(dc6), dc6.size(), "contexts = { \"B2\", \"DC6\" }, skills");
  spit(dir.path / "b.lua", batch);
  RunArgs a;
  a.script = (dir.path / "b.lua").string();
  a.out = (dir.path / "out").string();
  a.jobs = 2;
  std::ostringstream said;
  a.progress = &said;
  REQUIRE(command_run(a) == 0);
  const std::string js = slurp(dir.path / "out" / "dashboard.js");
  const json page = json::parse(js.substr(js.find('=') + 1, js.rfind(';') - js.find('=') - 1));
  int figures = 0;
  for (const auto& f : page["figures"])
    if (f["kind"] == "cumulative") {
      ++figures;
      REQUIRE(f["categories"] == json::array({"B2", "DC6"}));
      const json& sg = f["stacks"][0];
      CHECK(sg["name"] == "SG (Phi_SG, DC2)");
      CHECK(sg["minutes"][0] == 0.0);  // B2: no Phi_SG
      CHECK(sg["minutes"][1].get<double>() > 0.0);
      CHECK(f["stacks"][1]["minutes"][0].get<double>() > 0.0);  // B2's own time
    }
  CHECK(figures == 1);
  CHECK_THAT(slurp(dir.path / "out" / "tables.md"), Contains("in the contexts that use the skill"));
}

// Found by a probe: a row of one trial showed an IQM interval "[2:30, 2:30]", a p-value of 1 and a
// P(faster) from a single pair, as if they were evidence.
TEST_CASE("a row of one trial shows no interval and no test", "[report]") {
  KillCopy copy("one_trial");
  fs::remove_all(copy.dir / "trials" / "SG" / "DC2" / "001");
  ReportArgs r;
  r.dir = copy.dir.string();
  r.partial = true;
  std::ostringstream said;
  r.progress = &said;
  REQUIRE(command_report(r) == 0);
  const std::string tables = slurp(copy.dir / "tables.md");
  INFO(tables);
  CHECK(std::regex_search(tables, std::regex("\\| DC2 \\| [0-9]+:[0-9]{2} \\| -?[0-9.]+% \\| [^|]+ \\| [^|]+ \\| "
                                             "[0-9]+:[0-9]{2} \\| [0-9]+:[0-9]{2} \\| [0-9.]+% \\| - \\| - \\|")));
  CHECK(std::regex_search(tables, std::regex("\\| B1 \\| [^\\n]*\\[[0-9]+:[0-9]{2}, [0-9]+:[0-9]{2}\\] \\|")));
  const json report = json::parse(slurp(copy.dir / "report.json"));
  CHECK_THAT(report.dump(), Contains("\"time_iqm_ci_s\":null"));
  CHECK_THAT(report.dump(), !Contains("\"mann_whitney_p\""));
}

// Found by a probe: a comparison's row trained with other scenario parameters stood beside the
// others with nothing to tell them apart (a run's own table names them).
TEST_CASE("a comparison names each run's stage and parameters", "[report][run]") {
  const test::TempDir tmp("roger_report_compare_params");
  spit(tmp.path / "batch.lua",
       "return { name = 'cmp', curriculum = '" + fs::absolute("tests/scripts/kill_curriculum.lua").string() + "',\n"
       "  trials = 1, seed = 7,\n"
       "  runs = { { name = 'SG', stage = 'SG', contexts = { 'DC2' } },\n"
       "           { name = 'SG_heavy', stage = 'SG', contexts = { 'DC2' }, params = { mass = 0.7 } } },\n"
       "  tables = { { title = 'Cmp', compare = { 'SG/DC2', 'SG_heavy/DC2' } } }, figures = {} }\n");
  RunArgs a;
  a.script = (tmp.path / "batch.lua").string();
  a.out = (tmp.path / "out").string();
  a.jobs = 2;
  std::ostringstream os;
  a.progress = &os;
  REQUIRE(command_run(a) == 0);
  CHECK_THAT(slurp(tmp.path / "out" / "tables.md"),
             Contains("Rows: a context of a run each, against `SG/DC2`; run `SG_heavy`: stage SG with mass=0.7.\n"));
  const json runs = json::parse(slurp(tmp.path / "out" / "report.json"))["tables"][0]["runs"];
  CHECK(runs == json::array({{{"run", "SG"}, {"stage", "SG"}, {"params", json::object()}},
                             {{"run", "SG_heavy"}, {"stage", "SG"}, {"params", {{"mass", "0.7"}}}}}));
}

// Found by a probe: the Total row read "8/8" policies for 4 policies on 2 objects, and dropped the
// "(1 failed)" of its shape's row.
TEST_CASE("an evaluation's Total row counts policies on objects and keeps the failed ones", "[report]") {
  KillCopy copy("eval_total");
  std::string said;
  REQUIRE(copy.report(said) == 0);
  CHECK_THAT(slurp(copy.dir / "tables.md"), Contains("| 4/4 of 2 policies × 2 objects | 48 | 48 |"));
  const fs::path trial = copy.dir / "trials" / "eval" / "gen" / "circle" / "000";
  fs::remove(trial / "result.json");
  spit(trial / "error.json", json{{"error", "a fault"}, {"trial", "eval/gen/circle/000"}}.dump());
  REQUIRE(copy.report(said) == 0);
  const std::string tables = slurp(copy.dir / "tables.md");
  CHECK_THAT(tables, Contains("| 1/2 (1 failed) | 12 | 12 |") &&
                         Contains("| 3/4 of 2 policies × 2 objects (1 failed) | 36 | 36 |"));
  // Found by a probe: report.json's evaluation rows did not count the failed trials, so a figure
  // script read a rate pooled over fewer policies without knowing it; and roger report said nothing.
  const json rows = copy.read("report.json")["tables"].back()["rows"];
  REQUIRE(rows.size() == 3);
  CHECK(rows[0]["object"] == "circle");
  CHECK(rows[0]["failed"] == 1);
  CHECK(rows[0]["pending"] == 0);
  CHECK(rows[1]["failed"] == 0);
  CHECK(rows[2]["object"] == "Total");
  CHECK(rows[2]["failed"] == 1);
  CHECK_THAT(said, Contains("roger report: 1 trial failed, so the tables and figures draw on the others") &&
                       Contains("\n  eval/gen/circle/000: a fault\n"));
  // The failed evaluation's row of summary.csv names its stage, as the others do.
  CHECK_THAT(slurp(copy.dir / "summary.csv"), Contains("\neval/gen/circle/000,eval,T,T,DC6,gen,circle,0,,failed,") &&
                                                  Contains("\neval/gen/spade/000,eval,T,T,DC6,gen,spade,0,,ok,"));
}

namespace {

// roger report --partial on a copy of the kill batch's folder: its exit status, and what it said.
int partial_report(const KillCopy& copy, std::string& said, const std::vector<std::string>& by = {}) {
  ReportArgs r;
  r.dir = copy.dir.string();
  r.partial = true;
  r.by = by;
  std::ostringstream os;
  r.progress = &os;
  const int status = command_report(r);
  said = os.str();
  return status;
}

// Makes a trial of the copy pending (its folder gone) or failed (an error.json for its result).
void make_pending(const KillCopy& copy, const std::string& id) { fs::remove_all(copy.dir / "trials" / id); }
void make_failed(const KillCopy& copy, const std::string& id) {
  const fs::path trial = copy.dir / "trials" / id;
  fs::remove(trial / "result.json");
  spit(trial / "error.json", json{{"error", "a fault"}, {"trial", id}}.dump());
}

size_t occurrences(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

// Found by a probe: a partial report's tables.md and report.json did not say they were partial;
// only the Trials column read "pending".
TEST_CASE("a partial report says so in tables.md and report.json and the figures' list", "[report]") {
  KillCopy copy("partial_banner");
  std::string said;
  REQUIRE(copy.report(said) == 0);
  CHECK(!copy.read("report.json").contains("partial"));
  CHECK(slurp(copy.dir / "tables.md").find("Partial report") == std::string::npos);
  make_pending(copy, "T/DC6/000");
  make_pending(copy, "T/DC6/001");
  make_failed(copy, "SG/DC2/001");
  REQUIRE(partial_report(copy, said) == 0);
  const std::string tables = slurp(copy.dir / "tables.md");
  INFO(tables);
  CHECK_THAT(tables, Contains("# Results: kill\n\n**Partial report:** 7 of 10 trials have results (2 pending, 1 failed); "
                              "the tables and figures draw only on the trials with results.\n"));
  CHECK(copy.read("report.json")["partial"] ==
        json{{"trials", 10}, {"with_results", 7}, {"pending", 2}, {"failed", 1}});
  CHECK(std::regex_search(tables, std::regex("figure3\\.svg`: [^\\n]*\\(DC2 from 1 of 2 trials\\)\\n")));
  CHECK(std::regex_search(tables, std::regex("figure4\\.svg`: [^\\n]*\\(DC6 pending\\)\\n")));
  CHECK(std::regex_search(tables, std::regex("iqm_T\\.svg`: [^\\n]*\\(DC6 pending\\)\\n")));
  CHECK(std::regex_search(tables, std::regex("iqm_SG\\.svg`: [^\\n]*\\(DC2 from 1 of 2 trials\\)\\n")));
  // Found by a probe: a table split by a feature pooled what trials it had and said nothing of
  // the others; its rows now end in the Trials column the other tables have.
  REQUIRE(partial_report(copy, said, {"obstacles"}) == 0);
  const std::string whole = slurp(copy.dir / "tables.md");
  REQUIRE(whole.find(": final success by obstacles") != std::string::npos);
  const std::string split = whole.substr(whole.find(": final success by obstacles"));
  INFO(split);
  CHECK(std::regex_search(split, std::regex("\\| DC2 \\|[^\\n]* 1/2 \\(1 failed\\) \\|\\n")));
  CHECK(std::regex_search(split, std::regex("\\| DC6 \\|[^\\n]* 0/2 \\(2 pending\\) \\|\\n")));
  bool by_row = false;
  const json report = copy.read("report.json");
  for (const json& table : report["tables"])
    if (table.contains("by"))
      for (const json& row : table["rows"])
        if (row["context"] == "DC6") {
          by_row = true;
          CHECK(row["pending"] == 2);
          CHECK(row["trials"] == 0);
        }
  CHECK(by_row);
}

// Found by a probe: with a skill's source trial missing, Figure 5's skill part fell to the trials
// left (or to 0 with none) under every bar, and its line said nothing.
TEST_CASE("a partial cumulative figure names its skill's missing trials", "[report]") {
  KillCopy copy("partial_cumulative");
  make_failed(copy, "SG/DC2/001");
  std::string said;
  REQUIRE(partial_report(copy, said) == 0);
  const std::string tables = slurp(copy.dir / "tables.md");
  INFO(tables);
  CHECK(std::regex_search(tables, std::regex("figure5\\.svg`: [^\\n]*\\(SG/DC2 from 1 of 2 trials\\)\\n")));
  CHECK(std::regex_search(tables, std::regex("figure4\\.svg`: [^\\n]*[^)]\\n")));  // T's own trials are all there
  // With none of the skill's trials, its legend entry says it has no bar (found by a probe: it
  // named a colour the figure lacked).
  auto stack_names = [&]() {
    const std::string page = slurp(copy.dir / "dashboard.js");
    const json report = json::parse(page.substr(page.find('=') + 1, page.rfind(';') - page.find('=') - 1));
    for (const json& f : report["figures"])
      if (f["kind"] == "cumulative") return f["stacks"];
    return json();
  };
  CHECK(stack_names()[0]["name"] == "SG (Phi_SG, DC2)");
  make_failed(copy, "SG/DC2/000");
  REQUIRE(partial_report(copy, said) == 0);
  CHECK(stack_names()[0]["name"] == "SG (Phi_SG, DC2) (not drawn)");
  CHECK(stack_names()[1]["name"] == "T");
}

TEST_CASE("a partial report with one trial's result says it in the singular", "[report]") {
  KillCopy copy("partial_one");
  for (const char* id : {"SG/B1/001", "SG/DC2/000", "SG/DC2/001", "T/DC6/000", "T/DC6/001", "eval/gen/circle/000",
                         "eval/gen/circle/001", "eval/gen/spade/000", "eval/gen/spade/001"})
    make_pending(copy, id);
  std::string said;
  REQUIRE(partial_report(copy, said) == 0);
  const std::string tables = slurp(copy.dir / "tables.md");
  CHECK_THAT(tables, Contains("**Partial report:** 1 of 10 trials has a result (9 pending);"));
  // Every evaluation pending: a Total row of the counts alone, as the shape rows (found by a later
  // probe: it was left out), and the note under the table pools none in it.
  CHECK_THAT(tables, Contains("| Spade | - | - | - | 0/2 (2 pending) | 0 | 0 |\n"
                              "| **Total** | - | - | - | 0/4 of 2 policies × 2 objects (4 pending) | 0 | 0 |\n\nAvg. reward") &&
                         !Contains("(in the Total row"));
}

// Found by a probe: DC6 was blue in a partial Figure 4 and orange in the full one; a curve's
// colour followed the curves drawn, not the figure's contexts.
TEST_CASE("a curve keeps its colour when the figure's other curves are pending", "[report]") {
  KillCopy copy("partial_colour");
  const std::string blue = "stroke:rgb(0%,44.705882%,69.803922%)", orange = "stroke:rgb(83.529412%,36.862745%,0%)";
  std::string said;
  REQUIRE(copy.report(said) == 0);
  const std::string full = slurp(copy.dir / "figure3.svg");  // B1 blue, DC2 orange
  REQUIRE_THAT(full, Contains(blue) && Contains(orange));
  make_pending(copy, "SG/B1/000");
  make_pending(copy, "SG/B1/001");
  REQUIRE(partial_report(copy, said) == 0);
  for (const char* figure : {"figure3.svg", "iqm_SG.svg"}) {
    const std::string partial = slurp(copy.dir / figure);
    INFO(figure);
    CHECK_THAT(partial, Contains(orange));
    CHECK(partial.find(blue) == std::string::npos);
  }
}

// Found by a probe: a success-rate curve read "Test tasks mastered" on a stage without a test set,
// whose checkpoints' success rates are over their held-out episodes, not over any set of tasks.
TEST_CASE("a success-rate curve says test tasks mastered only when its trials had a test set", "[report]") {
  KillCopy copy("success_label");
  json manifest = copy.read("manifest.json");
  manifest["config"]["figures"].push_back(
      {{"file", "success_SG"}, {"title", ""}, {"kind", "curves"}, {"run", "SG"}, {"log_x", false}, {"y", "success"}});
  copy.write("manifest.json", manifest);
  auto label = [&]() {
    std::string said;
    REQUIRE(copy.report(said) == 0);
    const std::string page = slurp(copy.dir / "dashboard.js");
    const json report = json::parse(page.substr(page.find('=') + 1, page.rfind(';') - page.find('=') - 1));
    std::map<std::string, std::string> labels;
    for (const json& f : report["figures"])
      if (f["kind"] == "curves") labels[f["file"].get<std::string>()] = f.value("y_label", std::string());
    return labels;
  };
  std::map<std::string, std::string> labels = label();
  CHECK(labels["success_SG"] == "Checkpoint episodes succeeded (%)");
  CHECK(labels["figure3"] == "Greedy episodic reward");
  CHECK_THAT(slurp(copy.dir / "tables.md"), Contains("without one, the share of the checkpoint's held-out episodes"));
  // The same trials, as if each had run a test set of 4 tasks at its checkpoints.
  for (const char* id : {"SG/B1/000", "SG/B1/001", "SG/DC2/000", "SG/DC2/001"}) {
    const fs::path file = copy.dir / "trials" / id / "result.json";
    json r = json::parse(slurp(file));
    r["test"]["tasks"] = 4;
    spit(file, r.dump(1));
  }
  labels = label();
  CHECK(labels["success_SG"] == "Test tasks mastered (%)");
}

// Found by a probe: with every evaluation pending, Table III's note read "...drawn from: . It is".
TEST_CASE("Table III's interval note reads as a sentence when no evaluation has a result", "[report]") {
  KillCopy copy("partial_note");
  for (const char* id : {"eval/gen/circle/000", "eval/gen/circle/001", "eval/gen/spade/000", "eval/gen/spade/001"})
    make_pending(copy, id);
  std::string said;
  REQUIRE(partial_report(copy, said) == 0);
  const std::string tables = slurp(copy.dir / "tables.md");
  CHECK(tables.find("drawn from: .") == std::string::npos);
  CHECK_THAT(tables, Contains("draws again what the episodes were drawn from (none yet: no trial of the table has a "
                              "result). It is never narrower"));
}

// Found by a probe: 2499 successes in 2500 episodes read "100.0%", hiding the failure.
TEST_CASE("a success rate that is not 1 never reads 100.0% and one above 0 never reads 0.0%", "[report]") {
  KillCopy copy("rate_digits");
  // Results from before the outcomes were recorded carry a rate alone, of any count of episodes.
  auto set_rate = [&](const std::string& id, double rate) {
    json j = copy.read("trials/" + id + "/result.json");
    j.erase("final_outcomes");
    j["final_episodes"] = 2500;
    j["success_rate"] = rate;
    copy.write("trials/" + id + "/result.json", j);
  };
  set_rate("SG/B1/000", 0.9992);
  set_rate("SG/B1/001", 1.0);
  set_rate("SG/DC2/000", 0.0008);
  set_rate("SG/DC2/001", 0.0);
  std::string said;
  REQUIRE(copy.report(said) == 0);
  INFO(said);
  const std::string tables = slurp(copy.dir / "tables.md");
  INFO(tables);
  CHECK(std::regex_search(tables, std::regex("\\| B1 \\|[^\\n]*\\| 99\\.96% \\|")));
  CHECK(std::regex_search(tables, std::regex("\\| DC2 \\|[^\\n]*\\| 0\\.04% \\|")));
}

// Found reading the change: 10% and 1% start with a '1' followed by zeros, and were taken for
// 100% and given nine decimals ("10.000000000%").
TEST_CASE("rate_pct adds digits only where one decimal would read 100% or 0%", "[report]") {
  using report_detail::rate_pct;
  CHECK(rate_pct(1.0) == "100.0%");
  CHECK(rate_pct(0.0) == "0.0%");
  CHECK(rate_pct(0.1) == "10.0%");
  CHECK(rate_pct(0.01) == "1.0%");
  CHECK(rate_pct(0.5) == "50.0%");
  CHECK(rate_pct(0.9996) == "99.96%");
  CHECK(rate_pct(0.99996) == "99.996%");
  CHECK(rate_pct(0.0004) == "0.04%");
}

// Found by a probe: --by shape --by shape wrote each split table twice.
TEST_CASE("a --by feature given twice splits each table once", "[report]") {
  KillCopy copy("by_twice");
  std::string said;
  REQUIRE(partial_report(copy, said, {"obstacles"}) == 0);
  const std::string once = slurp(copy.dir / "tables.md");
  REQUIRE(partial_report(copy, said, {"obstacles", "obstacles"}) == 0);
  const std::string twice = slurp(copy.dir / "tables.md");
  CHECK(occurrences(twice, ": final success by obstacles") == occurrences(once, ": final success by obstacles"));
  CHECK(occurrences(twice, ": final success by obstacles") == 2);  // Tables I and II
}

// Found by a probe: the heat map of where a teacher sampled labelled its bins to two significant
// digits, so the bin of 1.16 to 1.28 read "1.2 to 1.3", and draws below 1.2 seemed above it.
TEST_CASE("bins are labelled finely enough to say where they lie", "[report]") {
  CHECK(report_detail::bin_label(0.8, 2.0, 2, 10) == "1.04 to 1.16");
  CHECK(report_detail::bin_label(0.8, 2.0, 3, 10) == "1.16 to 1.28");
  CHECK(report_detail::bin_label(0.0, 1.0, 0, 10) == "0 to 0.1");
  CHECK(report_detail::bin_label(0.0, 1.0, 9, 10) == "0.9 to 1");
  CHECK(report_detail::bin_label(-1.0, 1.0, 4, 10) == "-0.2 to 0");
  CHECK(report_detail::bin_label(0.0, 1000.0, 2, 10) == "200 to 300");
  CHECK(report_detail::bin_label(0.0, 0.001, 1, 10) == "0.0001 to 0.0002");
  CHECK(report_detail::bin_label(0.3, 2.4, 0, 5) == "0.3 to 0.72");
}

// Found by a probe: two trials' first seeds just below 2^53 (9007199254740991 and ...993) read as
// doubles became one layout, so an evaluation of 4 worlds counted 3 and its interval was resampled
// as if two policies had shared a world. Seeds are read as the integers they are.
TEST_CASE("rate cells keep every world seed apart, past 2^53 too", "[report]") {
  std::vector<RateCell> cells;
  report_detail::append_rate_cells(json{{"first_seed", 9007199254740991u}, {"episodes", 2}, {"outcomes", "10"}}, 0, "first_seed",
                    "episodes", "outcomes", cells);
  report_detail::append_rate_cells(json{{"first_seed", 9007199254740993u}, {"episodes", 2}, {"outcomes", "01"}}, 1, "first_seed",
                    "episodes", "outcomes", cells);
  std::set<int64_t> layouts;
  for (const RateCell& c : cells) layouts.insert(c.layout);
  CHECK(layouts.size() == 4);
  CHECK(cells[2].layout == int64_t(9007199254740993u));
}

// Found by a probe: a label of -1e308 ("%.2f": 313 characters) was cut at 63 by a fixed buffer.
TEST_CASE("a number formatted for the report is never cut", "[report]") {
  const std::string huge = report_detail::fmt("%.2f", -1e308);
  CHECK(huge.size() == 313);  // "-", 309 digits, ".00"
  CHECK(huge.substr(huge.size() - 3) == ".00");
  CHECK(report_detail::fmt("%.2f", 0.5) == "0.50");
}
