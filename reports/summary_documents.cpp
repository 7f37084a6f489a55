// summary.md and summary.html (reports/summary.h): the study's tables, built once as Tables and laid out
// by the report's own table writers, so that both documents say the same. summary.html is one offline
// page with the report's style sheet embedded (no script, no plot).
#include <fmt/format.h>

#include "core/errors.h"
#include "reports/capability_matrix.h"
#include "reports/summary_model.h"
#include "templates/report.css.h"

namespace causticbench::report_detail {

namespace {

std::string range_text(std::optional<double> low, std::optional<double> high, bool bytes = false) {
  if (!low) return "\u2014";
  auto text = [&](double value) { return bytes ? bytes_text(value) : num(value); };
  return *low == *high ? text(*low) : text(*low) + " \u2013 " + text(*high);
}

std::string point_text(const StudySummary& summary, const SummaryScene& scene, size_t point) {
  const Report& report = summary.report(scene);
  const VariantViews& views = summary.views(scene);
  const CostPoint& p = views.points[point];
  return fmt::format("{} {} {} \u00b7 {} ms \u00b7 {}", p.method, report.primary, num(p.error), num(p.frame_ms),
                     knobs_of(report.runs[views.runs[point]]));
}

std::string winner_text(const StudySummary& summary, const BudgetWinner& winner) {
  const SummaryScene& scene = summary.scenes[winner.scene];
  if (winner.point && !winner.beats_black)
    return fmt::format("no winner: the best, {}, is not {:.0f} % better than a black image ({} {})",
                       point_text(summary, scene, *winner.point), 100.0 * kBaselineMargin,
                       summary.report(scene).primary, num(*winner.black));
  if (winner.point)
    return point_text(summary, scene, *winner.point) +
           (winner.not_separated.empty()
                ? ""
                : "; not separated from " + join(winner.not_separated, ", ") + " (95 % intervals overlap)");
  if (winner.fastest) {
    const CostPoint& fastest = summary.views(scene).points[*winner.fastest];
    return fmt::format("none reached (fastest: {} {} ms)", fastest.method, num(fastest.frame_ms));
  }
  return "none reached (no measured run)";
}

Table budgets_table(const StudySummary& summary) {
  Table table;
  table.header = {"scene", "metric", "frame budget", "best method", "within the budget"};
  table.header_notes = {"experiment (@ variant)", "the experiment's primary metric and its direction",
                        "median frame time (update + render) at most this", "", "the best run: error, frame time, knobs"};
  for (const BudgetWinner& winner : summary.winners) {
    const SummaryScene& scene = summary.scenes[winner.scene];
    const Report& report = summary.report(scene);
    std::string method = !winner.point        ? std::string("none reached")
                         : !winner.beats_black ? std::string("none beats black")
                                               : summary.views(scene).points[*winner.point].method;
    table.rows.push_back({{scene.title},
                          {report.primary + " " + direction_arrow(report.primary)},
                          {budget_text(winner.budget_ms), false, true},
                          {method, winner.point.has_value() && winner.beats_black, false,
                           !winner.point || !winner.beats_black},
                          {winner_text(summary, winner)}});
    // The best run opens in its experiment's viewer, where the report wrote one.
    const fs::path viewer = report.folder / "viewer.html";
    if (winner.point && fs::exists(viewer) && !summary.out_folder.empty()) {
      const std::string key = report.runs[summary.views(scene).runs[*winner.point]].key;
      table.rows.back().back().link =
          fs::relative(viewer, summary.out_folder).generic_string() + "#run=" + key;
    }
  }
  return table;
}

Table standings_table(const StudySummary& summary) {
  Table table;
  table.header = {"method", "best at", "fails"};
  table.header_notes = {"", "scene @ frame budget where its run is the best of all methods",
                        "failed runs (refused: every run failed), the worst best-error of a scene's methods, the scene's light "
                        "it declares it does not model, or runs whose light its declarations and lost flux leave "
                        "unexplained"};
  for (const MethodStanding& standing : summary.standings) {
    std::vector<std::string> wins, fails;
    for (size_t w : standing.wins) {
      const BudgetWinner& winner = summary.winners[w];
      wins.push_back(summary.scenes[winner.scene].title + " \u2264 " + budget_text(winner.budget_ms));
    }
    for (const MethodFailure& failure : standing.failures)
      fails.push_back(fmt::format("{} ({}): {}", summary.scenes[failure.scene].title, failure.kind, failure.text));
    table.rows.push_back({{standing.method},
                          {wins.empty() ? "nowhere" : join(wins, "; ")},
                          {fails.empty() ? "nowhere" : join(fails, "; "), false, false, !fails.empty()}});
  }
  return table;
}

Table costs_table(const StudySummary& summary) {
  Table table;
  table.header = {"method", "scene", "runs", "prepare s", "memory", "frame ms", "best error"};
  table.header_notes = {"", "", "compared runs", "precomputation, paid once (range over the runs)",
                        "the method's own memory (range)", "median frame time (range)",
                        "the best primary metric of its runs"};
  for (const MethodStanding& standing : summary.standings) {
    for (const MethodCost& cost : standing.costs) {
      const SummaryScene& scene = summary.scenes[cost.scene];
      const std::string& primary = summary.report(scene).primary;
      table.rows.push_back({{standing.method},
                            {scene.title},
                            {std::to_string(cost.runs), false, true},
                            {range_text(cost.prepare_min, cost.prepare_max), false, true},
                            {range_text(cost.memory_min, cost.memory_max, true), false, true},
                            {range_text(cost.frame_min, cost.frame_max), false, true},
                            {cost.best_error ? primary + " " + num(*cost.best_error) : "\u2014", false, true}});
    }
  }
  return table;
}

Table claims_table(const StudySummary& summary) {
  Table table;
  table.header = {"experiment", "claim", "verdict", "evidence"};
  for (const Report& report : summary.experiments) {
    for (const ClaimResult& result : report.claims) {
      std::string text = string_member(result.claim, "text", result.claim.dump());
      table.rows.push_back({{report.name},
                            {text},
                            {verdict_name(result.verdict), result.verdict == Verdict::confirmed, false,
                             result.verdict == Verdict::refuted},
                            {claim_evidence(report, result, Format::plain)}});
    }
  }
  return table;
}

// Per scene with a break-even entry, the report's own break-even table.
template <typename Emit>
void break_even_sections(const StudySummary& summary, Emit emit) {
  for (const SummaryScene& scene : summary.scenes) {
    const Table table = break_even_table(summary.report(scene), scene.variant);
    if (!table.rows.empty()) emit(scene, table);
  }
}

std::string claims_total(const StudySummary& summary) {
  ClaimCounts counts;
  for (const Report& report : summary.experiments)
    for (const ClaimResult& result : report.claims) counts.add(result.verdict);
  return fmt::format("{} claims: {}.", counts.total, counts.breakdown());
}

const char* kIntroduction =
    "Per scene, the best method and knobs within each frame budget (the equal-time view of each experiment's "
    "report, over all its methods); per method, where it is best and where it fails; what each method costs; after "
    "how many frames a method that precomputes more overtakes one of equal or better error; and every claim with "
    "its verdict. Each experiment's numbers are those of its own report.";

std::string experiments_line(const StudySummary& summary) {
  std::vector<std::string> parts;
  for (const Report& report : summary.experiments)
    parts.push_back(fmt::format("{} ({} runs, {} failed, {} not run)", report.name, report.runs.size(),
                                report.failed_count(), report.missing.size()));
  return "Experiments: " + join(parts, "; ") + ".";
}

}  // namespace

std::string summary_markdown(const StudySummary& summary) {
  std::string out = "# causticbench study summary\n\n" + std::string(kIntroduction) + "\n\n";
  out += md_text(experiments_line(summary)) + "\n\n";
  out += "## Best method per frame budget\n\n";
  markdown_table(out, budgets_table(summary));
  out += "## Where each method wins and fails\n\n";
  markdown_table(out, standings_table(summary));
  out += "## Cost model\n\n";
  markdown_table(out, costs_table(summary));
  out += "## Break-even\n\n";
  bool any = false;
  break_even_sections(summary, [&](const SummaryScene& scene, const Table& table) {
    any = true;
    out += "### " + md_text(scene.title) + "\n\n";
    markdown_table(out, table);
  });
  if (!any) out += "No method that precomputes more overtakes another of equal or better error.\n\n";
  out += "## Claims\n\n" + md_text(claims_total(summary)) + "\n\n";
  markdown_table(out, claims_table(summary));
  for (const Report& report : summary.experiments)
    if (std::optional<CapabilityMatrix> matrix = report_capability_matrix(report))
      out += capability_matrix_markdown(*matrix, "Capability matrix: " + report.name);
  return out;
}

std::string summary_html(const StudySummary& summary) {
  std::string out = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n";
  out += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  out += "<title>causticbench study summary</title>\n<style>\n" + std::string(kReportStyle) + "</style>\n";
  out += "</head><body>\n<h1>causticbench study summary</h1>\n";
  out += "<p class=\"description\">" + html_escape(kIntroduction) + "</p>\n";
  out += "<nav><a href=\"#budgets\">best per budget</a><a href=\"#methods\">methods</a><a href=\"#costs\">cost "
         "model</a><a href=\"#break-even\">break-even</a><a href=\"#claims\">claims</a><a "
         "href=\"summary.md\">summary.md</a><a href=\"summary.json\">summary.json</a></nav>\n";
  out += "<p>" + html_escape(experiments_line(summary)) + "</p>\n";
  out += "<h2 id=\"budgets\">Best method per frame budget</h2>\n";
  html_table(out, budgets_table(summary));
  out += "<h2 id=\"methods\">Where each method wins and fails</h2>\n";
  html_table(out, standings_table(summary));
  out += "<h2 id=\"costs\">Cost model</h2>\n";
  html_table(out, costs_table(summary));
  out += "<h2 id=\"break-even\">Break-even</h2>\n";
  bool any = false;
  break_even_sections(summary, [&](const SummaryScene& scene, const Table& table) {
    any = true;
    out += "<h3>" + html_escape(scene.title) + "</h3>\n";
    html_table(out, table);
  });
  if (!any) out += "<p>No method that precomputes more overtakes another of equal or better error.</p>\n";
  out += "<h2 id=\"claims\">Claims</h2>\n<p>" + html_escape(claims_total(summary)) + "</p>\n";
  html_table(out, claims_table(summary));
  for (const Report& report : summary.experiments)
    if (std::optional<CapabilityMatrix> matrix = report_capability_matrix(report))
      out += capability_matrix_html(*matrix, "Capability matrix: " + report.name);
  out += "</body></html>\n";
  return out;
}

}  // namespace causticbench::report_detail
