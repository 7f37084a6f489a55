// The case table (experiment.json "case_table": true; docs/reports.md, "Case table"): every run of an
// extremes study as one row, case (scene variant) by method setting, with what happened there. The
// question it answers is not "which is best" but "does anything break": a run is finite, non-finite (a
// NaN or Inf pixel, which the runner stores as failed), stopped with the error it gave, or measured
// against a reference with no caustic in view. So, unlike the results table, failed runs are rows here,
// beside the energy ratio, the primary metric and the frame time of the runs that finished.
#include <fmt/format.h>

#include "core/errors.h"
#include "reports/report_parts.h"

namespace causticbench::report_detail {

namespace {

// The run's label without the " @<variant>" the runner appends: the method setting, the same in every
// case.
std::string setting_of(const Run& run) {
  std::string label = run.label;
  const std::string suffix = " @" + run.variant;
  if (label.size() >= suffix.size() && label.compare(label.size() - suffix.size(), suffix.size(), suffix) == 0)
    label.erase(label.size() - suffix.size());
  return label;
}

// The first sentence of an error message (a clear error says what was expected in its first sentence;
// the rest, often a path or a hint, stays in the failed-runs table).
std::string first_sentence(const std::string& text) {
  size_t end = text.find(". ");
  std::string sentence = end == std::string::npos ? text : text.substr(0, end + 1);
  return sentence.size() > 240 ? sentence.substr(0, 237) + "..." : sentence;
}

}  // namespace

bool has_case_table(const Report& report) {
  const json& flag = member(report.experiment, "case_table");
  return flag.is_boolean() && flag.get<bool>();
}

std::string case_outcome(const Run& run) {
  if (run.stale) return "stale";
  if (!run.ok) {
    const double nonfinite = run.record.metrics.count("nonfinite_pixels") ? run.record.metrics.at("nonfinite_pixels") : 0.0;
    return nonfinite > 0.0 || run.error.find("non-finite") != std::string::npos ? "non-finite" : "stopped";
  }
  return run.empty_reference ? "empty reference" : "finite";
}

std::vector<CaseRow> case_rows(const Report& report) {
  std::vector<CaseRow> rows;
  for (size_t v = 0; v < report.variants.size(); ++v) {
    for (size_t i = 0; i < report.runs.size(); ++i) {
      const Run& run = report.runs[i];
      if (run.variant_index != v) continue;
      CaseRow row;
      row.run = i;
      row.variant = report.variants[v].name;
      row.method = run.method;
      row.setting = setting_of(run);
      row.outcome = case_outcome(run);
      if (run.ok) {
        row.energy_ratio = run.metric("energy_ratio");
        row.primary = run.metric(report.primary);
        row.frame_ms = run.frame_ms();
        // From the record, not run.metric(): against an empty reference it is the one value that says
        // whether the run, too, gave nothing.
        row.max_error = run.record.metric("max_error");
      } else {
        row.message = row.outcome == "non-finite" ? run.error : first_sentence(run.error);
      }
      rows.push_back(row);
    }
  }
  return rows;
}

Table case_table(const Report& report) {
  Table table;
  table.header = {"case", "method", "setting", "outcome", "energy ratio", report.primary, "max error", "frame ms", "error"};
  table.header_notes = {"the scene variant (experiment.json \"variants\")",
                        "",
                        "the run's label without its case",
                        "finite; non-finite (a NaN or Inf pixel: stored as failed); stopped (the error it gave); "
                        "empty reference (its reference has no caustic in view: not scored)",
                        "E_c summed over the receivers, run over reference (1 is right)",
                        "the experiment's primary metric",
                        "max |run - reference| over the receivers, W/m^2 (the experiment must measure max_error); "
                        "against an empty reference, the brightest E_c the run gave where there is none",
                        "median over frames and repetitions",
                        "the first sentence of the error (the failed-runs table has all of it)"};
  auto value = [](const std::optional<double>& number) {
    return finite(number) ? Cell{num(*number), false, true} : Cell{""};
  };
  for (const CaseRow& row : case_rows(report)) {
    Cell outcome{row.outcome};
    outcome.warn = row.outcome == "non-finite" || row.outcome == "stale";
    table.rows.push_back({{row.variant}, {row.method}, {row.setting}, outcome, value(row.energy_ratio),
                          value(row.primary), value(row.max_error), value(row.frame_ms), {row.message, false, false, !row.message.empty()}});
  }
  return table;
}

std::string case_table_caption(const Report& report) {
  std::map<std::string, size_t> counts;
  const std::vector<CaseRow> rows = case_rows(report);
  for (const CaseRow& row : rows) ++counts[row.outcome];
  std::vector<std::string> parts;
  for (const char* outcome : {"finite", "empty reference", "stopped", "non-finite", "stale"})
    if (counts.count(outcome)) parts.push_back(fmt::format("{} {}", counts.at(outcome), outcome));
  std::string text = fmt::format("{} runs in {} cases: {}.", rows.size(), report.variants.size(), join(parts, ", "));
  if (!report.missing.empty()) text += fmt::format(" {} runs not run yet.", report.missing.size());
  text +=
      " The target is no non-finite run and no silent black image where a clear error belongs: a stopped run names "
      "what it cannot model, a finite run's energy ratio says whether it gave light where the reference has it.";
  return text;
}

json case_table_json(const Report& report) {
  json rows = json::array();
  for (const CaseRow& row : case_rows(report)) {
    auto optional = [](const std::optional<double>& value) { return finite(value) ? json(*value) : json(nullptr); };
    rows.push_back({{"case", row.variant},
                    {"method", row.method},
                    {"setting", row.setting},
                    {"key", report.runs[row.run].key},
                    {"outcome", row.outcome},
                    {"energy_ratio", optional(row.energy_ratio)},
                    {"primary_metric", optional(row.primary)},
                    {"max_error", optional(row.max_error)},
                    {"frame_ms", optional(row.frame_ms)},
                    {"error", row.message}});
  }
  return rows;
}

}  // namespace causticbench::report_detail
