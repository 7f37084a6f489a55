#include <filesystem>

#include <fmt/format.h>

#include "apps/commands.h"
#include "core/parallel.h"
#include "experiments/recompute_metrics.h"
#include "experiments/result_store.h"
#include "experiments/runner.h"
#include "reports/report.h"

namespace causticbench {

int run_experiment_command(const ExperimentOptions& options) {
  // Everything is checked before any work starts.
  Experiment experiment = load_experiment(options.experiment);
  if (!options.filter.empty()) check_filter_terms(experiment, options.filter);
  RunOptions run;
  run.results = options.results;
  run.dry_run = options.dry_run;
  run.force = options.force;
  run.filter = options.filter;
  run.threads = options.threads;
  if (!options.shard.empty()) parse_shard(options.shard, run.shard_index, run.shard_count);
  check_results_folder(options.results);
  ThreadLimit limit(options.threads);
  RunSummary summary = run_experiment(experiment, run);
  fmt::print("{}: {} runs, {} selected, {} already stored, {} run now, {} failed\n", experiment.name, summary.total,
             summary.selected, summary.stored, summary.completed, summary.failed);
  if (options.dry_run) return 0;
  std::string folder = ResultPaths{options.results}.experiment(experiment.name);
  if (options.report) return run_report(folder);
  fmt::print("results: {}\n", folder);
  return 0;
}

int run_report(const std::string& folder, bool recompute_metrics) {
  if (recompute_metrics) {
    RecomputeSummary recomputed = causticbench::recompute_metrics(folder);
    for (const std::string& problem : recomputed.problems) fmt::print(stderr, "warning: {}\n", problem);
    fmt::print("metrics recomputed for {} runs ({} skipped: failed, missing or not matching their images)\n",
               recomputed.recomputed, recomputed.skipped);
  }
  ReportSummary report = write_report(folder);
  fmt::print("report: {} ({} runs, {} failed)\n", report.html, report.runs, report.failed);
  fmt::print("also: {}, {}, {}\n", report.markdown, report.csv, report.json);
  return 0;
}

}  // namespace causticbench
