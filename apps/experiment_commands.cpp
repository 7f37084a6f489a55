#include <filesystem>

#include <fmt/format.h>

#include "apps/commands.h"
#include "core/errors.h"
#include "core/parallel.h"
#include "experiments/recompute_metrics.h"
#include "store/result_paths.h"
#include "experiments/runner.h"
#include "experiments/shard_plan.h"
#include "store/sweep_status.h"
#include "reports/report.h"
#include "reports/summary.h"

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
  run.prepare_only = options.prepare_only;
  if (!options.shard.empty()) parse_shard(options.shard, run.shard_index, run.shard_count);
  if (!options.shard_plan.empty()) {
    if (options.shard.empty()) throw InputError("--shard-plan: expected with --shard i/n, found no --shard");
    ShardPlan plan = read_shard_plan(options.shard_plan, experiment);
    if (plan.shards != run.shard_count) {
      throw InputError(fmt::format("--shard {}: expected n = {}, the shards of the plan {}", options.shard, plan.shards,
                                   options.shard_plan));
    }
    run.shard_of = plan.shard_of;
  }
  check_results_folder(options.results);
  ThreadLimit limit(options.threads);
  RunSummary summary = run_experiment(experiment, run);
  if (options.prepare_only) {
    fmt::print("{}: references and builds ready for {} runs ({} builds computed, {} already stored)\n", experiment.name,
               summary.selected - summary.stored, summary.builds_computed, summary.builds_stored);
    return 0;
  }
  fmt::print("{}: {} runs, {} selected, {} already stored, {} run now, {} failed\n", experiment.name, summary.total,
             summary.selected, summary.stored, summary.completed, summary.failed);
  if (options.dry_run) return 0;
  std::string folder = ResultPaths{options.results}.experiment(experiment.name);
  if (options.report) return run_report(folder);
  fmt::print("results: {}\n", folder);
  return 0;
}

int run_report(const std::string& folder, bool recompute_metrics, double viewer_megabytes) {
  if (recompute_metrics) {
    RecomputeSummary recomputed = causticbench::recompute_metrics(folder);
    for (const std::string& problem : recomputed.problems) fmt::print(stderr, "warning: {}\n", problem);
    fmt::print("metrics recomputed for {} runs ({} skipped: failed, missing or not matching their images)\n",
               recomputed.recomputed, recomputed.skipped);
  }
  ReportSummary report = write_report(folder, viewer_megabytes);
  fmt::print("report: {} ({} runs, {} failed)\n", report.html, report.runs, report.failed);
  fmt::print("also: {}, {}, {}\n", report.markdown, report.csv, report.json);
  if (!report.viewer.empty())
    fmt::print("viewer: {} (full-resolution images, {:.1f} MB of pixels under report/view/)\n", report.viewer,
               report.viewer_bytes / 1e6);
  return 0;
}

int run_summarize(const std::vector<std::string>& folders, const std::string& out) {
  std::string target = out;
  if (target.empty() && !folders.empty()) {
    std::filesystem::path first = std::filesystem::path(folders.front()).lexically_normal();
    if (!first.has_filename()) first = first.parent_path();  // "results/study_ring/"
    target = first.has_parent_path() ? first.parent_path().string() : ".";
  }
  SummaryFiles summary = write_summary(folders, target);
  fmt::print("summary: {} ({} experiments, {} scenes, {} claims: {})\n", summary.html, summary.experiments,
             summary.scenes, summary.claims.total, summary.claims.breakdown());
  for (const std::string& line : summary.headlines) fmt::print("  {}\n", line);
  fmt::print("also: {}, {}\n", summary.markdown, summary.json);
  return 0;
}

int run_status(const std::string& folder) {
  SweepStatus status = sweep_status(folder, experiment_file_runs);
  if (!status.plan_problem.empty()) {
    fmt::print("warning: the shard plan is damaged ({}); counting the runs of experiment.json instead, without "
               "shards (`causticbench slurm` writes the plan again)\n",
               status.plan_problem);
  }
  fmt::print("{} ({}): {} runs: {} stored ok, {} failed, {} pending\n", status.experiment, folder, status.all.total,
             status.all.ok, status.all.failed, status.all.pending);
  fmt::print("  {:<14} {:>6} {:>6} {:>7} {:>8}\n", "method", "runs", "ok", "failed", "pending");
  for (const auto& [method, counts] : status.methods) {
    fmt::print("  {:<14} {:>6} {:>6} {:>7} {:>8}\n", method, counts.total, counts.ok, counts.failed, counts.pending);
  }
  if (!status.plan.empty()) {
    std::vector<std::string> shards, pending;
    for (const auto& [shard, runs] : status.shard_pending) {
      shards.push_back(std::to_string(shard));
      pending.push_back(fmt::format("shard {} has {} pending", shard, runs));
    }
    fmt::print("shards ({} planned in {}): {}\n", status.shards, status.plan,
               pending.empty() ? std::string("none has runs to do") : join(pending, ", "));
    if (!shards.empty()) {
      fmt::print("  to finish them: sbatch --array={} {}\n", join(shards, ","),
                 (std::filesystem::path(status.plan).parent_path() / "shards.sbatch").string());
    }
  }
  fmt::print("{}\n", status.complete() ? "complete" : "incomplete");
  return status.complete() ? 0 : 3;
}

}  // namespace causticbench
