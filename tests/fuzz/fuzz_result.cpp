// fuzz_result: a trial's result.json on arbitrary bytes, read as `roger report` reads it
// (engine/batch/plan.cpp trial_status, engine/report/report.cpp). The results folder is a valid
// one (tests/fuzz/report_manifest.json: two training runs and an evaluation, one trial each, every
// kind of table and figure); the fuzzed bytes are the result of every one of its trials.
#include "batch/batch.h"
#include "fuzz_support.h"
#include "report/report.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  namespace fs = std::filesystem;
  const fs::path dir = roger::fuzz::scratch_dir() / "results";
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::copy_file(ROGER_FUZZ_REPORT_MANIFEST, dir / "manifest.json");
  roger::fuzz::expect_success_or_roger_error([&] {
    const roger::BatchPlan plan = roger::read_results_plan(dir.string());
    for (const auto& phase : plan.phases)
      for (const auto& trial : phase) {
        const fs::path trial_dir = roger::trial_dir(dir.string(), trial.id);
        fs::create_directories(trial_dir);
        roger::fuzz::write_bytes(trial_dir / "result.json", data, size);
      }
    roger::write_summary_csv(plan, roger::summarize_trials(plan));
    roger::write_report(dir.string());
  });
  return 0;
}
