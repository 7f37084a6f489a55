// summarize_study (reports/summary_model.h): each experiment folder loaded and compared by the report's
// own stages, then, across them, the best run per scene and frame budget, each method's wins and
// failures, and its cost ranges. The per-budget winner is the best entry of the equal-time view's row
// (reports/cost_views.h); nothing here redefines a front, a view or a claim.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>

#include "core/errors.h"
#include "reports/summary_model.h"

namespace causticbench::report_detail {

namespace {

// The experiment's name, or its folder when another folder of the study holds an experiment of the
// same name (two results folders compared); with " @variant" when it has several.
std::string scene_title(const StudySummary& summary, const Report& report, size_t variant) {
  size_t same = std::count_if(summary.experiments.begin(), summary.experiments.end(),
                              [&](const Report& other) { return other.name == report.name; });
  std::string base = same > 1 ? report.folder.string() : report.name;
  return report.multi() ? base + " @" + report.variants[variant].name : base;
}

void widen(std::optional<double>& low, std::optional<double>& high, std::optional<double> value) {
  if (!finite(value)) return;
  if (!low || *value < *low) low = value;
  if (!high || *value > *high) high = value;
}

// The best answer of an equal-time row (ties: the faster, as the view itself breaks them).
std::optional<size_t> row_winner(const Report& report, const VariantViews& views, const EqualTimeRow& row) {
  std::optional<size_t> best;
  for (const BudgetAnswer& answer : row.methods) {
    if (!answer.best) continue;
    const CostPoint& point = views.points[*answer.best];
    if (!best) {
      best = answer.best;
      continue;
    }
    const CostPoint& current = views.points[*best];
    if (quantity_better(report.primary, point.error, current.error) ||
        (!quantity_better(report.primary, current.error, point.error) && point.frame_ms < current.frame_ms))
      best = answer.best;
  }
  return best;
}

}  // namespace

bool beats_black_by_margin(const std::string& metric, double value, double black) {
  if (!std::isfinite(value)) return false;
  const std::optional<QuantityInfo> info = find_quantity(metric);
  if (info && info->target)
    return std::fabs(value - *info->target) <= (1.0 - kBaselineMargin) * std::fabs(black - *info->target);
  const double margin = kBaselineMargin * std::fabs(black);
  if (info && info->direction == QuantityDirection::higher) return value >= black + margin;
  return value <= black - margin;
}

namespace {

std::optional<size_t> fastest_point(const VariantViews& views) {
  std::optional<size_t> fastest;
  for (size_t p = 0; p < views.points.size(); ++p)
    if (!fastest || views.points[p].frame_ms < views.points[*fastest].frame_ms) fastest = p;
  return fastest;
}

// Where the method's light went in the scene (experiments/light_account.h): the share of the scene's light
// it declares it does not model, when beyond the tolerance (said once), and each run whose account is
// flagged: a bad score its declarations and lost flux do not explain.
void add_account_failures(const Report& report, const SummaryScene& scene, size_t scene_index, MethodStanding& standing) {
  std::optional<LightAccount> declared;
  std::vector<std::string> unexplained;
  size_t accounted = 0;
  for (size_t i : report.ok_runs()) {
    const Run& run = report.runs[i];
    if (run.method != standing.method || run.variant_index != scene.variant) continue;
    const std::optional<LightAccount>& account = run.light_account;
    if (!account) continue;
    ++accounted;
    if (!declared) declared = account;  // the model share is the method's and the scene's, not the run's
    if (account->flagged)
      unexplained.push_back(fmt::format("{}: {:.2f} {}", run.name(), std::abs(account->unexplained),
                                        account->unexplained > 0.0 ? "missing" : "in excess"));
  }
  if (declared && declared->model > kUnexplainedLightTolerance)
    standing.failures.push_back({scene_index, "not modelled",
                                 fmt::format("declares it does not model {:.1f} % of the scene's caustic in view ({})",
                                             100.0 * declared->model, unmodelled_text(*declared))});
  if (!unexplained.empty())
    standing.failures.push_back({scene_index, "light unexplained",
                                 fmt::format("{} of {} runs: {}", unexplained.size(), accounted, join(unexplained, "; "))});
}

// Failed runs of the method in the scene, and whether its best error is the worst of the methods there.
void add_failures(const StudySummary& summary, size_t scene_index, MethodStanding& standing) {
  const SummaryScene& scene = summary.scenes[scene_index];
  const Report& report = summary.report(scene);
  size_t runs = 0, failed = 0;
  std::vector<std::string> errors;
  for (const Run& run : report.runs) {
    if (run.method != standing.method || run.variant_index != scene.variant || run.stale) continue;
    ++runs;
    if (run.ok) continue;
    ++failed;
    if (errors.size() < 2 && std::find(errors.begin(), errors.end(), run.error) == errors.end())
      errors.push_back(run.error);
  }
  if (failed) {
    standing.failures.push_back({scene_index, failed == runs ? "refused" : "failed",
                                 fmt::format("{} of {} runs failed: {}", failed, runs, join(errors, "; "))});
  }
  add_account_failures(report, scene, scene_index, standing);
  // Worst error: the method's best is worse than every other measured method's best.
  const VariantViews& views = summary.views(scene);
  std::map<std::string, size_t> best_of;  // method -> its best point (over its entries)
  for (size_t p = 0; p < views.points.size(); ++p) {
    const CostPoint& point = views.points[p];
    auto found = best_of.find(point.of_method);
    if (found == best_of.end() || quantity_better(report.primary, point.error, views.points[found->second].error))
      best_of[point.of_method] = p;
  }
  auto own = best_of.find(standing.method);
  if (best_of.size() < 2 || own == best_of.end()) return;
  const double mine = views.points[own->second].error;
  std::optional<size_t> best_other;
  for (const auto& [method, p] : best_of) {
    if (method == standing.method) continue;
    if (!quantity_better(report.primary, views.points[p].error, mine)) return;  // someone is no better
    if (!best_other || quantity_better(report.primary, views.points[p].error, views.points[*best_other].error))
      best_other = p;
  }
  const CostPoint& other = views.points[*best_other];
  standing.failures.push_back(
      {scene_index, "worst error",
       fmt::format("its best {} {} ({}) is the worst of {} methods; best: {} {} {}", report.primary, num(mine),
                   report.runs[views.runs[own->second]].name(), best_of.size(),
                   report.runs[views.runs[*best_other]].name(), report.primary, num(other.error))});
}

MethodCost method_cost(const StudySummary& summary, size_t scene_index, const std::string& method) {
  const SummaryScene& scene = summary.scenes[scene_index];
  const Report& report = summary.report(scene);
  MethodCost cost;
  cost.scene = scene_index;
  for (size_t i : report.ok_runs()) {
    const Run& run = report.runs[i];
    if (run.method != method || run.variant_index != scene.variant) continue;
    ++cost.runs;
    widen(cost.prepare_min, cost.prepare_max, run.quantity("prepare_seconds"));
    widen(cost.memory_min, cost.memory_max, run.quantity("memory_bytes"));
    widen(cost.frame_min, cost.frame_max, run.frame_ms());
    auto error = run.metric(report.primary);
    if (finite(error) && (!cost.best_error || quantity_better(report.primary, *error, *cost.best_error)))
      cost.best_error = error;
  }
  return cost;
}

}  // namespace

StudySummary summarize_study(const std::vector<std::string>& folders) {
  if (folders.empty()) throw InputError("summarize: expected at least one experiment results folder, found none");
  StudySummary summary;
  std::set<std::string> seen;
  for (const std::string& folder : folders) {
    std::error_code error;
    fs::path canonical = fs::weakly_canonical(folder, error);
    if (!seen.insert(error ? folder : canonical.string()).second)
      throw InputError(fmt::format("{}: named twice; expected each experiment folder once", folder));
    Report report;
    load_report(report, folder);
    score_variant_baselines(report);
    compute_fronts(report);
    compute_views(report);
    evaluate_claims(report);
    summary.experiments.push_back(std::move(report));
  }

  for (size_t e = 0; e < summary.experiments.size(); ++e) {
    const Report& report = summary.experiments[e];
    for (const std::string& method : report.methods)
      if (std::find(summary.methods.begin(), summary.methods.end(), method) == summary.methods.end())
        summary.methods.push_back(method);
    // A capability matrix's variants are cases, each made for one capability, not scenes a user picks a
    // method for: their best per budget would only mislead. The summary shows its matrix instead.
    if (member(report.experiment, "capability_matrix").is_object()) continue;
    for (size_t v = 0; v < report.variants.size(); ++v) {
      bool any = std::any_of(report.runs.begin(), report.runs.end(),
                             [&](const Run& run) { return run.variant_index == v && !run.stale; });
      if (!any) continue;
      summary.scenes.push_back({e, v, scene_title(summary, report, v), string_member(report.experiment, "scene")});
    }
  }

  for (size_t s = 0; s < summary.scenes.size(); ++s) {
    const SummaryScene& scene = summary.scenes[s];
    const Report& report = summary.report(scene);
    const VariantViews& views = summary.views(scene);
    for (const EqualTimeRow& row : views.equal_time) {
      BudgetWinner winner{s, row.budget_ms, row_winner(report, views, row), std::nullopt};
      if (!winner.point) winner.fastest = fastest_point(views);
      winner.black = report.variants[scene.variant].black(report.primary);
      if (winner.point && winner.black)
        winner.beats_black = beats_black_by_margin(report.primary, views.points[*winner.point].error, *winner.black);
      if (winner.point)
        for (const BudgetAnswer& answer : row.methods)
          if (answer.best && *answer.best != *winner.point &&
              !separated(report.runs[views.runs[*answer.best]], report.runs[views.runs[*winner.point]], report.primary))
            winner.not_separated.push_back(answer.method);
      summary.winners.push_back(winner);
    }
  }

  for (const std::string& method : summary.methods) {
    MethodStanding standing;
    standing.method = method;
    for (size_t w = 0; w < summary.winners.size(); ++w) {
      const BudgetWinner& winner = summary.winners[w];
      if (winner.point && winner.beats_black &&
          summary.views(summary.scenes[winner.scene]).points[*winner.point].of_method == method)
        standing.wins.push_back(w);
    }
    for (size_t s = 0; s < summary.scenes.size(); ++s) {
      const Report& report = summary.report(summary.scenes[s]);
      if (std::find(report.methods.begin(), report.methods.end(), method) == report.methods.end()) continue;
      add_failures(summary, s, standing);
      MethodCost cost = method_cost(summary, s, method);
      if (cost.runs) standing.costs.push_back(cost);
    }
    summary.standings.push_back(std::move(standing));
  }
  return summary;
}

}  // namespace causticbench::report_detail
