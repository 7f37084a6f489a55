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
  // Columns: identity, flattened knobs, metrics, timings, sizes, counters (unions over runs), then where
  // the numbers come from.
  std::vector<std::string> build, frame, render, metrics = report.metrics, timings, counters;
  auto add = [](std::vector<std::string>& names, const std::string& name) {
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  };
  auto collect = [&](const json& object, std::vector<std::string>& names) {
    if (!object.is_object()) return;
    for (const auto& [name, value] : object.items()) add(names, name);
  };
  for (const auto& column : kTimingColumns) timings.push_back(column[0]);
  timings.push_back("frame_ms_min");
  for (const Run& run : report.runs) {
    collect(run.record.build, build);
    collect(run.record.frame, frame);
    collect(run.record.render, render);
    for (const auto& [name, value] : run.record.metrics) add(metrics, name);
    for (const auto& [name, why] : run.record.metrics_undefined) add(metrics, name);
    if (run.record.timings.gpu_render_ms_median) {
      add(timings, "gpu_render_ms_median");
      add(timings, "gpu_render_ms_min");
    }
    for (const auto& [name, value] : run.record.counters) add(counters, name);
  }
  const char* const sizes[] = {"prepare_seconds", "memory_bytes", "peak_rss_bytes"};
  std::vector<std::string> header = {"key",   "status", "method",  "label",
                                     "error", "swept",  "variant", "receiver_pixels"};
  for (const auto& name : build) header.push_back("build." + name);
  for (const auto& name : frame) header.push_back("frame." + name);
  for (const auto& name : render) header.push_back("render." + name);
  for (const auto& name : metrics) header.push_back(name);
  header.push_back("metrics_undefined");
  for (const auto& name : timings) header.push_back(name);
  for (const char* name : sizes) header.push_back(name);
  header.push_back("lost_flux");
  for (const auto& name : counters) header.push_back("counter." + name);
  for (const char* name : {"pareto_front", "reference_key", "git_revision", "record_version"}) header.push_back(name);
  // Measured with several seeds: how many, and each metric's 95 % half-width (the value is the mean).
  if (report.seeds > 1) {
    header.push_back("seeds");
    for (const auto& name : metrics) header.push_back(name + ".ci95");
  }

  // Whole numbers (bytes, counts) without a fraction, the others in full precision.
  auto number_cell = [](std::optional<double> value) {
    if (!value) return std::string();
    if (std::isfinite(*value) && std::floor(*value) == *value && std::abs(*value) < 9.0e15)
      return csv_value(json(static_cast<int64_t>(*value)));
    return csv_value(json(*value));
  };
  std::string out;
  for (size_t c = 0; c < header.size(); ++c) out += (c ? "," : "") + csv_cell(header[c]);
  out += "\n";
  for (size_t i = 0; i < report.runs.size(); ++i) {
    const Run& run = report.runs[i];
    const RunRecord& record = run.record;
    const bool measured = !record.frames.empty();  // ok, stale, or failed after measuring
    std::vector<std::string> swept;
    for (const auto& [name, value] : run.swept().items()) swept.push_back(name);
    std::vector<std::string> cells = {csv_cell(run.key),
                                      csv_cell(run.status),
                                      csv_cell(run.method),
                                      csv_cell(run.label),
                                      csv_cell(run.error),
                                      csv_cell(join(swept, ";")),
                                      csv_cell(record.variant),  // empty in a record before variants
                                      record.receiver_pixels ? std::to_string(*record.receiver_pixels) : ""};
    for (const auto& name : build) cells.push_back(csv_value(member(record.build, name)));
    for (const auto& name : frame) cells.push_back(csv_value(member(record.frame, name)));
    for (const auto& name : render) cells.push_back(csv_value(member(record.render, name)));
    std::vector<std::string> undefined;  // "name: reason" of the metrics without a value, as the tables show them
    for (const auto& name : metrics) {
      std::string why = run.undefined_reason(name);
      if (!why.empty()) undefined.push_back(name + ": " + why);
      auto found = record.metrics.find(name);
      cells.push_back(why.empty() && found != record.metrics.end() ? csv_value(json(found->second)) : "");
    }
    cells.push_back(csv_cell(join(undefined, "; ")));
    for (const auto& name : timings) cells.push_back(measured ? number_cell(record.timings.field(name)) : "");
    cells.push_back(measured ? number_cell(record.prepare.prepare_seconds) : "");
    cells.push_back(measured ? std::to_string(record.memory_bytes) : "");
    cells.push_back(measured ? std::to_string(record.peak_rss_bytes) : "");
    cells.push_back(measured && record.lost_flux ? csv_value(json(record.lost_flux->worst.fraction)) : "");
    for (const auto& name : counters) {
      auto found = record.counters.find(name);
      cells.push_back(found == record.counters.end() ? "" : number_cell(found->second));
    }
    cells.push_back(report.on_overall_front(i) ? "overall" : (report.on_front(i) ? "method" : ""));
    cells.push_back(csv_cell(run.reference_key));
    cells.push_back(csv_cell(record.git_revision));
    cells.push_back(std::to_string(record.record_version));
    if (report.seeds > 1) {
      cells.push_back(measured ? std::to_string(record.seed_count()) : "");
      for (const auto& name : metrics) {
        const std::optional<MetricInterval> interval = run.interval(name);
        cells.push_back(interval ? csv_value(json(interval->half_width)) : "");
      }
    }
    out += join(cells, ",") + "\n";
  }
  return out;
}

}  // namespace causticbench::report_detail
