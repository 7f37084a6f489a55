// The tables that report.html and report.md both show, as cells with their marks (best of the
// column, a warning, why a value is undefined): the results of the ok runs, the failed runs, and the
// paper's numbers beside ours. The writers only lay the cells out.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "reports/report_parts.h"

namespace causticbench::report_detail {

namespace {

// The cell of a metric value: the number, or no value with the reason it is undefined.
// In an experiment with several seeds, the mean and its 95 % half-width (a deterministic run's is 0).
Cell metric_cell(const Run& run, const std::string& metric, bool seeded = false) {
  auto value = run.metric(metric);
  if (value) {
    const std::optional<MetricInterval> interval = run.interval(metric);
    if (seeded && interval) return {num(*value) + " \u00b1 " + num(interval->half_width), false, true};
    return {num(*value), false, true};
  }
  std::string why = run.undefined_reason(metric);
  return {why.empty() ? "\u2014" : "", false, true, false, why};
}

// Two knob values are the same: equal, or numbers within a relative 1e-9.
bool same_value(const json& a, const json& b) {
  if (a.is_number() && b.is_number()) {
    double x = a.get<double>(), y = b.get<double>();
    return x == y || std::abs(x - y) <= 1e-9 * std::max(std::abs(x), std::abs(y));
  }
  return a == b;
}

// The run is one of the paper row's: its method, and its knobs hold every value of the row's "match".
bool matches(const Run& run, const json& row) {
  if (run.method != string_member(row, "method")) return false;
  const json& match = member(row, "match");
  if (!match.is_object()) return true;
  json knobs = run_knobs(run);  // a knob is either a build or a render knob, never both
  for (const auto& [name, wanted] : match.items()) {
    const json& found = member(knobs, name);
    if (found.is_null() || !same_value(found, name == "variant" ? json(value_text(wanted)) : wanted)) return false;
  }
  return true;
}

// "Ours" beside a paper value: `value`, else "not run" without a run, an undefined metric's empty cell with
// its reason, or "\u2014".
Cell ours_cell(const Run* run, const std::string& column, const std::optional<double>& value) {
  if (value) return {num(*value), false, true};
  if (!run) return {"not run", false, true};
  if (run->ok && !run->undefined_reason(column).empty()) return metric_cell(*run, column);
  return {"\u2014", false, true};
}

}  // namespace

Table results_table(const Report& report) {
  Table table;
  table.header = {"method", "label", "knobs"};
  table.header_notes = {"", "the entry's label and the values its sweep set",
                        "every knob whose value differs from the method's declared default, fixed or swept"};
  if (report.multi()) {
    table.header.insert(table.header.end(), {"variant", "receiver pixels"});
    table.header_notes.insert(table.header_notes.end(),
                              {"the scene variant (experiment.json \"variants\"); the run is compared with its "
                               "reference, and best values and fronts are per variant",
                               "receiver pixels of the G-buffer in the run's first frame"});
  }
  for (const std::string& metric : report.metrics) {
    table.header.push_back(metric + " " + direction_arrow(metric));
    const MetricInfo* info = metric_info(metric);
    table.header_notes.push_back(direction_text(metric) + (info ? ": " + info->definition : ""));
  }
  table.header.push_back("lost flux");
  table.header_notes.push_back(fmt::format(
      "the largest fraction over the frames of the caustic flux the run's configuration cannot represent, counted by "
      "the method (docs/metrics.md, Lost flux); marked above {:.0f} %: its error is explained there",
      100.0 * kLostFluxWarning));
  for (const auto& column : kTimingColumns) {
    table.header.push_back(column[1]);
    table.header_notes.push_back(std::string("timings.") + column[0]);
  }
  for (const char* name : {"prepare s", "memory", "peak RSS"}) {
    table.header.push_back(name);
    table.header_notes.push_back("");
  }

  std::vector<size_t> rows;
  for (const std::string& method : report.methods)
    for (size_t i : report.ok_runs())
      if (report.runs[i].method == method) rows.push_back(i);

  // The best value of each metric column (ties all marked), and the fastest frame, within each variant;
  // with intervals, the run that holds the best value, which the others are told apart from.
  std::vector<std::map<std::string, double>> bests(report.variants.size());
  std::vector<std::map<std::string, size_t>> best_runs(report.variants.size());
  for (const std::string& metric : report.metrics) {
    for (size_t i : rows) {
      auto value = report.runs[i].metric(metric);
      if (!finite(value)) continue;
      std::map<std::string, double>& best = bests[report.runs[i].variant_index];
      if (!best.count(metric) || quantity_better(metric, *value, best[metric])) {
        best[metric] = *value;
        best_runs[report.runs[i].variant_index][metric] = i;
      }
    }
  }
  std::vector<std::optional<double>> fastests(report.variants.size());
  for (size_t i : rows) {
    auto time = report.runs[i].frame_ms();
    std::optional<double>& fastest = fastests[report.runs[i].variant_index];
    if (finite(time) && (!fastest || *time < *fastest)) fastest = *time;
  }

  for (size_t i : rows) {
    const Run& run = report.runs[i];
    std::map<std::string, double>& best = bests[run.variant_index];
    const std::optional<double>& fastest = fastests[run.variant_index];
    std::vector<Cell> row;
    std::string label = run.label;
    if (report.on_overall_front(i)) label += " \u25c6";
    if (run.empty_reference) label += " (empty reference)";
    const LostFlux* lost = run.record.lost_flux ? &run.record.lost_flux->worst : nullptr;
    const bool loses = lost && lost->fraction > kLostFluxWarning;
    if (loses) label += fmt::format(" (loses {:.0f} % of the caustic: {})", 100.0 * lost->fraction, lost->knob);
    const std::optional<LightAccount>& account = run.light_account;
    if (account && account->flagged)
      label += fmt::format(" ({:.0f} % of the light unexplained{})", 100.0 * std::abs(account->unexplained),
                           account->unexplained < 0.0 ? ", in excess" : "");
    const bool black_is_as_good = no_better_than_black(report, run);
    if (black_is_as_good) label += " (no better than a black image)";
    row.push_back({run.method});
    row.push_back({label});
    row.push_back({run.changed_text()});
    if (report.multi()) {
      row.push_back({run.variant});
      const std::optional<int64_t>& pixels = run.record.receiver_pixels;
      row.push_back({pixels ? std::to_string(*pixels) : "\u2014", false, true});
    }
    for (const std::string& metric : report.metrics) {
      auto value = run.metric(metric);
      Cell cell = metric_cell(run, metric, report.seeds > 1);
      if (finite(value) && best.count(metric) && !quantity_better(metric, best[metric], *value)) cell.best = true;
      // Not the best mean, but its interval overlaps the best run's: not separated from it.
      if (finite(value) && !cell.best && best.count(metric) &&
          !separated(run, report.runs[best_runs[run.variant_index][metric]], metric))
        cell.text += " \u2248";
      if (metric == "nonfinite_pixels" && value && *value > 0) cell.warn = true;
      if (metric == report.primary && black_is_as_good) cell.warn = true;
      row.push_back(cell);
    }
    Cell lost_cell{lost ? fmt::format("{:.1f} %", 100.0 * lost->fraction) : "\u2014", false, true, loses};
    row.push_back(lost_cell);
    for (const auto& column : kTimingColumns) {
      auto value = run.timing(column[0]);
      Cell cell{value ? num(*value) : "\u2014", false, true};
      if (std::string(column[0]) == "frame_ms_median" && finite(value) && fastest && *value <= *fastest)
        cell.best = true;
      row.push_back(cell);
    }
    auto prepare = run.quantity("prepare_seconds");
    row.push_back({prepare ? num(*prepare) : "\u2014", false, true});
    auto memory = run.quantity("memory_bytes");
    row.push_back({memory ? bytes_text(*memory) : "\u2014", false, true});
    auto rss = run.quantity("peak_rss_bytes");
    row.push_back({rss ? bytes_text(*rss) : "\u2014", false, true});
    table.rows.push_back(row);
  }
  // The baselines of each variant (metrics/baselines.h), scored like a run: what showing nothing, or the
  // reference's caustic blurred, would score. The columns past the metrics do not apply to them.
  for (const Variant& variant : report.variants) {
    for (const BaselineScores& scores : variant.baselines) {
      std::vector<Cell> row = {{"baseline"}, {scores.name}, {scores.detail}};
      if (report.multi()) row.insert(row.end(), {Cell{variant.name}, Cell{"\u2014", false, true}});
      for (const std::string& metric : report.metrics) {
        auto value = scores.values.find(metric);
        Cell cell{value != scores.values.end() ? num(value->second) : "\u2014", false, true};
        if (value == scores.values.end() && scores.undefined.count(metric)) cell.undefined = scores.undefined.at(metric);
        row.push_back(cell);
      }
      while (row.size() < table.header.size()) row.push_back({"\u2014", false, true});
      table.rows.push_back(row);
    }
  }
  return table;
}

Table failed_table(const Report& report) {
  Table table;
  table.header = {"method", "label", "knobs", "status", "error"};
  if (report.multi()) table.header.insert(table.header.begin() + 3, "variant");
  table.header_notes.assign(table.header.size(), "");
  for (const Run& run : report.runs) {
    if (run.ok) continue;
    std::vector<Cell> row = {
        {run.method}, {run.label}, {run.changed_text()}, {run.status}, {run.error, false, false, true}};
    if (report.multi()) row.insert(row.begin() + 3, Cell{run.variant});
    table.rows.push_back(row);
  }
  return table;
}


Table paper_table(const Report& report) {
  Table table;
  const json& paper = member(report.experiment, "paper");
  std::vector<std::string> columns;
  for (const json& column : member(paper, "columns"))
    if (column.is_string()) columns.push_back(column.get<std::string>());
  table.header = {"method", "match", "our run"};
  for (const std::string& column : columns) {
    table.header.push_back(column + " (paper)");
    table.header.push_back(column + " (ours)");
    table.header.push_back("ours / paper");
  }
  table.header.push_back("note");
  table.header_notes.assign(table.header.size(), "");
  for (const json& row : member(paper, "rows")) {
    std::vector<size_t> found;
    for (size_t i = 0; i < report.runs.size(); ++i)
      if (matches(report.runs[i], row)) found.push_back(i);
    if (found.empty()) found.push_back(report.runs.size());
    for (size_t index : found) {
      const Run* run = index < report.runs.size() ? &report.runs[index] : nullptr;
      std::vector<Cell> cells = {{string_member(row, "method")}, {knobs_text(member(row, "match"))}};
      if (!run)
        cells.push_back({"not run", false, false, true});
      else if (!run->ok)
        cells.push_back({report.display(index) + " (failed: " + run->error + ")", false, false, true});
      else
        cells.push_back({report.display(index)});
      for (const std::string& column : columns) {
        const json& paper_value = member(member(row, "values"), column);
        cells.push_back(
            {paper_value.is_number() ? num(paper_value.get<double>()) : value_text(paper_value), false, true});
        std::optional<double> value = run && run->ok ? run->quantity(column) : std::nullopt;
        cells.push_back(ours_cell(run, column, value));
        if (value && paper_value.is_number() && paper_value.get<double>() != 0.0)
          cells.push_back({"\u00d7" + fmt::format("{:.3g}", *value / paper_value.get<double>()), false, true});
        else
          cells.push_back({"\u2014", false, true});
      }
      cells.push_back({string_member(row, "note")});
      table.rows.push_back(cells);
    }
  }
  return table;
}

std::vector<std::string> undefined_notes(const Table& table) {
  std::vector<std::string> notes;
  for (const auto& row : table.rows)
    for (const Cell& cell : row)
      if (!cell.undefined.empty() && std::find(notes.begin(), notes.end(), cell.undefined) == notes.end())
        notes.push_back(cell.undefined);
  return notes;
}

size_t note_number(const std::vector<std::string>& notes, const std::string& note) {
  return static_cast<size_t>(std::find(notes.begin(), notes.end(), note) - notes.begin()) + 1;
}

}  // namespace causticbench::report_detail
