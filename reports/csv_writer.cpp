// results.csv: one row per run with a record (ok and failed), numbers in full precision, for
// spreadsheets and scripts (the columns: docs/reports.md, "Outputs").
#include <algorithm>
#include <cmath>

#include "core/errors.h"
#include "reports/report_parts.h"

namespace causticbench::report_detail {

namespace {

std::string csv_cell(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

// Full precision, shortest round-trip form (nlohmann's number output); empty for null and NaN.
std::string csv_value(const json& value) {
  if (value.is_null()) return "";
  if (value.is_number_float() && !std::isfinite(value.get<double>())) return "";
  if (value.is_string()) return csv_cell(value.get<std::string>());
  return csv_cell(value.dump());
}

}  // namespace

std::string results_csv(const Report& report) {
  // Columns: identity, flattened knobs, metrics, timings, sizes, counters (unions over runs).
  std::vector<std::string> build, frame, render, metrics = report.metrics, timings, counters;
  auto collect = [&](const json& object, std::vector<std::string>& names) {
    if (!object.is_object()) return;
    for (const auto& [name, value] : object.items())
      if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  };
  for (const auto& column : kTimingColumns) timings.push_back(column[0]);
  for (const char* name : {"frame_ms_min"}) timings.push_back(name);
  for (const Run& run : report.runs) {
    collect(member(run.record, "build"), build);
    collect(member(run.record, "frame"), frame);
    collect(member(run.record, "render"), render);
    collect(member(run.record, "metrics"), metrics);
    collect(member(run.record, "metrics_undefined"), metrics);
    collect(member(run.record, "timings"), timings);
    collect(member(run.record, "counters"), counters);
  }
  std::vector<std::string> header = {"key",   "status", "method",  "label",
                                     "error", "swept",  "variant", "receiver_pixels"};
  for (const auto& name : build) header.push_back("build." + name);
  for (const auto& name : frame) header.push_back("frame." + name);
  for (const auto& name : render) header.push_back("render." + name);
  for (const auto& name : metrics) header.push_back(name);
  header.push_back("metrics_undefined");
  for (const auto& name : timings) header.push_back(name);
  for (const char* name : {"prepare_seconds", "memory_bytes", "peak_rss_bytes"}) header.push_back(name);
  for (const auto& name : counters) header.push_back("counter." + name);
  header.push_back("pareto_front");

  std::string out;
  for (size_t c = 0; c < header.size(); ++c) out += (c ? "," : "") + csv_cell(header[c]);
  out += "\n";
  for (size_t i = 0; i < report.runs.size(); ++i) {
    const Run& run = report.runs[i];
    std::vector<std::string> swept;
    if (run.swept().is_object())
      for (const auto& [name, value] : run.swept().items()) swept.push_back(name);
    std::vector<std::string> cells = {csv_cell(run.key),
                                      csv_cell(run.status),
                                      csv_cell(run.method),
                                      csv_cell(run.label),
                                      csv_cell(run.error),
                                      csv_cell(join(swept, ";")),
                                      csv_value(member(run.record, "variant")),
                                      csv_value(run.receiver_pixels())};
    for (const auto& name : build) cells.push_back(csv_value(member(member(run.record, "build"), name)));
    for (const auto& name : frame) cells.push_back(csv_value(member(member(run.record, "frame"), name)));
    for (const auto& name : render) cells.push_back(csv_value(member(member(run.record, "render"), name)));
    std::vector<std::string> undefined;  // "name: reason" of the metrics without a value, as the tables show them
    for (const auto& name : metrics) {
      std::string why = run.undefined_reason(name);
      if (!why.empty()) undefined.push_back(name + ": " + why);
      cells.push_back(why.empty() ? csv_value(member(member(run.record, "metrics"), name)) : "");
    }
    cells.push_back(csv_cell(join(undefined, "; ")));
    for (const auto& name : timings) cells.push_back(csv_value(member(member(run.record, "timings"), name)));
    for (const char* name : {"prepare_seconds", "memory_bytes", "peak_rss_bytes"})
      cells.push_back(csv_value(member(run.record, name)));
    for (const auto& name : counters) cells.push_back(csv_value(member(member(run.record, "counters"), name)));
    cells.push_back(report.on_overall_front(i) ? "overall" : (report.on_front(i) ? "method" : ""));
    out += join(cells, ",") + "\n";
  }
  return out;
}

}  // namespace causticbench::report_detail
