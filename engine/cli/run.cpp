// run.cpp: `roger run` (a batch script: plan, run every trial resumably, then the report) and
// `roger report` (tables and figures from a results folder). docs/batch.md describes both.
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <vector>
#include <string>

#include "batch/batch.h"
#include "cli/cli_internal.h"
#include "cli/commands.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/text.h"
#include "report/report.h"
#include "script/batch/batch_script.h"
#include "script/curriculum/curriculum.h"
#include "script/sandbox/lua_sandbox.h"

namespace roger {

namespace {

// The --trials and --set overrides of a batch script.
BatchOverrides overrides_of(const RunArgs& a) {
  BatchOverrides ov;
  ov.trials = a.trials;
  ov.sets = split_sets(a.sets, "--set");
  ov.instructions = a.lua.instructions;
  ov.memory_mib = a.lua.memory_mib;
  if (a.trials < 0) throw Error("--trials must be positive");
  return ov;
}

// A file's path from the project folder when inside it ("curricula/paper.lua"), else absolute.
std::string shown_from_project(const std::string& file) {
  std::error_code ec;
  const std::filesystem::path path = std::filesystem::absolute(file, ec).lexically_normal();
  const std::filesystem::path rel = path.lexically_relative(std::filesystem::weakly_canonical(project_root(), ec));
  return !rel.empty() && *rel.begin() != ".." ? rel.generic_string() : path.string();
}

// The closing lines of a run; returns 1 when some trial it selected failed or has corrupt files.
// The counts of the first line add up to its trials: those with a result, this run's failed and
// unreadable ones, those it has not run yet, and those outside its --only (not this command's).
int print_outcome(const BatchSummary& s, std::ostream& log, const std::string& again) {
  const size_t outside = size_t(s.outside_pending + s.outside_failed + s.outside_corrupt);
  const size_t done = s.trials - s.failed.size() - s.corrupt.size() - size_t(s.pending) - outside;
  log << "roger run: " << done << " of " << s.trials << (s.trials == 1 ? " trial" : " trials") << " done in "
      << format_duration(s.wall_s);
  // A resumed run: how many of them it ran, so "12 of 12 done in 1 s" does not read as 12 trials a second.
  if (done > s.finished_now) log << " (" << (done - s.finished_now) << " of them by earlier runs)";
  if (!s.failed.empty()) log << ", " << s.failed.size() << " failed";
  if (!s.corrupt.empty()) log << ", " << s.corrupt.size() << " with unreadable files";
  if (s.pending) log << ", " << s.pending << " not run yet (" << again << ")";
  std::vector<std::string> apart;
  if (s.outside_pending) apart.push_back(std::to_string(s.outside_pending) + " outside --only not run");
  if (s.outside_failed) apart.push_back(std::to_string(s.outside_failed) + " outside --only failed earlier");
  if (s.outside_corrupt) apart.push_back(std::to_string(s.outside_corrupt) + " outside --only with unreadable files");
  if (!apart.empty())
    log << ", " << join(apart, ", ") << " (run the command without --only, or with an --only that names them, to "
        << "run them)";
  log << "\n";
  if (!s.corrupt.empty()) {
    log << "roger run: " << s.corrupt.size() << " trial" << (s.corrupt.size() == 1 ? " has" : "s have")
        << " unreadable files (the same command runs them again when it selects them):\n";
    for (const auto& c : s.corrupt) log << "  " << c << "\n";
  }
  if (s.failed.empty()) return s.corrupt.empty() ? 0 : 1;
  const bool one = s.failed.size() == 1;
  log << "roger run: " << s.failed.size() << " trial" << (one ? "" : "s") << " failed ("
      << (one ? "its error.json holds the whole message; the same command tries it again" :
                "their error.json holds the whole message; the same command tries them again") << "):\n";
  for (const auto& f : s.failed) log << "  " << f << "\n";
  return 1;
}

// The note of a run under --explain that found `n` training trials finished by an earlier run
// without --explain: it runs no finished trial again, so they keep their result as it is.
void print_undiagnosed(int n, std::ostream& log) {
  log << "roger run: --explain: " << counted(n, "training trial") << " finished earlier "
      << (n == 1 ? "keeps its" : "keep their") << " result.json without a diagnosis (--explain adds one to the "
      << "trials it runs; a run that missed its threshold has one either way). For a diagnosis of every trial, run "
      << "the command with --explain into a new --out\n";
}

// scripts/slurm/submit.sh as a path that works from here: as it is in the project folder, else whole
// (found by a probe: a task's log said "submit this shard again: scripts/slurm/submit.sh ..." to a
// researcher submitting from a folder of their own, which has no scripts/).
std::string submit_script() {
  std::error_code ec;
  if (std::filesystem::equivalent(std::filesystem::current_path(ec), project_root(), ec)) return "scripts/slurm/submit.sh";
  return shell_word((project_root() / "scripts" / "slurm" / "submit.sh").string());
}

// "0-3, 7, 9-11": whole numbers, runs of consecutive ones as their ends.
std::string number_ranges(const std::set<int>& numbers) {
  std::string text;
  for (auto it = numbers.begin(); it != numbers.end();) {
    auto end = it;
    while (std::next(end) != numbers.end() && *std::next(end) == *end + 1) ++end;
    text += (text.empty() ? "" : ", ") + std::to_string(*it) + (end == it ? "" : "-" + std::to_string(*end));
    it = std::next(end);
  }
  return text;
}

// Lists the trials a report still needs; returns 1.
int print_missing(const std::vector<MissingTrial>& missing, const BatchPlan& plan, std::ostream& log) {
  const bool corrupt = std::any_of(missing.begin(), missing.end(), [](const MissingTrial& m) { return !m.problem.empty(); });
  log << "roger report: " << missing.size() << " trial" << (missing.size() == 1 ? "" : "s") << " of " << plan.out
      << (missing.size() == 1 ? " has" : " have") << " no result yet" << (corrupt ? " or a corrupt one" : "")
      << ", so no report was written:\n";
  // Every corrupt trial, and the first 20 of those without a result; the rest counted by run and
  // context or evaluation (found by a probe: 823 pending trials were 823 lines).
  // One more than 20 is listed rather than counted (found by a probe: "... and 1 more").
  const long pending = std::count_if(missing.begin(), missing.end(), [](const MissingTrial& m) { return m.problem.empty(); });
  const int kShown = pending <= 21 ? 21 : 20;
  int shown = 0;
  std::vector<std::pair<std::string, int>> rest;  // "run/context" or "evaluation" -> trials not listed
  std::set<int> rest_shards;                       // the shards of those, for the advice below
  for (const auto& m : missing) {
    const PlannedTrial& t = *m.trial;
    if (m.problem.empty() && shown == kShown) {
      const std::string group = t.run ? t.run->name + "/" + t.context : "eval/" + t.evaluation->name;
      auto it = std::find_if(rest.begin(), rest.end(), [&](const auto& g) { return g.first == group; });
      if (it == rest.end()) it = rest.insert(rest.end(), {group, 0});
      ++it->second;
      int shard = 0, shards = 0;
      if (std::sscanf(m.owner.c_str(), "shard %d of %d", &shard, &shards) == 2) rest_shards.insert(shard);
      continue;
    }
    if (m.problem.empty()) ++shown;
    log << "  " << t.id << " (";
    if (t.run) log << "run " << t.run->name << ", context " << t.context;
    else log << "evaluation " << t.evaluation->name << (t.shape.empty() ? "" : ", shape " + t.shape);
    log << ", trial " << t.index << (m.owner.empty() ? "" : "; " + m.owner) << ")";
    if (!m.problem.empty()) log << ": CORRUPT: " << m.problem.substr(0, m.problem.find('\n'));
    log << "\n";
  }
  if (!rest.empty()) {
    int more = 0;
    std::string groups;
    for (const auto& [group, n] : rest) {
      more += n;
      groups += (groups.empty() ? "" : ", ") + group + " (" + std::to_string(n) + (n == 1 ? " trial)" : " trials)");
    }
    // Their shards too (found by a probe: 568 more of a 50-shard run, and the advice to submit again
    // "each shard K named above" named only the first 21).
    log << "  ... and " << more << " more without a result: " << groups
        << (rest_shards.empty() ? "" : "; of shards " + number_ranges(rest_shards)) << "\n";
  }
  const bool sharded = std::any_of(missing.begin(), missing.end(), [](const MissingTrial& m) { return !m.owner.empty(); });
  // The script by its place, not as it was typed (found by a probe: `roger run quick.lua` of a lab's
  // own quick.lua, pasted in another folder, ran the project's scripts/quick.lua into the folder).
  const std::string script = plan.script->file.empty() ? plan.script->path : shown_from_project(plan.script->file);
  log << "Run the roger run command that made the folder again (roger run " << shell_word(script)
      << " --out " << shell_word(plan.out) << ", with the same options and the same --shard for a shard"
      << (sharded ? "; shards of a Slurm array: " + submit_script() + " SCRIPT N --array=K for each shard K named "
                    "above, with the same ROGER_OUT and ROGER_ARGS"
                  : "")
      << ") to finish them"
      << (corrupt ? " (it runs a trial with corrupt files again from scratch; removing such a trial's folder "
                    "under trials/ does the same). roger report --partial cannot help: a report never reads a "
                    "corrupt record, not even as pending.\n"
                  : ", or\nroger report --partial " + shell_word(plan.out) + " to report what is there, marked as pending.\n");
  return 1;
}

// Writes the report at the end of a run; returns "written", or "failed" having said why.
std::string report_of_run(const BatchPlan& plan, std::ostream& log) {
  try {
    for (const auto& f : write_report(plan.out)) log << "roger run: wrote " << f << "\n";
    return "written";
  } catch (const FileError&) {
    write_closing_status(plan.out, "failed");
    throw;  // the machine's fault, not the report's: command_run says it, with what to do
  } catch (const std::exception& e) {
    log << "roger run: the report failed: " << e.what() << "\n";
    return "failed";
  }
}

}  // namespace

std::string report_file_error_line(const FileError& e) {
  if (e.error_number == EACCES || e.error_number == EPERM || e.error_number == EROFS)
    return std::string(e.what()) + ". roger report writes its report into the results folder: make the folder "
           "writable (or copy it somewhere writable and report the copy), then run the same command again";
  return file_error_line(e, false);
}

std::string error_line(const std::string& message) {
  const std::string roger = "roger ";
  if (message.rfind(roger, 0) == 0) {
    const size_t colon = message.find(": ");
    const std::string command = message.substr(roger.size(), colon == std::string::npos ? 0 : colon - roger.size());
    const bool one_word = !command.empty() && command.find_first_not_of("abcdefghijklmnopqrstuvwxyz") == std::string::npos;
    if (one_word) return message.substr(0, colon) + ": error: " + message.substr(colon + 2);
  }
  return "roger: error: " + message;
}

std::string file_error_line(const FileError& e, bool resumes) {
  const std::string rerun = std::string("run the same command again") + (resumes ? ": it resumes where this one stopped" : "");
  const std::string again = "then " + rerun;
  switch (e.error_number) {
    case ENOSPC:
    case EDQUOT:
      return std::string("the disk is full: ") + e.what() + ". Free some space, " + again;
    case EACCES:
    case EPERM:
    case EROFS:
      return std::string(e.what()) + ". Make the folder writable (or give another with --out), " + again;
    case ENOENT:
    case 0: {
      // Either something the run used was removed under it, or the path never led anywhere (a
      // folder of --out that does not exist): the advice differs.
      const std::string what = e.what();
      if (what.find("removed while") != std::string::npos) return what + ". Put it back as it was, " + again;
      if (what.find("changed while") != std::string::npos)  // an edit: the finished trials read the old text
        return what + ". Put it back as it was, " + again + "; or, to run the new version, give another --out";
      // Found by a probe: /proc/x.png is refused with ENOENT, though /proc exists.
      std::error_code ec;
      const std::filesystem::path parent = std::filesystem::path(e.path).parent_path();
      if (!e.path.empty() && !parent.empty() && std::filesystem::is_directory(parent, ec))
        return what + ". The folder " + parent.string() + " exists but takes no new file (a system folder?): give "
               "another path, " + again;
      return what + ". A folder on that path does not exist: make it, or give another path, " + again;
    }
    case ENOTDIR:
    case EEXIST:  // a file where a folder must be: nothing was made, so nothing resumes
      return std::string(e.what()) + ". A file is in the way of a folder there: give another path, or move the file";
    default:
      return std::string(e.what()) + ". Once the cause is fixed, " + rerun;
  }
}

namespace {

// "SCRIPT -> OUT (N trials, curriculum C)", and the shard's line, each after `prefix`.
void print_run_plan(const BatchPlan& plan, const Shard& shard, const std::string& prefix, std::ostream& log) {
  const BatchScript& b = *plan.script;
  size_t trials = 0;
  for (const auto& p : plan.phases) trials += p.size();
  // The curriculum's file as found (a same-named file in the working folder is taken first).
  const std::string found = shown_from_project(b.curriculum_file);
  log << prefix << b.path << " -> " << plan.out << " (" << trials << (trials == 1 ? " trial" : " trials")
      << ", curriculum " << b.curriculum << (found == b.curriculum ? "" : ": " + found) << ")\n";
  if (shard.active()) log << prefix << describe_shard(plan, shard) << "\n";
}

// What a run says as it starts: its script, folder, trials and curriculum, its shard, and the
// dashboard that follows it.
void print_run_start(const BatchPlan& plan, const Shard& shard, std::ostream& log) {
  print_run_plan(plan, shard, "roger run: ", log);
  // The dashboard from the start: it follows the run's status.js until the report is written. Written
  // before the line names it: a folder that takes no file left "roger run: open " unfinished above
  // the error (found by a probe).
  const std::string page = write_dashboard_page(plan.out);
  log << "roger run: open " << page << " to follow the run\n";
}

// For a task of a Slurm array (--shard slurm), how to submit its shard again, which runs what it
// left ("" otherwise: the same command does). Found by a probe: a cancelled task's log said "run
// the same command again", which is array.sbatch's.
std::string submit_again(const RunArgs& a, const BatchPlan& plan, const Shard& shard) {
  if (a.shard != "slurm") return "";
  return submit_script() + " " + shell_word(plan.script->path) + " " + std::to_string(shard.count) +
         " --array=" + std::to_string(shard.index) + ", with the same ROGER_OUT and ROGER_ARGS";
}

// After the trials: the report (unless a shard, --no-report or unreadable trials), summary.csv,
// the closing status and the exit status, which says whether the run was interrupted.
int finish_run(const RunArgs& a, const BatchPlan& plan, const Shard& shard, const BatchSummary& summary,
               std::ostream& log) {
  const bool reporting = !a.no_report && !shard.active() && summary.corrupt.empty();
  // The report is short and written whole or not at all: a first Ctrl-C from now on lets it finish.
  if (reporting) catch_interrupts("finishing the report of the finished trials, then exiting");
  if (summary.undiagnosed) print_undiagnosed(summary.undiagnosed, log);
  int status = 0;
  std::string report = "none";
  // A stop that came before the report began (a resumed folder whose trials had all ended) is not
  // one "during the report" (found by a probe).
  const bool stopped_before_report = interrupt_requested();
  if (!summary.corrupt.empty() && !a.no_report && !shard.active()) {
    log << "roger run: no report: some trials' files cannot be read (listed below)\n";
  } else if (reporting) {
    log << "roger run: writing the report\n";
    report = report_of_run(plan, log);
    status = report == "written" ? 0 : 1;
  }
  // After the report: a kill in between leaves the previous summary beside the previous report.
  if (!shard.active()) {
    write_summary_csv(plan, summary);
    log << "roger run: wrote " << (std::filesystem::path(plan.out) / "summary.csv").string() << "\n";
  }
  // A shard's final status stays: it says what the run waits for (other shards, roger report).
  if (!shard.active()) write_closing_status(plan.out, report);
  const std::string again = submit_again(a, plan, shard);
  const int outcome =
      print_outcome(summary, log, again.empty() ? "run the same command again to continue"
                                                : "to continue, submit this shard again: " + again) ? 1 : status;
  // A stop with no selected trial left to run cut nothing (every one had a result before it came).
  const bool cut = summary.interrupted && summary.pending > 0;
  if (!cut && interrupt_requested()) {
    log << "roger run: stopped on request after its trials had ended"
        << (report != "written"        ? ""
            : stopped_before_report ? ", before the report, which was written all the same"
                                    : ", during the report, which was completed")
        << "\n";
    return interrupt_exit_status();
  }
  if (!cut) return outcome;
  log << "roger run: interrupted; the trials that were running start afresh when you "
      << (again.empty() ? "run the same command again" : "submit this shard again (" + again + ")") << "\n";
  return interrupt_exit_status();  // 130 after Ctrl-C, 143 after SIGTERM, as a shell reports them
}

// roger run --dry-run, once the script, its selectors and test tasks have passed: what the run
// would find in its folder (inspect_results_folder refuses what opening it would), then an --only
// that needs trials outside it; said on the standard output, nothing written, no trial run.
// Found by a probe: scripts/slurm/submit.sh queued shards that each refused their folder, or a
// misspelt option of ROGER_ARGS, once they had waited in the queue.
int dry_run(const RunArgs& a, const BatchPlan& plan, const Shard& shard) {
  const std::string folder = inspect_results_folder(plan, shard);
  // What the run would meet opening the folder (found by a probe: a folder in use by another run,
  // or read-only, passed the dry run and refused the run).
  if (const std::string why = results_folder_unavailable(plan.out, shard, a.only); !why.empty())
    throw Error(why + "; the run would be refused");
  check_only_needs(plan, a.only, shard);
  print_run_plan(plan, shard, "roger run --dry-run: ", std::cout);
  std::cout << "roger run --dry-run: " << folder << "\n"
            << "roger run --dry-run: nothing written, no trial run\n";
  return 0;
}

// A test task no layout of its world seed holds fails every trial of its run at the first
// evaluation that runs it: said before any trial starts, as roger check says it (found by a
// newcomer: the nine trials of such a batch trained to their first checkpoint, then all failed).
// Runs of the same parameters are checked together. Returns whether any was found.
bool refuse_unplaceable_test_tasks(const BatchScript& b, std::ostream& log) {
  std::map<ParamList, std::vector<std::string>> stages_by_params;
  for (const BatchRun& r : b.runs) stages_by_params[r.params].push_back(r.stage);
  size_t found = 0;
  for (const auto& [params, stages] : stages_by_params)
    for (const std::string& p : check_test_sets(b.curriculum_file, b.limits, params, stages)) {
      log << "roger run: " << p << "\n";
      ++found;
    }
  if (found) log << "roger run: nothing run: every trial of such a run would fail (roger check says the same)\n";
  return found > 0;
}

}  // namespace

int command_run(const RunArgs& a) {
  std::ostream& log = a.progress ? *a.progress : std::cerr;
  catch_interrupts();  // Ctrl-C keeps what finished and writes the report of it (below)
  std::string out;  // the results folder, once known
  try {
    const Shard shard = a.shard.empty() ? Shard() : parse_shard(a.shard);
    const BatchOverrides overrides = overrides_of(a);
    if (const std::string why = module_given(a.script, resolve_batch_script_path(a.script), "batch script"); !why.empty())
      throw Error(why);
    auto script = std::make_shared<const BatchScript>(load_batch_script(a.script, overrides));
    const BatchScript& b = *script;
    for (const std::string& n : b.notes) log << "roger run: note: " << n << "\n";  // as roger check says them
    for (const std::string& w : unread_sets_in_batch(b, overrides.sets)) log << "roger run: warning: " << w << "\n";
    const BatchPlan plan = plan_batch(script, a.out.empty() ? "results/" + b.name : a.out);
    out = plan.out;
    check_selectors(plan, a.only);
    if (refuse_unplaceable_test_tasks(b, log)) return 1;
    if (a.dry_run) return dry_run(a, plan, shard);
    // A new folder's --only that needs trials outside it is refused before anything is made there
    // (found by a probe: its manifest then refused the corrected command's other --trials); an
    // existing folder's once it is opened, against the trials it holds.
    std::error_code ec;
    const bool fresh = !std::filesystem::exists(std::filesystem::path(plan.out) / "manifest.json", ec);
    if (fresh) check_only_needs(plan, a.only, shard);
    check_out_folder(plan.out);  // before the claim makes its lock files there
    const RunningClaim claim(plan.out, shard, a.only);  // until the run has ended, its report written
    std::string note;
    // A shard's first start in a folder another shard made is no resumption (found by a probe: every
    // shard but the first said "resuming" on the batch's first run).
    const bool shard_ran_here = shard.active() && std::filesystem::exists(shard.record_path(plan.out), ec);
    const bool resuming = open_results_folder(plan, &note, shard, &claim);
    if (!fresh) check_only_needs(plan, a.only, shard);  // before "resuming": a refused --only resumes nothing
    if (resuming && shard.active() && !shard_ran_here)
      log << "roger run: joining the shards' folder " << plan.out << " (this shard's first start there)\n";
    else if (resuming) log << "roger run: resuming " << plan.out << "\n";
    if (!note.empty()) log << "roger run: " << note << "\n";
    print_run_start(plan, shard, log);
    const BatchSummary summary = run_batch(plan, RunControl{a.jobs, a.live, a.max_trials, a.only, &log, shard, !a.no_eval_cache, a.explain});
    return finish_run(a, plan, shard, summary, log);
  } catch (const FileError& e) {
    // A folder without a manifest has nothing to resume (found by probes: --out /sys/x, and a
    // read-only empty folder, said "it resumes where this one stopped").
    std::error_code ec;
    const bool made = !out.empty() && std::filesystem::exists(std::filesystem::path(out) / "manifest.json", ec);
    log << "roger run: error: " << file_error_line(e, made) << "\n";
    return 1;
  } catch (const std::exception& e) {
    log << "roger run: error: " << e.what() << "\n";
    return 1;
  }
}

int command_report(const ReportArgs& a) {
  std::ostream& log = a.progress ? *a.progress : std::cerr;
  // The report is short and written whole or not at all: a first Ctrl-C lets it finish, as in
  // roger run (found by a probe: it stopped without a word, its staging folder left behind).
  catch_interrupts("finishing the report, then exiting");
  try {
    const BatchPlan plan = read_results_plan(a.dir);
    const std::vector<MissingTrial> missing = missing_trials(plan);
    const bool corrupt = std::any_of(missing.begin(), missing.end(), [](const MissingTrial& m) { return !m.problem.empty(); });
    // A corrupt record is never reported, not even as pending: the report would be wrong about it.
    if (!missing.empty() && (!a.partial || corrupt)) return print_missing(missing, plan, log);
    // The report first: summary.csv is only replaced once the tables and figures are.
    const std::vector<std::string> written = write_report(a.dir, a.by);
    const BatchSummary summary = summarize_trials(plan);
    write_summary_csv(plan, summary);
    log << "roger report: wrote " << (std::filesystem::path(plan.out) / "summary.csv").string() << "\n";
    for (const auto& f : written) log << "roger report: wrote " << f << "\n";
    // The dashboard of a sharded run waits for this report: the run's closing status (none
    // without a status.json) says it is there. A partial report leaves the status to the trials
    // still to come.
    if (missing.empty()) write_closing_status(plan.out, "written");
    else refresh_status_place(plan);
    if (summary.pending)
      log << "roger report: " << counted(summary.pending, "trial") << (summary.pending == 1 ? " has" : " have")
          << " no result yet (marked pending)\n";
    // Found by a probe: a report over failed trials said nothing of them but the files it wrote,
    // so `roger report DIR && figure.py DIR` never noticed its rates pooled fewer trials.
    if (!summary.failed.empty()) {
      log << "roger report: " << counted(long(summary.failed.size()), "trial") << " failed, so the tables and figures "
          << "draw on the others (tables.md opens with a Partial report line; report.json's \"partial\" counts them; "
          << "`roger run` with the same command tries them again):\n";
      for (const auto& f : summary.failed) log << "  " << f << "\n";
    }
    if (interrupt_requested()) {
      log << "roger report: stopped on request, once the report was written\n";
      return interrupt_exit_status();
    }
    return 0;
  } catch (const FileError& e) {
    log << "roger report: error: " << report_file_error_line(e) << "\n";
    return 1;
  } catch (const std::exception& e) {
    log << "roger report: error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace roger
