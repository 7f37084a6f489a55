// write_summary (reports/summary.h): the study's summary from the stored results of several
// experiments — read and compare them all (summary_model.cpp), then write summary.json (here, for
// scripts and tests), summary.md and summary.html (summary_documents.cpp).
#include "reports/summary.h"

#include <fmt/format.h>

#include "core/errors.h"
#include "core/files.h"
#include "reports/capability_matrix.h"
#include "reports/summary_model.h"

namespace causticbench {

using namespace report_detail;

namespace report_detail {

namespace {

json optional_number(std::optional<double> value) { return finite(value) ? json(*value) : json(nullptr); }

json point_json(const StudySummary& summary, const SummaryScene& scene, size_t point) {
  const Report& report = summary.report(scene);
  const VariantViews& views = summary.views(scene);
  const CostPoint& p = views.points[point];
  const Run& run = report.runs[views.runs[point]];
  return {{"method", p.of_method}, {"entry", p.method},  {"run", run.key},
          {"label", report.display(views.runs[point])}, {"name", run.name()},
          {"knobs", run.changed}, {"swept", run.swept()}, {"error", p.error}, {"frame_ms", p.frame_ms},
          {"prepare_seconds", p.prepare_seconds}};
}

}  // namespace

json summary_json(const StudySummary& summary) {
  json scenes = json::array();
  for (size_t s = 0; s < summary.scenes.size(); ++s) {
    const SummaryScene& scene = summary.scenes[s];
    const Report& report = summary.report(scene);
    json budgets = json::array();
    for (const BudgetWinner& winner : summary.winners) {
      if (winner.scene != s) continue;
      json entry = {{"budget_ms", winner.budget_ms}, {"best", nullptr}};
      if (winner.point) entry["best"] = point_json(summary, scene, *winner.point);
      else entry["none_reached"] = winner.fastest ? json(point_json(summary, scene, *winner.fastest)) : json(nullptr);
      entry["black"] = winner.black ? json(*winner.black) : json(nullptr);
      entry["beats_black"] = winner.beats_black;
      budgets.push_back(entry);
    }
    json breaks = json::array();
    const VariantViews& views = summary.views(scene);
    for (const BreakEven& entry : views.break_even)
      breaks.push_back({{"precomputing", point_json(summary, scene, entry.precomputing)},
                        {"competitor", point_json(summary, scene, entry.competitor)},
                        {"frames", entry.frames}});
    scenes.push_back({{"title", scene.title},
                      {"experiment", report.name},
                      {"variant", report.variants[scene.variant].name},
                      {"scene", scene.scene},
                      {"primary_metric", report.primary},
                      {"direction", direction_text(report.primary)},
                      {"budgets", budgets},
                      {"break_even", breaks}});
  }
  json methods = json::array();
  for (const MethodStanding& standing : summary.standings) {
    json wins = json::array(), failures = json::array(), costs = json::array();
    for (size_t w : standing.wins) {
      const BudgetWinner& winner = summary.winners[w];
      wins.push_back({{"scene", summary.scenes[winner.scene].title}, {"budget_ms", winner.budget_ms}});
    }
    for (const MethodFailure& failure : standing.failures)
      failures.push_back({{"scene", summary.scenes[failure.scene].title}, {"kind", failure.kind}, {"text", failure.text}});
    for (const MethodCost& cost : standing.costs)
      costs.push_back({{"scene", summary.scenes[cost.scene].title},
                       {"runs", cost.runs},
                       {"prepare_seconds", {optional_number(cost.prepare_min), optional_number(cost.prepare_max)}},
                       {"memory_bytes", {optional_number(cost.memory_min), optional_number(cost.memory_max)}},
                       {"frame_ms", {optional_number(cost.frame_min), optional_number(cost.frame_max)}},
                       {"best_error", optional_number(cost.best_error)}});
    methods.push_back({{"method", standing.method}, {"wins", wins}, {"failures", failures}, {"costs", costs}});
  }
  json experiments = json::array();
  for (const Report& report : summary.experiments) {
    json claims = json::array();
    for (const ClaimResult& result : report.claims) claims.push_back(claim_json(report, result));
    experiments.push_back({{"name", report.name},
                           {"folder", report.folder.string()},
                           {"primary_metric", report.primary},
                           {"runs", report.runs.size()},
                           {"failed", report.failed_count()},
                           {"not_run", report.missing.size()},
                           {"claims", claims}});
    if (std::optional<CapabilityMatrix> matrix = report_capability_matrix(report))
      experiments.back()["capability_matrix"] = capability_matrix_json(*matrix);
  }
  return {{"experiments", experiments}, {"scenes", scenes}, {"methods", methods}};
}

}  // namespace report_detail

SummaryFiles write_summary(const std::vector<std::string>& experiment_folders, const std::string& out_folder) {
  StudySummary summary = summarize_study(experiment_folders);
  SummaryFiles files;
  files.experiments = summary.experiments.size();
  files.scenes = summary.scenes.size();
  for (const Report& report : summary.experiments)
    for (const ClaimResult& result : report.claims) files.claims.add(result.verdict);
  for (size_t s = 0; s < summary.scenes.size(); ++s) {
    std::vector<std::string> parts;
    for (const BudgetWinner& winner : summary.winners) {
      if (winner.scene != s) continue;
      std::string best = !winner.point        ? "none"
                         : !winner.beats_black ? "none beats black"
                                               : summary.views(summary.scenes[s]).points[*winner.point].method;
      parts.push_back(budget_text(winner.budget_ms) + " " + best);
    }
    files.headlines.push_back(fmt::format("{} ({}): {}", summary.scenes[s].title,
                                          summary.report(summary.scenes[s]).primary, join(parts, ", ")));
  }
  const fs::path out(out_folder);
  ensure_folder(out.string());
  summary.out_folder = out;
  files.json = (out / "summary.json").string();
  files.markdown = (out / "summary.md").string();
  files.html = (out / "summary.html").string();
  write_text_atomically(files.json, summary_json(summary).dump(2) + "\n");
  write_text_atomically(files.markdown, summary_markdown(summary));
  write_text_atomically(files.html, summary_html(summary));
  return files;
}

}  // namespace causticbench
