// The equal-time, equal-error and break-even views of the report (docs/reports.md, "Equal time, equal
// error, break-even"): computed per scene variant from the compared runs by reports/cost_views.h, and
// laid out as tables and summary lines that the Markdown and HTML writers share.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/errors.h"
#include "reports/report_parts.h"

namespace causticbench::report_detail {

namespace {

ErrorBetter error_better(const Report& report) {
  QuantityInfo error = find_quantity(report.primary).value_or(QuantityInfo{});
  return [error](double a, double b) { return quantity_better(error, a, b); };
}

// The entries with any run in the variant (ok or not), in the report's order: the views' columns (two
// entries of one method are two). An entry whose runs all failed shows as "no run" rather than vanishing.
std::vector<std::string> variant_methods(const Report& report, size_t variant) {
  std::vector<std::string> entries;
  for (const std::string& entry : report.entries) {
    bool any = std::any_of(report.runs.begin(), report.runs.end(), [&](const Run& run) {
      return run.entry == entry && run.variant_index == variant;
    });
    if (any) entries.push_back(entry);
  }
  return entries;
}

std::string heading(const Report& report, size_t variant) {
  return report.multi() ? " (" + report.variants[variant].name + ")" : "";
}

}  // namespace

std::string knobs_of(const Run& run) { return run.changed_text(); }

std::string budget_text(double ms) { return ms >= 1000.0 ? num(ms / 1000.0) + " s" : num(ms) + " ms"; }

void compute_views(Report& report) {
  const ErrorBetter better = error_better(report);
  report.views.assign(report.variants.size(), VariantViews{});
  for (size_t v = 0; v < report.variants.size(); ++v) {
    VariantViews& views = report.views[v];
    for (size_t i : report.ok_runs()) {
      const Run& run = report.runs[i];
      auto time = run.frame_ms();
      auto error = run.metric(report.primary);
      if (run.variant_index != v || !finite(time) || !finite(error)) continue;
      views.runs.push_back(i);
      views.points.push_back({run.entry, *time, run.quantity("prepare_seconds").value_or(0.0), *error, run.method});
    }
    const std::vector<std::string> methods = variant_methods(report, v);
    views.targets = report.error_targets.empty() ? default_error_targets(views.points, better) : report.error_targets;
    views.equal_time = equal_time_view(views.points, methods, report.budgets_ms, better);
    views.equal_error = equal_error_view(views.points, methods, views.targets, better);
    views.break_even = break_even_view(views.points, methods, better);
  }
}

namespace {

// An error value, with its 95 % half-width in an experiment with several seeds.
std::string error_text(const Report& report, const Run& run, double error) {
  const std::optional<MetricInterval> interval = run.interval(report.primary);
  if (report.seeds > 1 && interval) return num(error) + " \u00b1 " + num(interval->half_width);
  return num(error);
}

}  // namespace

Table equal_time_table(const Report& report, size_t variant) {
  const VariantViews& views = report.views.at(variant);
  Table table;
  table.header = {"frame budget"};
  for (const std::string& method : variant_methods(report, variant)) table.header.push_back(method);
  table.header_notes.assign(table.header.size(), "");
  table.header_notes[0] = "median frame time (update + render) at most this";
  for (const EqualTimeRow& row : views.equal_time) {
    std::vector<Cell> cells = {{budget_text(row.budget_ms)}};
    std::optional<double> best;
    std::optional<size_t> best_run;
    for (const BudgetAnswer& answer : row.methods)
      if (answer.best && (!best || quantity_better(report.primary, views.points[*answer.best].error, *best))) {
        best = views.points[*answer.best].error;
        best_run = views.runs[*answer.best];
      }
    for (const BudgetAnswer& answer : row.methods) {
      if (answer.best) {
        const CostPoint& point = views.points[*answer.best];
        const Run& run = report.runs[views.runs[*answer.best]];
        Cell cell{fmt::format("{} {} \u00b7 {} ms \u00b7 {}", report.primary, error_text(report, run, point.error),
                              num(point.frame_ms), knobs_of(run))};
        cell.best = best && !quantity_better(report.primary, *best, point.error);
        // Not the best, but not told apart from it at 95 %.
        if (!cell.best && best_run && !separated(run, report.runs[*best_run], report.primary)) cell.text += " \u2248";
        cells.push_back(cell);
      } else if (answer.fastest) {
        cells.push_back({fmt::format("not reached (fastest {} ms)", num(views.points[*answer.fastest].frame_ms))});
      } else {
        cells.push_back({"no measured run"});
      }
    }
    table.rows.push_back(cells);
  }
  return table;
}

Table equal_error_table(const Report& report, size_t variant) {
  const VariantViews& views = report.views.at(variant);
  Table table;
  table.header = {fmt::format("{} target", report.primary)};
  for (const std::string& method : variant_methods(report, variant)) table.header.push_back(method);
  table.header_notes.assign(table.header.size(), "");
  table.header_notes[0] = "an error at least as good as this (" + direction_text(report.primary) + ")";
  for (const EqualErrorRow& row : views.equal_error) {
    std::vector<Cell> cells = {{num(row.target)}};
    std::optional<double> fastest;
    for (const TargetAnswer& answer : row.methods)
      if (answer.fastest && (!fastest || views.points[*answer.fastest].frame_ms < *fastest))
        fastest = views.points[*answer.fastest].frame_ms;
    for (const TargetAnswer& answer : row.methods) {
      if (answer.fastest) {
        const CostPoint& point = views.points[*answer.fastest];
        const Run& run = report.runs[views.runs[*answer.fastest]];
        Cell cell{fmt::format("{} ms \u00b7 {} {} \u00b7 {}", num(point.frame_ms), report.primary,
                              error_text(report, run, point.error), knobs_of(run))};
        cell.best = fastest && point.frame_ms <= *fastest;
        // Reached by the mean, but the target lies within the interval: not separated from it.
        const std::optional<MetricInterval> interval = run.interval(report.primary);
        if (interval && interval->half_width > 0.0 && interval->contains(row.target)) cell.text += " \u2248";
        cells.push_back(cell);
      } else if (answer.closest) {
        cells.push_back({fmt::format("not reached (best {} {})", report.primary,
                                     num(views.points[*answer.closest].error))});
      } else {
        cells.push_back({"no measured run"});
      }
    }
    table.rows.push_back(cells);
  }
  return table;
}

Table break_even_table(const Report& report, size_t variant) {
  const VariantViews& views = report.views.at(variant);
  Table table;
  table.header = {"precomputing run", "prepare s", "frame ms", report.primary, "overtakes",
                  "prepare s", "frame ms", report.primary, "after frames"};
  table.header_notes.assign(table.header.size(), "");
  table.header_notes[4] = "the other method's run that stays cheaper longest among those at least as accurate";
  table.header_notes[8] = "prepare + N x frame time is no larger from this frame count on";
  for (const BreakEven& entry : views.break_even) {
    const CostPoint& a = views.points[entry.precomputing];
    const CostPoint& b = views.points[entry.competitor];
    table.rows.push_back({{report.display(views.runs[entry.precomputing])},
                          {num(a.prepare_seconds), false, true},
                          {num(a.frame_ms), false, true},
                          {num(a.error), false, true},
                          {report.display(views.runs[entry.competitor])},
                          {num(b.prepare_seconds), false, true},
                          {num(b.frame_ms), false, true},
                          {num(b.error), false, true},
                          {entry.frames == 0.0 ? "from the first" : fmt::format("{:.0f}", entry.frames), true, true}});
  }
  return table;
}

bool has_views(const Report& report) {
  return std::any_of(report.views.begin(), report.views.end(), [](const VariantViews& v) { return !v.points.empty(); });
}

std::string views_caption(const Report& report) {
  return fmt::format(
      "Equal time: per frame budget, the best {0} each method reaches with a median frame time within it, and with "
      "which knobs. Equal error: per target, the least frame time at which each method reaches a {0} at least as "
      "good{1}. Break-even: after how many frames a run that precomputes more costs no more in total (prepare + N "
      "\u00d7 frame time) than every run of another entry that is at least as accurate. Marked: the best of the row.{2}",
      report.primary, report.error_targets.empty() ? " (targets: the best error each method reaches)" : "",
      report.seeds > 1 ? " Errors are means over the seeds \u00b1 their 95 % interval; \u2248: not separated (equal time: "
                         "its interval overlaps the row's best; equal error: the target lies within its interval)."
                       : "");
}

std::vector<std::string> budget_lines(const Report& report) {
  std::vector<std::string> lines;
  for (size_t v = 0; v < report.views.size(); ++v) {
    const VariantViews& views = report.views[v];
    if (views.points.empty()) continue;
    for (const EqualTimeRow& row : views.equal_time) {
      std::vector<const BudgetAnswer*> reached;
      std::vector<std::string> missed;
      for (const BudgetAnswer& answer : row.methods) {
        if (answer.best) reached.push_back(&answer);
        else if (answer.fastest)
          missed.push_back(fmt::format("{} not reached (fastest {} ms)", answer.method,
                                       num(views.points[*answer.fastest].frame_ms)));
      }
      std::stable_sort(reached.begin(), reached.end(), [&](const BudgetAnswer* a, const BudgetAnswer* b) {
        return quantity_better(report.primary, views.points[*a->best].error, views.points[*b->best].error);
      });
      std::vector<std::string> parts;
      for (const BudgetAnswer* answer : reached) {
        const CostPoint& point = views.points[*answer->best];
        parts.push_back(fmt::format("{} {} {} ({})", answer->method, report.primary, num(point.error),
                                    knobs_of(report.runs[views.runs[*answer->best]])));
      }
      parts.insert(parts.end(), missed.begin(), missed.end());
      if (reached.empty() && missed.empty()) continue;
      lines.push_back(fmt::format("Within {} a frame{}: {}{}.", budget_text(row.budget_ms), heading(report, v),
                                  reached.empty() ? "no method; " : "", join(parts, "; ")));
    }
  }
  return lines;
}

}  // namespace causticbench::report_detail
