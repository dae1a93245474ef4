// fuzz_manifest: a results folder's manifest.json on arbitrary bytes, read as `roger report` reads
// it (engine/batch/plan.cpp read_results_plan, engine/script/batch/batch_script.cpp
// batch_config_from_json, engine/report/report.cpp write_report). The folder holds no trial yet,
// so every table and figure is reported as pending.
#include "batch/batch.h"
#include "fuzz_support.h"
#include "report/report.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  namespace fs = std::filesystem;
  const fs::path dir = roger::fuzz::scratch_dir() / "manifest";
  fs::remove_all(dir);
  fs::create_directories(dir);
  roger::fuzz::write_bytes(dir / "manifest.json", data, size);
  roger::fuzz::expect_success_or_roger_error([&] {
    const roger::BatchPlan plan = roger::read_results_plan(dir.string());
    roger::missing_trials(plan);
    roger::write_summary_csv(plan, roger::summarize_trials(plan));
    roger::write_report(dir.string());
  });
  return 0;
}
