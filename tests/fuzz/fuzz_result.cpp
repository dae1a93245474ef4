// fuzz_result: a trial's result.json on arbitrary bytes, read as `roger report` reads it
// (engine/batch/records.cpp trial_status, engine/report/report.cpp). The results folder is a valid
// one (tests/fuzz/report_manifest.json: two training runs and an evaluation, one trial each, every
// kind of table and figure); the fuzzed bytes are the result of every one of its trials.
//
// Bytes that are a JSON object without an "id" are completed as roger run writes a trial's record:
// each trial's own "id" and "trial", and beside a training trial a policy.json over its "psi" (up to
// four actions) and a final.jsonl of its "final_outcomes". Without that every record but one failed
// the id check, and the report's tables, figures and teacher lines never read a fuzzed field. Bytes
// with an "id", or that are no object, go in as they are: the record checks' own inputs.
#include "batch/batch.h"
#include "core/json_input.h"
#include "fuzz_support.h"
#include "learn/learning.h"
#include "report/report.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Writes what roger run leaves beside a training trial's result `r`: its policy and final episodes.
void write_training_files(const fs::path& trial_dir, const json& r) {
  if (r.contains("psi") && r["psi"].is_array() && r["psi"].size() <= 4) {
    std::vector<std::string> psi;
    for (const json& a : r["psi"])
      if (a.is_string()) psi.push_back(a.get<std::string>());
    try {
      const std::string policy = roger::QTable(psi).to_json().dump();
      roger::fuzz::write_bytes(trial_dir / "policy.json", reinterpret_cast<const uint8_t*>(policy.data()), policy.size());
    } catch (const roger::Error&) {  // names no QTable takes: the record check refuses the trial
    }
  }
  if (r.contains("final_outcomes") && r["final_outcomes"].is_string()) {
    std::string lines;
    for (const char c : r["final_outcomes"].get<std::string>()) lines += c == '1' ? "{\"success\":true}\n" : "{\"success\":false}\n";
    roger::fuzz::write_bytes(trial_dir / "final.jsonl", reinterpret_cast<const uint8_t*>(lines.data()), lines.size());
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const fs::path dir = roger::fuzz::scratch_dir() / "results";
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::copy_file(ROGER_FUZZ_REPORT_MANIFEST, dir / "manifest.json");
  // Read as the engine reads a result (parse_json): nlohmann's own parse would let through a value
  // nested so deep that copying it here overflows the harness's stack, not the engine's.
  const std::string text_given(reinterpret_cast<const char*>(data), size);
  const json given = roger::parse_json(text_given.cbegin(), text_given.cend(), false);
  const bool complete = given.is_object() && !given.contains("id");
  roger::fuzz::expect_success_or_roger_error([&] {
    const roger::BatchPlan plan = roger::read_results_plan(dir.string());
    for (const auto& phase : plan.phases)
      for (const auto& trial : phase) {
        const fs::path trial_dir = roger::trial_dir(dir.string(), trial.id);
        fs::create_directories(trial_dir);
        if (!complete) {
          roger::fuzz::write_bytes(trial_dir / "result.json", data, size);
          continue;
        }
        json r = given;
        r["id"] = trial.id, r["trial"] = trial.index;
        const std::string text = r.dump();
        roger::fuzz::write_bytes(trial_dir / "result.json", reinterpret_cast<const uint8_t*>(text.data()), text.size());
        if (trial.run) write_training_files(trial_dir, r);
      }
    roger::write_summary_csv(plan, roger::summarize_trials(plan));
    roger::write_report(dir.string());
  });
  return 0;
}
