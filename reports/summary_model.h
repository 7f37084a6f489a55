// The model of the study's summary (reports/summary.h): the experiments' reports, each loaded and
// compared by the report pipeline's own stages (load_report, compute_fronts, compute_views,
// evaluate_claims), and what the summary derives across them. summary_model.cpp fills it;
// summary_documents.cpp turns it into summary.md and summary.html, summary.cpp into summary.json.
// Internal to reports/.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "reports/report_model.h"
#include "reports/report_parts.h"

namespace causticbench::report_detail {

// One scene of the study: an experiment's variant (a plain experiment has one, "default").
struct SummaryScene {
  size_t experiment = 0, variant = 0;  // into StudySummary::experiments and that report's variants
  std::string title;                   // the experiment's name, with " @variant" when it has several
  std::string scene;                   // the scene file experiment.json names
};

// Per frame budget, the best run of any method within it (the equal-time view's row): its point in
// the scene's views, or none when no method reached the budget.
struct BudgetWinner {
  size_t scene = 0;
  double budget_ms = 0.0;
  std::optional<size_t> point;     // into the variant's VariantViews::points
  std::optional<size_t> fastest;   // none reached: the fastest point of all, to say by how much
  std::optional<double> black;     // the black image's primary metric in that scene (metrics/baselines.h)
  // The best run beats the black image by at least kBaselineMargin (or no black score is known): only
  // then does its method "win" the budget.
  bool beats_black = true;
  // With several seeds: the other methods whose best in the budget is not told apart from the winner's
  // (their 95 % intervals overlap).
  std::vector<std::string> not_separated;
};

// How much better than a black image a budget's best run must be on the primary metric to win it: a
// tenth of the black image's value (for relMSE 0.9 x black's or less; for PSNR 1.1 x or more).
inline constexpr double kBaselineMargin = 0.1;
// Whether `value` is better than `black` by kBaselineMargin of |black| in the metric's direction.
bool beats_black_by_margin(const std::string& metric, double value, double black);

// Where a method fails in one scene: failed runs (a scene it refuses fails every run before any work),
// the worst best-error of the methods measured there, or its light account (experiments/light_account.h):
// light it declares it does not model, or light that neither that nor its lost flux explains.
struct MethodFailure {
  size_t scene = 0;
  // "refused" (every run failed), "failed" (some runs failed), "worst error", "not modelled" (the scene's
  // light in classes it declares it lacks, beyond kUnexplainedLightTolerance), "light unexplained" (a run
  // flagged by its account)
  std::string kind;
  std::string text;   // the numbers or the error, plain text
};

// What a method costs in one scene, over its compared runs: ranges of each quantity.
struct MethodCost {
  size_t scene = 0;
  size_t runs = 0;
  std::optional<double> prepare_min, prepare_max, memory_min, memory_max, frame_min, frame_max, best_error;
};

struct MethodStanding {
  std::string method;
  std::vector<size_t> wins;  // into StudySummary::winners
  std::vector<MethodFailure> failures;
  std::vector<MethodCost> costs;
};

struct StudySummary {
  std::vector<Report> experiments;  // in the order given
  std::vector<SummaryScene> scenes;
  std::vector<BudgetWinner> winners;  // scene by scene, budgets in each experiment's order
  std::vector<std::string> methods;   // in order of first appearance across the experiments
  std::vector<MethodStanding> standings;  // one per method, same order
  fs::path out_folder;  // where the summary is written: its links into the experiments' viewers are relative

  const Report& report(const SummaryScene& scene) const { return experiments[scene.experiment]; }
  const VariantViews& views(const SummaryScene& scene) const { return report(scene).views[scene.variant]; }
};

// Loads and compares every folder (InputError: not an experiment folder, or named twice), then derives
// the winners, failures and costs.
StudySummary summarize_study(const std::vector<std::string>& folders);

std::string summary_markdown(const StudySummary& summary);  // summary_documents.cpp
std::string summary_html(const StudySummary& summary);      // summary_documents.cpp
json summary_json(const StudySummary& summary);             // summary.cpp

}  // namespace causticbench::report_detail
