#include "reports/report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>

#include "core/errors.h"
#include "core/files.h"
#include "core/image.h"
#include "core/gbuffer.h"
#include "core/image_statistics.h"
#include "experiments/experiment.h"
#include "experiments/record_check.h"
#include "experiments/result_store.h"
#include "metrics/metrics.h"

namespace causticbench {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// ---------------------------------------------------------------------------------------------------
// Constants of the pictures (docs/reports.md).

constexpr int kThumbnailWidth = 256;  // thumbnails are at most this wide (never enlarged)
constexpr double kMiddleGrey = 0.18;  // the reference's masked mean maps to this after exposure
constexpr double kErrorScale = 1.0;   // error maps saturate at kErrorScale x reference mean
const char* const kVendorFiles[] = {"vega.min.js", "vega-lite.min.js", "vega-embed.min.js"};

// ---------------------------------------------------------------------------------------------------
// Small helpers.

json read_json(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("cannot read {}", path.string()));
  try {
    return json::parse(in);
  } catch (const json::exception& error) {
    throw InputError(fmt::format("{} is not valid JSON: {}", path.string(), error.what()));
  }
}

std::optional<double> number(const json& object, const std::string& key) {
  if (!object.is_object()) return std::nullopt;
  auto it = object.find(key);
  if (it == object.end() || !it->is_number()) return std::nullopt;
  return it->get<double>();
}

const json& member(const json& object, const std::string& key) {
  static const json null_value;
  if (!object.is_object()) return null_value;
  auto it = object.find(key);
  return it == object.end() ? null_value : *it;
}

std::string string_member(const json& object, const std::string& key, const std::string& fallback = "") {
  const json& value = member(object, key);
  return value.is_string() ? value.get<std::string>() : fallback;
}

bool finite(const std::optional<double>& value) { return value && std::isfinite(*value); }

// Four significant digits: enough to compare, short enough to read in a table.
std::string num(double value) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  return fmt::format("{:.4g}", value);
}

std::string bytes_text(double bytes) {
  static const char* const units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
  int unit = 0;
  while (bytes >= 1024.0 && unit < 4) {
    bytes /= 1024.0;
    ++unit;
  }
  return unit == 0 ? fmt::format("{:.0f} B", bytes) : fmt::format("{:.3g} {}", bytes, units[unit]);
}

// A knob or paper value as a person writes it.
std::string value_text(const json& value) {
  if (value.is_string()) return value.get<std::string>();
  if (value.is_number_float()) return fmt::format("{:.6g}", value.get<double>());
  if (value.is_null()) return "";
  return value.dump();
}

std::string knobs_text(const json& knobs, const std::string& separator = ", ") {
  std::string text;
  if (!knobs.is_object()) return text;
  for (const auto& [name, value] : knobs.items()) {
    if (!text.empty()) text += separator;
    text += name + "=" + value_text(value);
  }
  return text;
}

std::string html_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string md_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '|')
      out += "\\|";
    else if (c == '\n' || c == '\r')
      out += ' ';
    else
      out += c;
  }
  return out;
}

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

// JSON placed inside a <script> element: no "</script>" or "<!--" may appear in it. '<' occurs in JSON
// only inside strings, where \u003c means the same character.
std::string script_json(const json& value) {
  std::string text = value.dump(), out;
  out.reserve(text.size());
  for (char c : text) out += c == '<' ? std::string("\\u003c") : std::string(1, c);
  return out;
}

std::string file_safe(const std::string& text) {
  std::string out;
  for (char c : text) out += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' ? c : '_';
  return out.empty() ? "run" : out;
}

std::string frame_file(int64_t frame, const std::string& prefix = "frame") {
  return ResultPaths::frame_file(static_cast<int>(frame), prefix) + ".exr";
}

// ---------------------------------------------------------------------------------------------------
// Metric directions.

const MetricInfo* metric_info(const std::string& name) {
  for (const MetricInfo& info : metric_registry()) {
    if (info.name == name) return &info;
  }
  return nullptr;
}

// Unknown metrics (none should exist) count as lower-is-better, NaN as worst.
bool better(const std::string& metric, double a, double b) {
  if (const MetricInfo* info = metric_info(metric)) return metric_better(*info, a, b);
  if (std::isnan(a)) return false;
  if (std::isnan(b)) return true;
  return a < b;
}

std::string direction_text(const std::string& metric) {
  const MetricInfo* info = metric_info(metric);
  if (!info) return "lower is better";
  if (info->target) return "best = " + num(*info->target);
  return info->higher_is_better ? "higher is better" : "lower is better";
}

std::string direction_arrow(const std::string& metric) {
  const MetricInfo* info = metric_info(metric);
  if (info && info->target) return "\u2192" + num(*info->target);
  return info && info->higher_is_better ? "\u2191" : "\u2193";
}

// ---------------------------------------------------------------------------------------------------
// What the report is made of.

struct Run {
  std::string key;
  json record;
  bool ok = false;
  std::string status, method, label, error;
  // The scene variant the run belongs to and the reference it is compared with: the record's "variant"
  // and "reference_key"; an older record without them gets the variant whose reference_key it names,
  // else the first variant ("default" in a plain experiment), and that variant's reference.
  std::string variant, reference_key;
  size_t variant_index = 0;  // into Report::variants

  // Its reference had no caustic in view (record "empty_reference", written when the experiment sets
  // empty_reference_expected): every metric but nonfinite_pixels is undefined, whatever the record holds.
  bool empty_reference = false;

  // A metric's value; none when the record has none or says it is undefined.
  std::optional<double> metric(const std::string& name) const {
    if (!undefined_reason(name).empty()) return std::nullopt;
    return number(member(record, "metrics"), name);
  }
  // Why the run has no value of the metric (docs/metrics.md, "Undefined values"); empty when it has one or
  // the record gives no reason.
  std::string undefined_reason(const std::string& name) const {
    if (empty_reference && metric_info(name) && name != "nonfinite_pixels") {
      std::string why = string_member(member(record, "empty_reference"), "reason");
      return why.empty() ? "empty reference" : "empty reference: " + why;
    }
    return string_member(member(record, "metrics_undefined"), name);
  }
  std::optional<double> timing(const std::string& name) const { return number(member(record, "timings"), name); }
  std::optional<double> top(const std::string& name) const { return number(record, name); }
  const json& swept() const { return member(record, "swept"); }
  std::string swept_text() const { return knobs_text(swept()); }
  std::optional<double> frame_ms() const { return timing("frame_ms_median"); }
  // Receiver pixels of the run's first frame (G-buffer), when the record has them.
  const json& receiver_pixels() const { return member(record, "receiver_pixels"); }
};

// One scene variant of the experiment (experiment.json "variants"; a plain experiment has one,
// "default") with its reference.
struct Variant {
  std::string name, reference_key;
  json resolution, overrides;  // as experiment.json states them (null when it does not)
  bool listed = true;          // false: named by a run record only
  json reference;              // the reference's record.json, or null
  std::optional<double> noise_floor;
  json history = json::array();
};

// Pareto fronts (indices into Report::runs) within one variant: over all methods, and per method.
struct Fronts {
  std::vector<size_t> overall;
  std::map<std::string, std::vector<size_t>> per_method;
};

struct Thumbnail {
  std::string title, caption, ec_png, error_png, note;
  bool reference = false;
};

struct Plot {
  std::string id, caption;
  json spec;
};

// A claim of experiment.json checked on the stored runs (docs/reports.md, "Claims"). Run indices are
// into Report::runs; the evidence text is made from these fields when the report is written.
struct LinearGroup {
  json knobs = json::object();  // the values of the grouping knobs (empty when there is one group)
  std::vector<size_t> runs;
  std::vector<double> xs, ys;
  bool fitted = false;          // >= 3 points and x varies
  double slope = NAN, intercept = NAN, r2 = NAN;
  bool passed = false;
};

struct ClaimPoint {
  size_t run = 0;
  double value = NAN;
};

struct ClaimResult {
  json claim;                // as experiment.json states it
  std::string kind, verdict;  // verdict: "confirmed", "not confirmed" or "not measured"
  std::string quantity;      // metric (best, better) or y (linear)
  std::string problem;       // a malformed claim: what is wrong with it
  // best: the runs matching `among` (with a value), split by `expect`.
  // better: the runs matching `run` (first) and `than` (other).
  size_t first_count = 0, other_count = 0, failed_first = 0, failed_other = 0;
  size_t undefined_first = 0, undefined_other = 0;  // ok runs that match but whose value is undefined
  std::optional<ClaimPoint> first, other;  // best: best matching / not matching `expect`;
                                           // better: worst of `run`, best of `than`
  // linear
  std::vector<std::string> group_by;
  std::vector<LinearGroup> groups;
  size_t points = 0;
  double min_r2 = 0.98;
};

struct Report {
  fs::path folder;
  json experiment, environment;
  std::string name, primary;
  std::vector<std::string> metrics;  // metric columns of the tables
  std::vector<Run> runs;             // records found, in the experiment's order
  std::vector<std::string> missing;  // run keys without a record.json
  std::vector<std::string> methods;  // in order of first appearance
  std::vector<Variant> variants;     // never empty; experiment.json's order, then any only runs name
  std::vector<std::string> notes;    // warnings shown at the top of the report

  // Pareto fronts, one set per variant (index as in variants): a run competes only within its variant.
  std::vector<Fronts> fronts;

  std::vector<Thumbnail> thumbnails;
  std::string error_scale_text;  // what the brightest colour of the error maps means
  std::vector<Plot> plots;
  std::vector<ClaimResult> claims;

  std::vector<size_t> ok_runs() const {
    std::vector<size_t> indices;
    for (size_t i = 0; i < runs.size(); ++i)
      if (runs[i].ok) indices.push_back(i);
    return indices;
  }
  size_t failed_count() const {
    return static_cast<size_t>(std::count_if(runs.begin(), runs.end(), [](const Run& run) { return !run.ok; }));
  }
  bool multi() const { return variants.size() > 1; }
  fs::path reference_folder(const std::string& key) const {
    return key.empty() ? fs::path() : fs::path(ResultPaths{folder.parent_path().string()}.reference(key));
  }
  bool on_front(size_t run) const {
    if (fronts.empty()) return false;
    const auto& per_method = fronts[runs[run].variant_index].per_method;
    auto it = per_method.find(runs[run].method);
    return it != per_method.end() && std::find(it->second.begin(), it->second.end(), run) != it->second.end();
  }
  bool on_overall_front(size_t run) const {
    if (fronts.empty()) return false;
    const std::vector<size_t>& overall = fronts[runs[run].variant_index].overall;
    return std::find(overall.begin(), overall.end(), run) != overall.end();
  }
  // Every variant's overall front, in variant order.
  std::vector<size_t> overall_fronts() const {
    std::vector<size_t> all;
    for (const Fronts& f : fronts) all.insert(all.end(), f.overall.begin(), f.overall.end());
    return all;
  }
  // The run's label as a person reads it: with several variants, its variant is added unless the label
  // names it already (the runner appends " @<variant>").
  std::string display(size_t run) const {
    const Run& r = runs[run];
    if (!multi() || r.label.find("@" + r.variant) != std::string::npos) return r.label;
    return r.label + " @" + r.variant;
  }
};

// ---------------------------------------------------------------------------------------------------
// Loading.

void load(Report& report, const std::string& folder_text) {
  if (folder_text.empty()) throw InputError("report: no experiment folder given (expected results/<experiment>/)");
  fs::path folder(folder_text);
  std::error_code error;
  if (!fs::exists(folder, error)) {
    throw InputError(
        fmt::format("'{}' does not exist: expected an experiment results folder such as "
                    "results/<experiment>/, written by `causticbench run EXPERIMENT.yaml`",
                    folder_text));
  }
  if (!fs::is_directory(folder, error)) {
    throw InputError(
        fmt::format("'{}' is a file, not an experiment results folder (results/<experiment>/)", folder_text));
  }
  folder = fs::absolute(folder).lexically_normal();
  if (folder.filename().empty()) folder = folder.parent_path();
  report.folder = folder;
  if (!fs::is_regular_file(folder / "experiment.json")) {
    std::vector<std::string> inside;
    for (const auto& entry : fs::directory_iterator(folder, error)) {
      if (entry.is_directory() && fs::is_regular_file(entry.path() / "experiment.json"))
        inside.push_back((fs::path(folder_text) / entry.path().filename()).string());
    }
    std::sort(inside.begin(), inside.end());
    std::string hint = inside.empty() ? "; `causticbench run EXPERIMENT.yaml` writes one as results/<experiment>/"
                                      : "; the experiment folders inside it are: " + join(inside, ", ");
    throw InputError(
        fmt::format("'{}' is not an experiment results folder: it has no experiment.json{}", folder_text, hint));
  }
  report.experiment = read_json(folder / "experiment.json");
  if (!report.experiment.is_object())
    throw InputError(fmt::format("{} is not a JSON object", (folder / "experiment.json").string()));
  report.name = string_member(report.experiment, "name", folder.filename().string());

  if (fs::is_regular_file(folder / "environment.json")) {
    report.environment = read_json(folder / "environment.json");
  } else {
    report.notes.push_back("environment.json is missing: the machine these numbers come from is unknown.");
  }

  // Runs: the experiment's list, in its order; without a list, every runs/<key>/ folder.
  std::vector<std::string> keys;
  const json& listed = member(report.experiment, "runs");
  if (listed.is_array()) {
    for (const json& key : listed)
      if (key.is_string()) keys.push_back(key.get<std::string>());
  } else if (fs::is_directory(folder / "runs")) {
    for (const auto& entry : fs::directory_iterator(folder / "runs"))
      if (entry.is_directory()) keys.push_back(entry.path().filename().string());
    std::sort(keys.begin(), keys.end());
  }
  size_t unconverged = 0;  // runs measured against a reference stopped by its time cap
  for (const std::string& key : keys) {
    fs::path path = folder / "runs" / key / "record.json";
    if (!fs::is_regular_file(path)) {
      report.missing.push_back(key);
      continue;
    }
    Run run;
    run.key = key;
    try {
      run.record = read_json(path);
      // The store's own check (experiments/record_check.h): a damaged record is never shown as ok.
      std::string problem = run_record_problem(run.record, (folder / "runs" / key).string());
      if (!problem.empty()) throw InputError(fmt::format("damaged record {}: {}", path.string(), problem));
    } catch (const InputError& failure) {
      run.record = json{{"key", key}, {"status", "failed"}, {"error", failure.what()}};
    }
    run.status = string_member(run.record, "status", "ok");
    run.ok = run.status == "ok";
    run.method = string_member(run.record, "method", "?");
    run.label = string_member(run.record, "label", run.method + " " + key.substr(0, 8));
    run.error = string_member(run.record, "error");
    if (!run.ok && run.error.empty()) run.error = "(no error message recorded)";
    run.empty_reference = member(run.record, "empty_reference").is_object();
    if (member(run.record, "reference_converged") == false) ++unconverged;
    report.runs.push_back(std::move(run));
  }
  if (unconverged)
    report.notes.push_back(fmt::format("{} run(s) were measured against a reference that stopped on its time cap "
                                       "(max_seconds), not converged: their errors include the reference's own.",
                                       unconverged));
  if (report.runs.empty() && report.missing.empty()) report.notes.push_back("experiment.json names no runs.");
  if (fs::is_directory(folder / "runs")) {
    std::set<std::string> known(keys.begin(), keys.end());
    size_t stale = 0;
    for (const auto& entry : fs::directory_iterator(folder / "runs"))
      if (entry.is_directory() && !known.count(entry.path().filename().string())) ++stale;
    if (stale)
      report.notes.push_back(
          fmt::format("{} folder(s) under runs/ are not runs of this experiment (an earlier "
                      "version of it?) and are left out.",
                      stale));
  }

  for (const Run& run : report.runs) {
    if (std::find(report.methods.begin(), report.methods.end(), run.method) == report.methods.end())
      report.methods.push_back(run.method);
  }

  // Metric columns: the experiment's, then any other metric a run stored (temporal_flicker, ...),
  // except nonfinite_pixels unless some run has any.
  const json& named = member(report.experiment, "metrics");
  if (named.is_array()) {
    for (const json& metric : named)
      if (metric.is_string()) report.metrics.push_back(metric.get<std::string>());
  }
  std::set<std::string> stored;
  bool nonfinite = false;
  for (const Run& run : report.runs) {
    const json& undefined = member(run.record, "metrics_undefined");
    if (undefined.is_object())
      for (const auto& [name, why] : undefined.items()) stored.insert(name);
    const json& metrics = member(run.record, "metrics");
    if (!metrics.is_object()) continue;
    for (const auto& [name, value] : metrics.items()) {
      stored.insert(name);
      if (name == "nonfinite_pixels" && value.is_number() && value.get<double>() > 0) nonfinite = true;
    }
  }
  std::vector<std::string> extra;
  for (const MetricInfo& info : metric_registry())
    if (stored.count(info.name)) extra.push_back(info.name);
  for (const std::string& name : stored)
    if (!metric_info(name)) extra.push_back(name);
  for (const std::string& name : extra) {
    if (name == "nonfinite_pixels" && !nonfinite) continue;
    if (std::find(report.metrics.begin(), report.metrics.end(), name) == report.metrics.end())
      report.metrics.push_back(name);
  }
  report.primary = string_member(report.experiment, "primary_metric");
  if (report.primary.empty()) {
    report.primary = std::find(report.metrics.begin(), report.metrics.end(), "relmse") != report.metrics.end()
                         ? "relmse"
                         : (report.metrics.empty() ? "relmse" : report.metrics.front());
  }

  // The scene variants: experiment.json's list; without one, a single "default" variant with the
  // top-level reference_key.
  std::string top_key = string_member(report.experiment, "reference_key");
  const json& listed_variants = member(report.experiment, "variants");
  if (listed_variants.is_array()) {
    for (const json& entry : listed_variants) {
      if (!entry.is_object()) continue;
      Variant variant;
      variant.name = string_member(
          entry, "name", report.variants.empty() ? "default" : fmt::format("variant{}", report.variants.size()));
      variant.reference_key = string_member(entry, "reference_key", report.variants.empty() ? top_key : "");
      variant.resolution = member(entry, "resolution");
      variant.overrides = member(entry, "overrides");
      bool known = std::any_of(report.variants.begin(), report.variants.end(),
                               [&](const Variant& v) { return v.name == variant.name; });
      if (!known) report.variants.push_back(std::move(variant));
    }
  }
  if (report.variants.empty()) {
    Variant variant;
    variant.name = "default";
    variant.reference_key = top_key;
    variant.resolution = member(report.experiment, "resolution");
    variant.overrides = member(report.experiment, "overrides");
    report.variants.push_back(std::move(variant));
  }
  std::vector<std::string> unlisted;
  for (Run& run : report.runs) {
    run.variant = string_member(run.record, "variant");
    run.reference_key = string_member(run.record, "reference_key");
    if (run.variant.empty()) {
      auto named = std::find_if(report.variants.begin(), report.variants.end(), [&](const Variant& v) {
        return !run.reference_key.empty() && v.reference_key == run.reference_key;
      });
      run.variant = named != report.variants.end() ? named->name : report.variants.front().name;
    }
    auto found = std::find_if(report.variants.begin(), report.variants.end(),
                              [&](const Variant& v) { return v.name == run.variant; });
    if (found == report.variants.end()) {
      Variant variant;
      variant.name = run.variant;
      variant.reference_key = run.reference_key;
      variant.listed = false;
      unlisted.push_back(run.variant);
      report.variants.push_back(std::move(variant));
      found = std::prev(report.variants.end());
    }
    run.variant_index = static_cast<size_t>(found - report.variants.begin());
    if (run.reference_key.empty()) run.reference_key = found->reference_key;
  }
  if (!unlisted.empty())
    report.notes.push_back(
        fmt::format("Run records name variant(s) that experiment.json does not list: {}.", join(unlisted, ", ")));

  // Each variant's reference record: noise floor, history, passes, seconds.
  std::map<std::string, json> records;
  std::set<std::string> missing_records;
  for (Variant& variant : report.variants) {
    if (variant.reference_key.empty()) {
      report.notes.push_back(report.multi() ? fmt::format("Variant {} names no reference_key: no reference image, "
                                                          "noise floor or error maps for it.",
                                                          variant.name)
                                            : "experiment.json names no reference_key: no reference images, noise "
                                              "floor or error maps.");
      continue;
    }
    fs::path path = report.reference_folder(variant.reference_key) / "record.json";
    if (!records.count(variant.reference_key)) {
      if (fs::is_regular_file(path)) {
        records[variant.reference_key] = read_json(path);
      } else {
        records[variant.reference_key] = nullptr;
        if (missing_records.insert(variant.reference_key).second)
          report.notes.push_back(fmt::format("The reference record {} is missing: no noise floor or convergence plot{}.",
                                             path.string(), report.multi() ? " for variant " + variant.name : ""));
      }
    }
    variant.reference = records[variant.reference_key];
    const json& floor = member(variant.reference, "noise_floor");
    if (floor.is_number()) variant.noise_floor = floor.get<double>();
    const json& history = member(variant.reference, "history");
    if (history.is_array()) variant.history = history;
  }
}

// ---------------------------------------------------------------------------------------------------
// Pareto fronts.

void compute_fronts(Report& report) {
  report.fronts.assign(report.variants.size(), Fronts{});
  auto is_better = [&](double a, double b) { return better(report.primary, a, b); };
  for (size_t v = 0; v < report.variants.size(); ++v) {
    Fronts& fronts = report.fronts[v];
    std::vector<size_t> candidates;
    std::vector<TradeoffPoint> points;
    for (size_t i : report.ok_runs()) {
      if (report.runs[i].variant_index != v) continue;
      auto time = report.runs[i].frame_ms();
      auto value = report.runs[i].metric(report.primary);
      if (!finite(time) || !finite(value)) continue;
      candidates.push_back(i);
      points.push_back({*time, *value});
    }
    for (size_t f : pareto_front(points, is_better)) fronts.overall.push_back(candidates[f]);
    for (const std::string& method : report.methods) {
      std::vector<size_t> mine;
      std::vector<TradeoffPoint> my_points;
      for (size_t c = 0; c < candidates.size(); ++c) {
        if (report.runs[candidates[c]].method != method) continue;
        mine.push_back(candidates[c]);
        my_points.push_back(points[c]);
      }
      if (mine.empty()) continue;
      for (size_t f : pareto_front(my_points, is_better)) fronts.per_method[method].push_back(mine[f]);
    }
  }
}

// ---------------------------------------------------------------------------------------------------
// Images.

cv::Mat to_mat(const Image& image) {
  cv::Mat mat(image.height(), image.width(), CV_32FC3);
  for (int y = 0; y < image.height(); ++y) {
    float* row = mat.ptr<float>(y);
    for (int x = 0; x < image.width(); ++x) {
      size_t pixel = static_cast<size_t>(y) * image.width() + x;
      for (int c = 0; c < 3; ++c) {
        float value = image.at(pixel, std::min(c, image.channels() - 1));
        row[3 * x + c] = std::isfinite(value) ? value : 0.0f;
      }
    }
  }
  return mat;
}

Image to_image(const cv::Mat& mat) {
  Image image(mat.cols, mat.rows, 3);
  for (int y = 0; y < mat.rows; ++y) {
    const float* row = mat.ptr<float>(y);
    for (int x = 0; x < mat.cols; ++x)
      for (int c = 0; c < 3; ++c) image.at(static_cast<size_t>(y) * mat.cols + x, c) = row[3 * x + c];
  }
  return image;
}

cv::Mat shrink(const cv::Mat& mat) {
  if (mat.cols <= kThumbnailWidth) return mat;
  int height = std::max(1, static_cast<int>(std::lround(mat.rows * static_cast<double>(kThumbnailWidth) / mat.cols)));
  cv::Mat small;
  cv::resize(mat, small, cv::Size(kThumbnailWidth, height), 0, 0, cv::INTER_AREA);
  return small;
}

// Pixels where the reference has caustic light (masked-out pixels are stored as zero): the fallback
// mask when a reference has no stored G-buffer.
std::vector<uint8_t> lit_mask(const Image& reference) {
  std::vector<uint8_t> mask(reference.pixel_count(), 0);
  for (size_t pixel = 0; pixel < reference.pixel_count(); ++pixel) {
    for (int c = 0; c < std::min(3, reference.channels()); ++c) {
      float value = reference.at(pixel, c);
      if (std::isfinite(value) && value > 0.0f) mask[pixel] = 1;
    }
  }
  return mask;
}

// The receiver mask of a reference frame, from its stored G-buffer (channel 10, "receiver"), so that
// the exposure matches `causticbench render`; the lit pixels when the G-buffer is missing.
std::vector<uint8_t> receiver_mask(const fs::path& reference_folder, int64_t frame, const Image& reference) {
  fs::path gbuffer_path = reference_folder / frame_file(frame, "gbuffer");
  if (fs::is_regular_file(gbuffer_path)) {
    Image gbuffer = read_exr(gbuffer_path.string());
    if (gbuffer.channels() > GBuffer::kReceiverChannel && gbuffer.pixel_count() == reference.pixel_count()) {
      std::vector<uint8_t> mask(gbuffer.pixel_count(), 0);
      for (size_t pixel = 0; pixel < gbuffer.pixel_count(); ++pixel) {
        mask[pixel] = gbuffer.at(pixel, GBuffer::kReceiverChannel) > 0.5f;
      }
      return mask;
    }
  }
  return lit_mask(reference);
}

void write_png_atomically(const cv::Mat& bgr, const fs::path& path) {
  fs::path temporary = path;
  temporary += ".partial.png";
  if (!cv::imwrite(temporary.string(), bgr)) throw std::runtime_error("cannot write " + path.string());
  fs::rename(temporary, path);
}

void write_thumbnail(const Image& image, const fs::path& path, float exposure) {
  write_png(to_image(shrink(to_mat(image))), path.string(), exposure);
}

// |test - reference| as luminance, clamped to [0, scale], then shrunk, then coloured.
void write_error_map(const Image& test, const Image& reference, double scale, const fs::path& path) {
  cv::Mat error(reference.height(), reference.width(), CV_32F);
  for (int y = 0; y < reference.height(); ++y) {
    float* row = error.ptr<float>(y);
    for (int x = 0; x < reference.width(); ++x) {
      size_t pixel = static_cast<size_t>(y) * reference.width() + x;
      const float weights[3] = {0.2126f, 0.7152f, 0.0722f};
      double sum = 0.0;
      bool bad = false;
      for (int c = 0; c < 3; ++c) {
        float t = test.at(pixel, std::min(c, test.channels() - 1));
        float r = reference.at(pixel, std::min(c, reference.channels() - 1));
        if (!std::isfinite(t) || !std::isfinite(r)) bad = true;
        sum += weights[c] * std::abs(static_cast<double>(t) - r);
      }
      row[x] = bad ? 1.0f : static_cast<float>(std::clamp(sum, 0.0, scale) / scale);
    }
  }
  cv::Mat small = shrink(error), bytes, coloured;
  small.convertTo(bytes, CV_8U, 255.0);
  cv::applyColorMap(bytes, coloured, cv::COLORMAP_INFERNO);
  write_png_atomically(coloured, path);
}

void write_colour_bar(const fs::path& path) {
  cv::Mat ramp(1, 256, CV_8U);
  for (int i = 0; i < 256; ++i) ramp.at<uint8_t>(0, i) = static_cast<uint8_t>(i);
  cv::Mat bar, coloured;
  cv::resize(ramp, bar, cv::Size(256, 12), 0, 0, cv::INTER_NEAREST);
  cv::applyColorMap(bar, coloured, cv::COLORMAP_INFERNO);
  write_png_atomically(coloured, path);
}

// "relmse 0.012", "relmse undefined", or "empty reference": the primary metric under a run's picture.
std::string primary_caption(const Report& report, const Run& run) {
  if (run.empty_reference) return "empty reference";
  if (auto value = run.metric(report.primary)) return report.primary + " " + num(*value);
  return report.primary + (run.undefined_reason(report.primary).empty() ? " \u2014" : " undefined");
}

struct ReferenceFrame {
  Image image;
  double mean = 0.0;  // masked mean (average of RGB) over the lit pixels
  bool ok = false;
  std::string error;
};

void make_images(Report& report, std::set<std::string>& written) {
  fs::path images = report.folder / "report";
  // Reference frames, keyed by (reference_key, frame): every run is compared with its own reference.
  std::map<std::pair<std::string, int64_t>, ReferenceFrame> references;
  auto reference_frame = [&](const std::string& key, int64_t frame) -> ReferenceFrame& {
    auto it = references.find({key, frame});
    if (it != references.end()) return it->second;
    ReferenceFrame& entry = references[{key, frame}];
    if (key.empty()) {
      entry.error = "no reference";
      return entry;
    }
    fs::path folder = report.reference_folder(key);
    fs::path path = folder / frame_file(frame);
    try {
      entry.image = read_exr(path.string());
      entry.mean = masked_mean(entry.image, receiver_mask(folder, frame, entry.image));
      entry.ok = true;
    } catch (const std::exception& failure) {
      entry.error = fmt::format("reference image {} unreadable: {}", path.string(), failure.what());
    }
    return entry;
  };

  int64_t first_frame = 0;
  const json& frames = member(report.experiment, "frames");
  if (frames.is_array() && !frames.empty() && frames[0].is_number_integer()) first_frame = frames[0].get<int64_t>();
  for (size_t i : report.ok_runs()) {
    const json& run_frames = member(report.runs[i].record, "frames");
    if (run_frames.is_array() && !run_frames.empty() && member(run_frames[0], "frame").is_number_integer()) {
      first_frame = member(run_frames[0], "frame").get<int64_t>();
      break;
    }
  }

  // The references first: one per variant ("reference.png" when there is one variant).
  std::vector<std::string> scales;  // the error maps' saturation value of each variant
  for (const Variant& variant : report.variants) {
    ReferenceFrame& reference = reference_frame(variant.reference_key, first_frame);
    if (!reference.ok) {
      if (!variant.reference_key.empty())
        report.notes.push_back((report.multi() ? "Variant " + variant.name + ": " : std::string()) + reference.error +
                               ": thumbnails are exposed on their own mean and have no error maps.");
      continue;
    }
    Thumbnail thumb;
    thumb.reference = true;
    thumb.title = report.multi() ? "reference " + variant.name : "reference";
    std::string passes = member(variant.reference, "passes").is_number()
                             ? value_text(member(variant.reference, "passes")) + " passes"
                             : "";
    thumb.caption = fmt::format("frame {}{}{}", first_frame, passes.empty() ? "" : " \u00b7 " + passes,
                                variant.noise_floor ? " \u00b7 noise floor " + num(*variant.noise_floor) : "");
    thumb.ec_png = report.multi() ? "reference_" + file_safe(variant.name) + ".png" : "reference.png";
    for (size_t n = 2; written.count(thumb.ec_png); ++n)
      thumb.ec_png = fmt::format("reference_{}_{}.png", file_safe(variant.name), n);
    float exposure = reference.mean > 0.0 ? static_cast<float>(kMiddleGrey / reference.mean) : 1.0f;
    write_thumbnail(reference.image, images / thumb.ec_png, exposure);
    written.insert(thumb.ec_png);
    if (!(reference.mean > 0.0)) thumb.note = "black over the receivers: no error maps against it";
    report.thumbnails.push_back(thumb);
    if (!(reference.mean > 0.0)) continue;  // error maps need the reference's mean as their scale
    scales.push_back((report.multi() ? variant.name + " " : std::string()) + num(kErrorScale * reference.mean) +
                     " W/m\u00b2");
  }
  if (scales.size() == 1 && !report.multi()) {
    report.error_scale_text = fmt::format("{} \u00d7 reference mean = {}", num(kErrorScale), scales.front());
  } else if (!scales.empty()) {
    report.error_scale_text =
        fmt::format("{} \u00d7 the mean of the run's own reference ({})", num(kErrorScale), join(scales, ", "));
  }

  // Runs grouped by method, in their order.
  for (const std::string& method : report.methods) {
    for (size_t i : report.ok_runs()) {
      const Run& run = report.runs[i];
      if (run.method != method) continue;
      Thumbnail thumb;
      thumb.title = report.display(i);
      auto time = run.frame_ms();
      thumb.caption = primary_caption(report, run) + (time ? " \u00b7 " + num(*time) + " ms" : "");
      const json& run_frames = member(run.record, "frames");
      if (!run_frames.is_array() || run_frames.empty()) {
        thumb.note = "no frames recorded";
        report.thumbnails.push_back(thumb);
        continue;
      }
      int64_t frame = member(run_frames[0], "frame").is_number_integer() ? member(run_frames[0], "frame").get<int64_t>()
                                                                         : first_frame;
      std::string image_name = string_member(run_frames[0], "image", frame_file(frame));
      fs::path path = report.folder / "runs" / run.key / image_name;
      try {
        Image image = read_exr(path.string());
        ReferenceFrame& reference = reference_frame(run.reference_key, frame);
        // A black reference gives no exposure: the run is then exposed on its own light, so that light the
        // method puts where the reference has none shows.
        double mean = reference.ok && reference.mean > 0.0 ? reference.mean : masked_mean(image, lit_mask(image));
        float exposure = mean > 0.0 ? static_cast<float>(kMiddleGrey / mean) : 1.0f;
        std::string stem = file_safe(run.key);
        thumb.ec_png = stem + ".png";
        write_thumbnail(image, images / thumb.ec_png, exposure);
        written.insert(thumb.ec_png);
        if (reference.ok && reference.mean > 0.0) {
          if (reference.image.width() == image.width() && reference.image.height() == image.height()) {
            thumb.error_png = stem + "_error.png";
            write_error_map(image, reference.image, kErrorScale * reference.mean, images / thumb.error_png);
            written.insert(thumb.error_png);
          } else {
            thumb.note = fmt::format("{}x{} but the reference is {}x{}: no error map", image.width(), image.height(),
                                     reference.image.width(), reference.image.height());
          }
        }
      } catch (const std::exception& failure) {
        thumb.note = fmt::format("image {} unreadable: {}", path.string(), failure.what());
      }
      report.thumbnails.push_back(thumb);
    }
  }
  if (!report.error_scale_text.empty()) {
    write_colour_bar(images / "error_colour_bar.png");
    written.insert("error_colour_bar.png");
  }
}

// ---------------------------------------------------------------------------------------------------
// Plots (Vega-Lite v5 specifications, rendered by vega-embed in report.html).

bool all_positive(const std::vector<double>& values) {
  return !values.empty() && std::all_of(values.begin(), values.end(), [](double v) { return v > 0.0; });
}

json base_spec(const std::string& title, const std::string& subtitle) {
  json title_block = {{"text", title}, {"anchor", "start"}, {"fontSize", 15}};
  if (!subtitle.empty()) title_block["subtitle"] = subtitle;
  return {{"$schema", "https://vega.github.io/schema/vega-lite/v5.json"},
          {"title", title_block},
          {"width", 430},
          {"height", 300},
          {"config",
           {{"font", "system-ui, -apple-system, Segoe UI, Helvetica, Arial, sans-serif"},
            {"axis", {{"labelFontSize", 11}, {"titleFontSize", 12}, {"gridOpacity", 0.6}}},
            {"legend", {{"labelLimit", 360}, {"labelFontSize", 11}, {"titleFontSize", 12}}},
            {"title", {{"subtitleColor", "#555"}, {"subtitleFontSize", 11}}}}}};
}

json axis(const std::string& field, const std::string& title, bool log) {
  json encoding = {{"field", field}, {"type", "quantitative"}, {"title", title}};
  if (log) {
    encoding["scale"] = {{"type", "log"}};
    encoding["axis"] = {{"format", "~g"}};
  } else {
    encoding["scale"] = {{"zero", false}};
  }
  return encoding;
}

// Vega's tableau10 colours, given to the methods in their order, so that a method keeps its colour in
// every plot even when a plot shows only some of the methods.
json method_colour(const Report& report, const std::set<std::string>& shown = {}) {
  static const char* const palette[] = {"#4c78a8", "#f58518", "#e45756", "#72b7b2", "#54a24b",
                                        "#eeca3b", "#b279a2", "#ff9da6", "#9d755d", "#bab0ac"};
  json domain = json::array(), range = json::array();
  for (size_t m = 0; m < report.methods.size(); ++m) {
    if (!shown.empty() && !shown.count(report.methods[m])) continue;
    domain.push_back(report.methods[m]);
    range.push_back(palette[m % 10]);
  }
  return {
      {"field", "method"}, {"type", "nominal"}, {"title", "method"}, {"scale", {{"domain", domain}, {"range", range}}}};
}

// A dashed horizontal rule at `value` with a label, as two layers.
std::vector<json> rule_layers(const std::string& field, double value, const std::string& text,
                              const std::string& colour) {
  json data = {{"values", json::array({{{field, value}, {"text", text}}})}};
  json y = {{"field", field}, {"type", "quantitative"}};
  return {{{"data", data},
           {"mark", {{"type", "rule"}, {"strokeDash", {6, 4}}, {"color", colour}, {"strokeWidth", 1.5}}},
           {"encoding", {{"y", y}}}},
          {{"data", data},
           {"mark",
            {{"type", "text"},
             {"align", "left"},
             {"baseline", "bottom"},
             {"dx", 4},
             {"dy", -3},
             {"color", colour},
             {"fontSize", 11}}},
           {"encoding", {{"y", y}, {"x", {{"value", 0}}}, {"text", {{"field", "text"}}}}}}};
}

json run_row(const Report& report, size_t i) {
  const Run& run = report.runs[i];
  json row = {{"key", run.key},
              {"method", run.method},
              {"label", report.display(i)},
              {"knobs", run.swept_text()},
              {"frame_ms", run.frame_ms().value_or(NAN)},
              {"value", run.metric(report.primary).value_or(NAN)},
              {"front", report.on_front(i)}};
  if (report.multi()) {
    row["variant"] = run.variant;
    row["series"] = run.variant + " " + run.method;
  }
  return row;
}

json tooltip(const Report& report) {
  json fields = json::array({{{"field", "label"}, {"title", "run"}},
                             {{"field", "method"}},
                             {{"field", "knobs"}, {"title", "swept"}},
                             {{"field", "frame_ms"}, {"title", "frame ms (median)"}, {"format", ".4g"}},
                             {{"field", "value"}, {"title", report.primary}, {"format", ".4g"}}});
  if (report.multi()) fields.insert(fields.begin() + 2, json{{"field", "variant"}});
  return fields;
}

// The reference noise floor rules of the error plots (primary metric relMSE only): one per variant whose
// reference has a positive floor, labelled with the variant's name when there are several. The floors
// are appended to `values` (for the choice of a log axis).
std::vector<json> floor_layers(const Report& report, const std::string& field, std::vector<double>& values) {
  std::vector<json> layers;
  if (report.primary != "relmse") return layers;
  for (const Variant& variant : report.variants) {
    if (!finite(variant.noise_floor) || !(*variant.noise_floor > 0.0)) continue;
    double floor = *variant.noise_floor;
    values.push_back(floor);
    std::string text = report.multi() ? fmt::format("reference noise floor {} {}", variant.name, num(floor))
                                      : "reference noise floor " + num(floor);
    for (json& layer : rule_layers(field, floor, text, "#666")) layers.push_back(layer);
  }
  return layers;
}

// Points of several variants are told apart by their shape.
void add_variant_shape(const Report& report, json& encoding) {
  if (!report.multi()) return;
  json names = json::array();
  for (const Variant& variant : report.variants) names.push_back(variant.name);
  encoding["shape"] = {{"field", "variant"}, {"type", "nominal"}, {"title", "variant"}, {"scale", {{"domain", names}}}};
}

void make_tradeoff_plot(Report& report) {
  std::vector<size_t> plotted;
  std::vector<double> times, values;
  for (size_t i : report.ok_runs()) {
    auto time = report.runs[i].frame_ms();
    auto value = report.runs[i].metric(report.primary);
    if (!finite(time) || !finite(value)) continue;
    plotted.push_back(i);
    times.push_back(*time);
    values.push_back(*value);
  }
  if (plotted.empty()) return;
  std::vector<json> floors = floor_layers(report, "value", values);
  bool log_x = all_positive(times), log_y = all_positive(values);

  // Fronts are computed within each variant: one line per (variant, method), one band per variant.
  json front_points = json::array(), dominated = json::array(), front_lines = json::array(), overall = json::array();
  for (size_t i : plotted) (report.on_front(i) ? front_points : dominated).push_back(run_row(report, i));
  for (const Fronts& fronts : report.fronts) {
    for (const auto& [method, front] : fronts.per_method) {
      int order = 0;
      for (size_t i : front) {
        json row = run_row(report, i);
        row["order"] = order++;
        front_lines.push_back(row);
      }
    }
    if (fronts.overall.size() < 2) continue;
    int order = 0;
    for (size_t i : fronts.overall) {
      json row = run_row(report, i);
      row["order"] = order++;
      overall.push_back(row);
    }
  }

  std::string y_title = fmt::format("{} ({}{})", report.primary, direction_text(report.primary), log_y ? ", log" : "");
  json x = axis("frame_ms", std::string("frame time, median ms") + (log_x ? " (log)" : ""), log_x);
  json y = axis("value", y_title, log_y);
  json layers = json::array();
  if (!overall.empty()) {
    json band = {{"x", x}, {"y", y}, {"order", {{"field", "order"}}}};
    if (report.multi()) band["detail"] = {{"field", "variant"}};
    layers.push_back({{"data", {{"values", overall}}},
                      {"mark",
                       {{"type", "line"},
                        {"color", "#999"},
                        {"opacity", 0.3},
                        {"strokeWidth", 9},
                        {"strokeCap", "round"},
                        {"strokeJoin", "round"}}},
                      {"encoding", band}});
  }
  json lines = {{"x", x}, {"y", y}, {"color", method_colour(report)}, {"order", {{"field", "order"}}}};
  if (report.multi()) lines["detail"] = {{"field", "series"}};
  layers.push_back(
      {{"data", {{"values", front_lines}}}, {"mark", {{"type", "line"}, {"strokeWidth", 2}}}, {"encoding", lines}});
  json points = {{"x", x}, {"y", y}, {"color", method_colour(report)}, {"tooltip", tooltip(report)}};
  add_variant_shape(report, points);
  if (!dominated.empty()) {
    layers.push_back({{"data", {{"values", dominated}}},
                      {"mark", {{"type", "point"}, {"filled", false}, {"size", 60}, {"strokeWidth", 1.5}}},
                      {"encoding", points}});
  }
  layers.push_back({{"data", {{"values", front_points}}},
                    {"mark", {{"type", "point"}, {"filled", true}, {"size", 80}, {"opacity", 1}}},
                    {"encoding", points}});
  for (json& layer : floors) layers.push_back(layer);
  json spec = base_spec(fmt::format("Trade-off: {} versus frame time", report.primary),
                        report.multi() ? "each point one run, shape = scene variant; filled = on its method's Pareto "
                                         "front within its variant, hollow = dominated; grey bands = fronts over all "
                                         "methods"
                                       : "each point one run; filled = on its method's Pareto front, hollow = "
                                         "dominated; grey band = front over all methods");
  spec["layer"] = layers;
  std::string caption = fmt::format(
      "x: median frame time (update + render) over the repetitions; y: {} against the reference (mean over the "
      "frames). A run is on its method's front when no run of that method is at least as fast and at least as "
      "good ({}) and strictly better in one of the two.",
      report.primary, direction_text(report.primary));
  if (report.multi())
    caption +=
        " Fronts are computed within each scene variant: a run competes only with runs of its own variant, each "
        "measured against its own reference.";
  if (!floors.empty())
    caption += report.multi() ? " Below a variant's dashed noise floor its reference cannot tell errors apart."
                              : " Below the dashed noise floor the reference cannot tell errors apart.";
  report.plots.push_back({"plot-tradeoff", caption, spec});
}

void make_convergence_plot(Report& report) {
  // One line per variant's reference (a plain experiment has one).
  json rows = json::array();
  std::vector<double> seconds, floors;
  for (const Variant& variant : report.variants) {
    for (const json& entry : variant.history) {
      auto s = number(entry, "seconds"), f = number(entry, "noise_floor");
      if (!finite(s) || !finite(f)) continue;
      json row = {{"seconds", *s}, {"noise_floor", *f}};
      if (entry.contains("pass")) row["pass"] = entry["pass"];
      if (entry.contains("photons")) row["photons"] = entry["photons"];
      if (report.multi()) row["variant"] = variant.name;
      rows.push_back(row);
      seconds.push_back(*s);
      floors.push_back(*f);
    }
  }
  if (rows.empty()) return;
  // The best relMSE any method reached: the floor must sit well below it.
  std::optional<double> best;
  std::string best_label;
  for (size_t i : report.ok_runs()) {
    auto value = report.runs[i].metric("relmse");
    if (!finite(value)) continue;
    if (!best || better("relmse", *value, *best)) {
      best = *value;
      best_label = report.display(i);
    }
  }
  std::vector<double> all = floors;
  if (best) all.push_back(*best);
  bool log_x = all_positive(seconds), log_y = all_positive(all);
  json x = axis("seconds", std::string("reference time, s") + (log_x ? " (log)" : ""), log_x);
  json y = axis("noise_floor", std::string("noise floor, estimated relMSE") + (log_y ? " (log)" : ""), log_y);
  json tip = json::array({{{"field", "pass"}},
                          {{"field", "photons"}, {"format", ",d"}},
                          {{"field", "seconds"}, {"format", ".4g"}},
                          {{"field", "noise_floor"}, {"title", "noise floor"}, {"format", ".4g"}}});
  json layers = json::array();
  if (report.multi()) {
    tip.insert(tip.begin(), json{{"field", "variant"}});
    layers.push_back({{"data", {{"values", rows}}},
                      {"mark", {{"type", "line"}, {"point", {{"filled", true}, {"size", 30}}}}},
                      {"encoding",
                       {{"x", x},
                        {"y", y},
                        {"color", {{"field", "variant"}, {"type", "nominal"}, {"title", "variant"}, {"sort", nullptr}}},
                        {"tooltip", tip}}}});
  } else {
    layers.push_back(
        {{"data", {{"values", rows}}},
         {"mark",
          {{"type", "line"}, {"point", {{"filled", true}, {"size", 30}, {"color", "#333"}}}, {"color", "#333"}}},
         {"encoding", {{"x", x}, {"y", y}, {"tooltip", tip}}}});
  }
  if (best) {
    for (json& layer :
         rule_layers("noise_floor", *best, "best method relMSE " + num(*best) + " (" + best_label + ")", "#e45756"))
      layers.push_back(layer);
  }
  json spec = base_spec("Reference convergence: noise floor versus time",
                        "relMSE of the reference estimated from two independent halves, after each pass");
  spec["layer"] = layers;
  std::string caption =
      "The reference's estimated relMSE (its noise floor) after each progressive pass, against the seconds it "
      "had run. Metrics below the floor are not resolved; the red rule is the best relMSE any method reached "
      "in this experiment.";
  if (report.multi()) caption += " One line per scene variant's reference; the rule is the best over all variants.";
  report.plots.push_back({"plot-convergence", caption, spec});
}

void make_sweep_plots(Report& report) {
  // Knob name -> methods that sweep it over at least two values.
  std::map<std::string, std::set<std::string>> knobs;
  for (const std::string& method : report.methods) {
    std::map<std::string, std::set<std::string>> seen;
    for (size_t i : report.ok_runs()) {
      if (report.runs[i].method != method || !report.runs[i].swept().is_object()) continue;
      for (const auto& [name, value] : report.runs[i].swept().items()) seen[name].insert(value.dump());
    }
    for (const auto& [name, values] : seen)
      if (values.size() >= 2) knobs[name].insert(method);
  }
  for (const auto& [knob, methods] : knobs) {
    std::vector<size_t> runs;
    bool numeric = true;
    std::vector<double> xs, values;
    for (size_t i : report.ok_runs()) {
      const Run& run = report.runs[i];
      if (!methods.count(run.method) || !run.swept().contains(knob) || !finite(run.metric(report.primary))) continue;
      runs.push_back(i);
      const json& x = run.swept()[knob];
      if (x.is_number())
        xs.push_back(x.get<double>());
      else
        numeric = false;
      values.push_back(*run.metric(report.primary));
    }
    if (runs.size() < 2) continue;
    std::vector<json> floors = floor_layers(report, "value", values);
    bool log_x = false;
    if (numeric) {
      auto [low, high] = std::minmax_element(xs.begin(), xs.end());
      log_x = *low > 0.0 && *high / *low >= 20.0;
    }
    bool log_y = all_positive(values);
    json rows = json::array();
    std::set<std::string> others_seen;
    for (size_t i : runs) {
      const Run& run = report.runs[i];
      json others = json::object();
      for (const auto& [name, value] : run.swept().items())
        if (name != knob) others[name] = value;
      if (report.multi() && knob != "variant") others["variant"] = run.variant;  // one line per variant
      std::string others_text = knobs_text(others);
      if (others_text.empty()) others_text = "\u2014";
      others_seen.insert(run.method + "|" + others_text);
      json row = run_row(report, i);
      row["x"] = numeric ? run.swept()[knob] : json(value_text(run.swept()[knob]));
      row["others"] = others_text;
      row["series"] = run.method + " " + others_text;
      rows.push_back(row);
    }
    json x = numeric ? axis("x", knob + (log_x ? " (log)" : ""), log_x)
                     : json{{"field", "x"}, {"type", "ordinal"}, {"title", knob}, {"sort", nullptr}};
    json y = axis(
        "value", fmt::format("{} ({}{})", report.primary, direction_text(report.primary), log_y ? ", log" : ""), log_y);
    bool dashed = others_seen.size() > methods.size();
    json line_encoding = {{"x", x},
                          {"y", y},
                          {"color", method_colour(report, methods)},
                          {"detail", {{"field", "series"}}},
                          {"order", {{"field", "x"}}}};
    if (dashed) line_encoding["strokeDash"] = {{"field", "others"}, {"type", "nominal"}, {"title", "other knobs"}};
    json layers = json::array();
    layers.push_back(
        {{"data", {{"values", rows}}}, {"mark", {{"type", "line"}, {"strokeWidth", 2}}}, {"encoding", line_encoding}});
    json tip = tooltip(report);
    tip.push_back({{"field", "others"}, {"title", "other knobs"}});
    layers.push_back({{"data", {{"values", rows}}},
                      {"mark", {{"type", "point"}, {"filled", true}, {"size", 50}}},
                      {"encoding", {{"x", x}, {"y", y}, {"color", method_colour(report, methods)}, {"tooltip", tip}}}});
    for (json& layer : floors) layers.push_back(layer);
    std::vector<std::string> method_list(methods.begin(), methods.end());
    json spec = base_spec(fmt::format("{} versus {}", report.primary, knob),
                          fmt::format("swept by {}; one line per method{}", join(method_list, ", "),
                                      dashed ? " and combination of its other swept knobs (dash)" : ""));
    spec["layer"] = layers;
    report.plots.push_back({"plot-sweep-" + file_safe(knob),
                            fmt::format("The primary metric of every run that sweeps {}, against its value; the "
                                        "other knobs of a line are fixed.",
                                        knob),
                            spec});
  }
}

// ---------------------------------------------------------------------------------------------------
// Tables shared by HTML and Markdown: a cell's text and whether it is the best of its column.

struct Cell {
  std::string text;
  bool best = false;
  bool numeric = false;
  bool warn = false;
  std::string undefined = {};  // why the cell has no value: shown as a footnote (and, in HTML, on hover)
};

// The cell of a metric value: the number, or no value with the reason it is undefined.
Cell metric_cell(const Run& run, const std::string& metric) {
  auto value = run.metric(metric);
  if (value) return {num(*value), false, true};
  std::string why = run.undefined_reason(metric);
  return {why.empty() ? "\u2014" : "", false, true, false, why};
}

struct Table {
  std::vector<std::string> header;
  std::vector<std::string> header_notes;  // tooltip text for HTML headers (may be empty)
  std::vector<std::vector<Cell>> rows;
};

const char* const kTimingColumns[][2] = {{"frame_ms_median", "frame ms median"},
                                         {"update_ms_median", "update ms median"},
                                         {"update_ms_min", "update ms min"},
                                         {"render_ms_median", "render ms median"},
                                         {"render_ms_min", "render ms min"}};

Table results_table(const Report& report) {
  Table table;
  table.header = {"method", "label", "swept knobs"};
  table.header_notes = {"", "", ""};
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

  // The best value of each metric column (ties all marked), and the fastest frame, within each variant.
  std::vector<std::map<std::string, double>> bests(report.variants.size());
  for (const std::string& metric : report.metrics) {
    for (size_t i : rows) {
      auto value = report.runs[i].metric(metric);
      if (!finite(value)) continue;
      std::map<std::string, double>& best = bests[report.runs[i].variant_index];
      if (!best.count(metric) || better(metric, *value, best[metric])) best[metric] = *value;
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
    row.push_back({run.method});
    row.push_back({label});
    row.push_back({run.swept_text()});
    if (report.multi()) {
      row.push_back({run.variant});
      const json& pixels = run.receiver_pixels();
      row.push_back({pixels.is_number() ? value_text(pixels) : "\u2014", false, true});
    }
    for (const std::string& metric : report.metrics) {
      auto value = run.metric(metric);
      Cell cell = metric_cell(run, metric);
      if (finite(value) && best.count(metric) && !better(metric, best[metric], *value)) cell.best = true;
      if (metric == "nonfinite_pixels" && value && *value > 0) cell.warn = true;
      row.push_back(cell);
    }
    for (const auto& column : kTimingColumns) {
      auto value = run.timing(column[0]);
      Cell cell{value ? num(*value) : "\u2014", false, true};
      if (std::string(column[0]) == "frame_ms_median" && finite(value) && fastest && *value <= *fastest)
        cell.best = true;
      row.push_back(cell);
    }
    auto prepare = run.top("prepare_seconds");
    row.push_back({prepare ? num(*prepare) : "\u2014", false, true});
    auto memory = run.top("memory_bytes");
    row.push_back({memory ? bytes_text(*memory) : "\u2014", false, true});
    auto rss = run.top("peak_rss_bytes");
    row.push_back({rss ? bytes_text(*rss) : "\u2014", false, true});
    table.rows.push_back(row);
  }
  return table;
}

Table failed_table(const Report& report) {
  Table table;
  table.header = {"method", "label", "swept knobs", "status", "error"};
  if (report.multi()) table.header.insert(table.header.begin() + 3, "variant");
  table.header_notes.assign(table.header.size(), "");
  for (const Run& run : report.runs) {
    if (run.ok) continue;
    std::vector<Cell> row = {
        {run.method}, {run.label}, {run.swept_text()}, {run.status}, {run.error, false, false, true}};
    if (report.multi()) row.insert(row.begin() + 3, Cell{run.variant});
    table.rows.push_back(row);
  }
  return table;
}

// "ours" for a paper column: the run's timing (median when the name has one), metric, or top-level number.
std::optional<double> ours(const Run& run, const std::string& column) {
  if (auto value = run.timing(column + "_median")) return value;
  if (auto value = run.timing(column)) return value;
  if (auto value = run.metric(column)) return value;
  if (auto value = run.top(column)) return value;
  return number(member(run.record, "counters"), column);
}

bool same_value(const json& a, const json& b) {
  if (a.is_number() && b.is_number()) {
    double x = a.get<double>(), y = b.get<double>();
    return x == y || std::abs(x - y) <= 1e-9 * std::max(std::abs(x), std::abs(y));
  }
  return a == b;
}

// The run's resolved knobs as record_matches_filter sees them, with the variant the report assigned
// (an older record names none).
json run_knobs(const Run& run) {
  json knobs = record_knobs(run.record);
  knobs["variant"] = run.variant;
  return knobs;
}

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
        std::optional<double> value = run && run->ok ? ours(*run, column) : std::nullopt;
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

// ---------------------------------------------------------------------------------------------------
// Claims: the paper's statements checked on the stored runs (docs/reports.md, "Claims").

const char* const kClaimQuantities[] = {"render_ms", "update_ms", "frame_ms", "prepare_seconds", "memory_bytes"};
constexpr size_t kLinearMinPoints = 3;

// Not in the metric registry, so better() and direction_text() take them as lower-is-better, as they are.
bool is_claim_quantity(const std::string& name) {
  return std::any_of(std::begin(kClaimQuantities), std::end(kClaimQuantities),
                     [&](const char* quantity) { return name == quantity; });
}

// A claim's metric or quantity of a run: metrics from "metrics"; timings (medians), prepare seconds and
// memory through the paper block's lookup.
std::optional<double> claim_value(const Run& run, const std::string& name) {
  std::optional<double> value = is_claim_quantity(name) ? ours(run, name) : run.metric(name);
  return finite(value) ? value : std::nullopt;
}


std::optional<double> knob_number(const json& knobs, const std::string& name) {
  const json& value = member(knobs, name);
  if (value.is_number()) return value.get<double>();
  if (value.is_string()) {
    const std::string& text = value.get_ref<const std::string&>();
    try {
      size_t used = 0;
      double parsed = std::stod(text, &used);
      if (used == text.size()) return parsed;
    } catch (const std::exception&) {
    }
  }
  return std::nullopt;
}

// The ok runs matching `filter` that have a value of `quantity`, how many failed runs match it, and how
// many ok runs match it with an undefined value (docs/metrics.md, "Undefined values").
std::vector<ClaimPoint> claim_points(const Report& report, const std::string& filter, const std::string& quantity,
                                     size_t& failed, size_t& undefined) {
  std::vector<ClaimPoint> points;
  failed = 0;
  undefined = 0;
  for (size_t i = 0; i < report.runs.size(); ++i) {
    const Run& run = report.runs[i];
    if (!record_matches_filter(run.record, filter)) continue;
    if (!run.ok) {
      ++failed;
      continue;
    }
    if (auto value = claim_value(run, quantity))
      points.push_back({i, *value});
    else if (!run.undefined_reason(quantity).empty())
      ++undefined;
  }
  return points;
}

// The best point (first of equals), or the worst with `worst`.
std::optional<ClaimPoint> extreme(const std::vector<ClaimPoint>& points, const std::string& quantity, bool worst) {
  std::optional<ClaimPoint> found;
  for (const ClaimPoint& point : points) {
    if (!found || (worst ? better(quantity, found->value, point.value)
                         : better(quantity, point.value, found->value)))
      found = point;
  }
  return found;
}

// Least squares y = slope x + intercept; R^2 = 1 - SS_res / SS_tot (1 for an exact fit).
void fit_line(LinearGroup& group) {
  size_t n = group.xs.size();
  if (n < kLinearMinPoints) return;
  double mean_x = 0.0, mean_y = 0.0;
  for (size_t i = 0; i < n; ++i) {
    mean_x += group.xs[i];
    mean_y += group.ys[i];
  }
  mean_x /= static_cast<double>(n);
  mean_y /= static_cast<double>(n);
  double sxx = 0.0, sxy = 0.0, syy = 0.0;
  for (size_t i = 0; i < n; ++i) {
    double dx = group.xs[i] - mean_x, dy = group.ys[i] - mean_y;
    sxx += dx * dx;
    sxy += dx * dy;
    syy += dy * dy;
  }
  if (!(sxx > 0.0)) return;  // x does not vary: no line to fit
  group.fitted = true;
  group.slope = sxy / sxx;
  group.intercept = mean_y - group.slope * mean_x;
  double residual = 0.0;
  for (size_t i = 0; i < n; ++i) {
    double e = group.ys[i] - (group.slope * group.xs[i] + group.intercept);
    residual += e * e;
  }
  group.r2 = syy > 0.0 ? 1.0 - residual / syy : 1.0;
}

void evaluate_best(const Report& report, ClaimResult& result) {
  std::string among = string_member(result.claim, "among"), expect = string_member(result.claim, "expect");
  std::vector<ClaimPoint> points =
      claim_points(report, among, result.quantity, result.failed_first, result.undefined_first);
  std::vector<ClaimPoint> expected, others;
  for (const ClaimPoint& point : points)
    (record_matches_filter(report.runs[point.run].record, expect) ? expected : others).push_back(point);
  result.first_count = expected.size();
  result.other_count = others.size();
  result.first = extreme(expected, result.quantity, false);
  result.other = extreme(others, result.quantity, false);
  if (points.size() < 2 || !result.first || !result.other) return;
  result.verdict = better(result.quantity, result.first->value, result.other->value) ? "confirmed"
                                                                                            : "not confirmed";
}

void evaluate_better(const Report& report, ClaimResult& result) {
  std::vector<ClaimPoint> mine =
      claim_points(report, string_member(result.claim, "run"), result.quantity, result.failed_first,
                   result.undefined_first);
  std::vector<ClaimPoint> theirs =
      claim_points(report, string_member(result.claim, "than"), result.quantity, result.failed_other,
                   result.undefined_other);
  result.first_count = mine.size();
  result.other_count = theirs.size();
  result.first = extreme(mine, result.quantity, true);
  result.other = extreme(theirs, result.quantity, false);
  if (!result.first || !result.other) return;
  result.verdict = better(result.quantity, result.first->value, result.other->value) ? "confirmed"
                                                                                            : "not confirmed";
}

void evaluate_linear(const Report& report, ClaimResult& result) {
  std::string x = string_member(result.claim, "x");
  result.min_r2 = number(result.claim, "min_r2").value_or(0.98);
  std::vector<size_t> runs;
  std::vector<json> knobs;
  std::vector<double> xs, ys;
  for (const ClaimPoint& point : claim_points(report, string_member(result.claim, "among"), result.quantity,
                                             result.failed_first, result.undefined_first)) {
    const Run& run = report.runs[point.run];
    json resolved = run_knobs(run);
    auto x_value = knob_number(resolved, x);
    if (!finite(x_value)) continue;
    resolved.erase(x);
    resolved["method"] = run.method;
    runs.push_back(point.run);
    knobs.push_back(std::move(resolved));
    xs.push_back(*x_value);
    ys.push_back(point.value);
  }
  result.points = runs.size();
  // Group by every other knob (and the method) whose value differs between the runs. receiver_pixels is
  // measured, not set, so it never groups; nor does the variant when x is receiver_pixels (the variants
  // are what makes x vary).
  std::set<std::string> names;
  for (const json& k : knobs)
    for (const auto& [name, value] : k.items()) names.insert(name);
  names.erase("receiver_pixels");
  if (x == "receiver_pixels") names.erase("variant");
  for (const std::string& name : names) {
    std::set<std::string> values;
    for (const json& k : knobs) values.insert(member(k, name).dump());
    if (values.size() > 1) result.group_by.push_back(name);
  }
  if (std::count(result.group_by.begin(), result.group_by.end(), "method")) {
    result.group_by.erase(std::find(result.group_by.begin(), result.group_by.end(), "method"));
    result.group_by.insert(result.group_by.begin(), "method");
  }
  for (size_t p = 0; p < runs.size(); ++p) {
    json key = json::object();
    for (const std::string& name : result.group_by) key[name] = member(knobs[p], name);
    auto group = std::find_if(result.groups.begin(), result.groups.end(),
                              [&](const LinearGroup& g) { return g.knobs == key; });
    if (group == result.groups.end()) {
      result.groups.push_back(LinearGroup{});
      group = std::prev(result.groups.end());
      group->knobs = key;
    }
    group->runs.push_back(runs[p]);
    group->xs.push_back(xs[p]);
    group->ys.push_back(ys[p]);
  }
  bool any = false, all = true;
  for (LinearGroup& group : result.groups) {
    fit_line(group);
    if (!group.fitted) continue;
    group.passed = group.r2 >= result.min_r2;
    any = true;
    all = all && group.passed;
  }
  if (any) result.verdict = all ? "confirmed" : "not confirmed";
}

void evaluate_claims(Report& report) {
  const json& claims = member(report.experiment, "claims");
  if (!claims.is_array()) return;
  for (const json& claim : claims) {
    ClaimResult result;
    result.claim = claim;
    result.kind = string_member(claim, "kind");
    result.verdict = "not measured";
    std::vector<std::string> needed;
    if (result.kind == "best")
      needed = {"metric", "among", "expect"};
    else if (result.kind == "better")
      needed = {"metric", "run", "than"};
    else if (result.kind == "linear")
      needed = {"x", "y", "among"};
    else
      result.problem = "unknown kind '" + result.kind + "' (expected best, better or linear)";
    for (const std::string& field : needed)
      if (!member(claim, field).is_string() && result.problem.empty())
        result.problem = "the claim has no '" + field + "'";
    result.quantity = string_member(claim, result.kind == "linear" ? "y" : "metric");
    if (result.problem.empty()) {
      if (result.kind == "best")
        evaluate_best(report, result);
      else if (result.kind == "better")
        evaluate_better(report, result);
      else
        evaluate_linear(report, result);
    }
    report.claims.push_back(std::move(result));
  }
}

enum class Format { plain, markdown, html };

std::string code_text(const std::string& text, Format format) {
  if (format == Format::markdown) return "`" + text + "`";
  if (format == Format::html) return "<code>" + html_escape(text) + "</code>";
  return text;
}

std::string escaped(const std::string& text, Format format) {
  return format == Format::html ? html_escape(text) : text;
}

std::string runs_text(size_t count) { return fmt::format("{} run{}", count, count == 1 ? "" : "s"); }

// " (1 failed run and 2 runs with an undefined value not counted)", or "" when every matching run counted.
std::string not_counted_note(size_t failed, size_t undefined) {
  std::vector<std::string> parts;
  if (failed) parts.push_back(fmt::format("{} failed run{}", failed, failed == 1 ? "" : "s"));
  if (undefined) parts.push_back(fmt::format("{} with an undefined value", runs_text(undefined)));
  return parts.empty() ? "" : " (" + join(parts, " and ") + " not counted)";
}

// Why the claim has its verdict, with the numbers that decided it.
std::string claim_evidence(const Report& report, const ClaimResult& result, Format format) {
  if (!result.problem.empty()) return escaped(result.problem, format);
  const json& claim = result.claim;
  std::string quantity = escaped(result.quantity, format);
  auto point = [&](const ClaimPoint& p) {
    return escaped(report.display(p.run), format) + " (" + quantity + " " + num(p.value) + ")";
  };
  std::string direction = quantity + ": " + escaped(direction_text(result.quantity), format) + ".";
  const std::string first_note = not_counted_note(result.failed_first, result.undefined_first);
  const std::string other_note = not_counted_note(result.failed_other, result.undefined_other);
  if (result.kind == "best") {
    std::string among = code_text(string_member(claim, "among"), format);
    std::string expect = code_text(string_member(claim, "expect"), format);
    size_t total = result.first_count + result.other_count;
    if (result.verdict == "not measured") {
      return fmt::format("{} with a {} value match{} {}{}, {} of them matching {}: the check needs at least 2, "
                         "one matching {} and one not.",
                         runs_text(total), quantity, total == 1 ? "es" : "", among, first_note,
                         result.first_count, expect, expect);
    }
    bool confirmed = result.verdict == "confirmed";
    const ClaimPoint& best = confirmed ? *result.first : *result.other;
    const ClaimPoint& runner = confirmed ? *result.other : *result.first;
    return fmt::format("best of {} matching {}{}: {}, which {} {}; best run {} it: {}. {}", runs_text(total), among,
                       first_note, point(best), confirmed ? "matches" : "does not match",
                       expect, confirmed ? "not matching" : "matching", point(runner), direction);
  }
  if (result.kind == "better") {
    std::string run = code_text(string_member(claim, "run"), format);
    std::string than = code_text(string_member(claim, "than"), format);
    if (result.verdict == "not measured") {
      return fmt::format("{} with a {} value match{} {}{}, {} match{} {}{}: the check needs at least 1 on each side.",
                         runs_text(result.first_count), quantity, result.first_count == 1 ? "es" : "", run,
                         first_note, result.other_count, result.other_count == 1 ? "es" : "",
                         than, other_note);
    }
    return fmt::format("worst of {} matching {}{}: {}; best of {} matching {}{}: {}. {}",
                       runs_text(result.first_count), run, first_note, point(*result.first),
                       runs_text(result.other_count), than, other_note, point(*result.other),
                       direction);
  }
  std::string x = escaped(string_member(claim, "x"), format);
  std::string among = code_text(string_member(claim, "among"), format);
  std::string grouped = result.group_by.empty() ? "" : ", grouped by " + escaped(join(result.group_by, ", "), format);
  std::string text = fmt::format("{} against {} over {} matching {}{}{}", quantity, x, runs_text(result.points), among,
                                 first_note, grouped);
  if (result.verdict == "not measured") {
    return text + fmt::format(": no {} has {} points with different {} values to fit.",
                              result.group_by.empty() ? "set" : "group", kLinearMinPoints, x);
  }
  std::vector<std::string> parts;
  for (const LinearGroup& group : result.groups) {
    std::string part = group.knobs.empty() ? "" : escaped(knobs_text(group.knobs), format) + ": ";
    if (!group.fitted) {
      part += fmt::format("{} point{}, not fitted", group.xs.size(), group.xs.size() == 1 ? "" : "s");
    } else {
      part += fmt::format("{} = {} \u00d7 {} {} {}, R\u00b2 {} {} {}, n = {}", quantity, num(group.slope), x,
                          group.intercept < 0 ? "\u2212" : "+", num(std::abs(group.intercept)), num(group.r2),
                          group.passed ? "\u2265" : "<", num(result.min_r2), group.xs.size());
    }
    parts.push_back(part);
  }
  return text + ": " + join(parts, "; ") + ".";
}

json claim_point_json(const Report& report, const std::optional<ClaimPoint>& point) {
  if (!point) return nullptr;
  const Run& run = report.runs[point->run];
  json out = {{"key", run.key}, {"label", run.label}, {"value", point->value}};
  if (report.multi()) out["variant"] = run.variant;
  return out;
}

// The claim as experiment.json states it, with "verdict", "evidence" (plain text) and "details".
json claim_json(const Report& report, const ClaimResult& result) {
  json out = result.claim.is_object() ? result.claim : json{{"claim", result.claim}};
  out["verdict"] = result.verdict;
  out["evidence"] = claim_evidence(report, result, Format::plain);
  json details = json::object();
  if (!result.problem.empty()) {
    details["problem"] = result.problem;
  } else if (result.kind == "best") {
    details = {{"direction", direction_text(result.quantity)},
               {"runs", result.first_count + result.other_count},
               {"matching_expect", result.first_count},
               {"failed_runs", result.failed_first},
               {"undefined_runs", result.undefined_first},
               {"best_matching_expect", claim_point_json(report, result.first)},
               {"best_not_matching_expect", claim_point_json(report, result.other)}};
    if (result.verdict != "not measured")
      details["best"] = claim_point_json(report, result.verdict == "confirmed" ? result.first : result.other);
  } else if (result.kind == "better") {
    details = {{"direction", direction_text(result.quantity)},
               {"run_runs", result.first_count},
               {"than_runs", result.other_count},
               {"failed_runs", result.failed_first + result.failed_other},
               {"undefined_runs", result.undefined_first + result.undefined_other},
               {"worst_of_run", claim_point_json(report, result.first)},
               {"best_of_than", claim_point_json(report, result.other)}};
  } else {
    json groups = json::array();
    const LinearGroup* only = nullptr;
    size_t fitted = 0;
    for (const LinearGroup& group : result.groups) {
      json keys = json::array();
      for (size_t i : group.runs) keys.push_back(report.runs[i].key);
      json entry = {{"knobs", group.knobs}, {"n", group.xs.size()}, {"runs", keys}, {"fitted", group.fitted}};
      if (group.fitted) {
        entry.update(
            {{"slope", group.slope}, {"intercept", group.intercept}, {"r2", group.r2}, {"passed", group.passed}});
        only = &group;
        ++fitted;
      }
      groups.push_back(entry);
    }
    details = {{"n", result.points}, {"failed_runs", result.failed_first}, {"undefined_runs", result.undefined_first},
               {"min_r2", result.min_r2},
               {"group_by", result.group_by}, {"groups", groups}};
    if (fitted == 1) details.update({{"slope", only->slope}, {"intercept", only->intercept}, {"r2", only->r2}});
  }
  out["details"] = details;
  return out;
}

// "3 of 4 claims confirmed (1 not confirmed)": the summary's line, empty without claims.
std::string claims_count_text(const Report& report) {
  if (report.claims.empty()) return "";
  size_t confirmed = 0, refuted = 0, unmeasured = 0;
  for (const ClaimResult& result : report.claims) {
    if (result.verdict == "confirmed")
      ++confirmed;
    else if (result.verdict == "not confirmed")
      ++refuted;
    else
      ++unmeasured;
  }
  std::vector<std::string> rest;
  if (refuted) rest.push_back(fmt::format("{} not confirmed", refuted));
  if (unmeasured) rest.push_back(fmt::format("{} not measured", unmeasured));
  return fmt::format("{} of {} claim{} confirmed{}.", confirmed, report.claims.size(),
                     report.claims.size() == 1 ? "" : "s", rest.empty() ? "" : " (" + join(rest, ", ") + ")");
}

// environment.json flattened to "key: value" lines, nested objects with dotted keys.
void flatten(const json& value, const std::string& prefix, std::vector<std::pair<std::string, std::string>>& out) {
  if (value.is_object()) {
    for (const auto& [name, child] : value.items()) flatten(child, prefix.empty() ? name : prefix + "." + name, out);
  } else if (value.is_array() &&
             std::all_of(value.begin(), value.end(), [](const json& v) { return v.is_primitive(); })) {
    std::vector<std::string> parts;
    for (const json& item : value) parts.push_back(value_text(item));
    out.push_back({prefix, join(parts, ", ")});
  } else {
    out.push_back({prefix, value.is_primitive() ? value_text(value) : value.dump()});
  }
}

std::vector<std::pair<std::string, std::string>> experiment_facts(const Report& report) {
  std::vector<std::pair<std::string, std::string>> facts;
  auto add = [&](const std::string& name, const json& value) {
    if (!value.is_null()) {
      std::vector<std::pair<std::string, std::string>> flat;
      flatten(value, name, flat);
      for (auto& entry : flat) facts.push_back(entry);
    }
  };
  add("source", member(report.experiment, "source"));
  add("scene", member(report.experiment, "scene"));
  auto resolution_text = [](const json& resolution) {
    return resolution.is_array() && resolution.size() == 2
               ? value_text(resolution[0]) + " x " + value_text(resolution[1])
               : std::string();
  };
  auto reference_text = [](const Variant& variant) {
    std::string text = variant.reference_key;
    if (variant.noise_floor) text += ", noise floor " + num(*variant.noise_floor);
    const json& passes = member(variant.reference, "passes");
    if (passes.is_number()) text += ", " + value_text(passes) + " passes";
    const json& seconds = member(variant.reference, "seconds");
    if (seconds.is_number()) text += ", " + num(seconds.get<double>()) + " s";
    if (member(variant.reference, "converged") == false) text += ", NOT converged (stopped on its time cap)";
    return text;
  };
  std::string resolution = resolution_text(member(report.experiment, "resolution"));
  if (!report.multi() && !resolution.empty()) facts.push_back({"resolution", resolution});
  add("frames", member(report.experiment, "frames"));
  add("repetitions", member(report.experiment, "repetitions"));
  facts.push_back({"primary metric", report.primary + " (" + direction_text(report.primary) + ")"});
  if (!report.multi()) {
    if (!report.variants.front().reference_key.empty())
      facts.push_back({"reference", reference_text(report.variants.front())});
    return facts;
  }
  // Several variants: each with its resolution, overrides and reference.
  for (const Variant& variant : report.variants) {
    std::vector<std::string> parts;
    if (!resolution_text(variant.resolution).empty()) parts.push_back(resolution_text(variant.resolution));
    if (variant.overrides.is_object() && !variant.overrides.empty())
      parts.push_back("overrides " + variant.overrides.dump());
    if (!variant.listed) parts.push_back("not listed in experiment.json");
    parts.push_back(variant.reference_key.empty() ? "no reference" : "reference " + reference_text(variant));
    facts.push_back({"variant " + variant.name, join(parts, "; ")});
  }
  return facts;
}

// One-line findings at the top: best, fastest, overall front.
std::vector<std::string> findings(const Report& report, bool html) {
  std::vector<std::string> lines;
  auto name = [&](size_t i) {
    std::string label = report.display(i);
    return html ? "<b>" + html_escape(label) + "</b>" : "**" + md_escape(label) + "**";
  };
  lines.push_back(fmt::format("{} runs: {} ok, {} failed{}.", report.runs.size() + report.missing.size(),
                              report.runs.size() - report.failed_count(), report.failed_count(),
                              report.missing.empty() ? "" : fmt::format(", {} not run yet", report.missing.size())));
  size_t empty = 0;
  for (size_t i : report.ok_runs()) empty += report.runs[i].empty_reference ? 1 : 0;
  if (empty)
    lines.push_back(fmt::format("{} run{} against an empty reference (no caustic in view; the experiment sets "
                                "empty_reference_expected): reported as \"empty reference\", not scored, and left out "
                                "of best values, fronts, claims and plots; timings are still shown.",
                                empty, empty == 1 ? "" : "s"));
  if (!report.claims.empty())
    lines.push_back(claims_count_text(report) + (html ? " See <a href=\"#claims\">Claims</a>." : " See Claims below."));
  auto describe = [&](size_t i) {
    auto time = report.runs[i].frame_ms();
    return fmt::format("{} ({}, {} ms)", name(i), primary_caption(report, report.runs[i]),
                       time ? num(*time) : "\u2014");
  };
  // One set of lines per variant (best, fastest, front and noise floor compare runs of one variant only).
  for (size_t v = 0; v < report.variants.size(); ++v) {
    const Variant& variant = report.variants[v];
    std::string in = report.multi() ? " (variant " + variant.name + ")" : "";
    std::optional<size_t> best, fastest;
    for (size_t i : report.ok_runs()) {
      if (report.runs[i].variant_index != v) continue;
      auto value = report.runs[i].metric(report.primary);
      if (finite(value) && (!best || better(report.primary, *value, *report.runs[*best].metric(report.primary))))
        best = i;
      auto time = report.runs[i].frame_ms();
      if (finite(time) && (!fastest || *time < *report.runs[*fastest].frame_ms())) fastest = i;
    }
    if (best) lines.push_back("Best " + report.primary + in + ": " + describe(*best) + ".");
    if (fastest) lines.push_back("Fastest frame" + in + ": " + describe(*fastest) + ".");
    const std::vector<size_t>& overall = report.fronts[v].overall;
    if (!overall.empty()) {
      std::vector<std::string> steps;
      for (size_t i : overall) steps.push_back(describe(i));
      lines.push_back("Pareto front over all methods" + in +
                      " (fastest first, \u25c6 in the table): " + join(steps, " \u2192 ") + ".");
    }
    if (best && report.primary == "relmse" && variant.noise_floor && *variant.noise_floor > 0.0) {
      double value = *report.runs[*best].metric(report.primary);
      double ratio = value / *variant.noise_floor;
      lines.push_back(fmt::format("The reference's noise floor{} {} is {} the best relMSE ({}\u00d7 below it).", in,
                                  num(*variant.noise_floor), ratio >= 10.0 ? "well below" : "NOT well below",
                                  fmt::format("{:.3g}", ratio)));
    }
  }
  return lines;
}

// ---------------------------------------------------------------------------------------------------
// Markdown.

// The distinct reasons of a table's undefined cells, in the order they first appear: its footnotes.
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

void markdown_table(std::string& out, const Table& table) {
  out += "|";
  for (const std::string& name : table.header) out += " " + md_escape(name) + " |";
  out += "\n|";
  for (size_t c = 0; c < table.header.size(); ++c) {
    bool numeric = !table.rows.empty() && std::all_of(table.rows.begin(), table.rows.end(), [&](const auto& row) {
      return c < row.size() && row[c].numeric;
    });
    out += numeric ? "--:|" : "---|";
  }
  out += "\n";
  const std::vector<std::string> notes = undefined_notes(table);
  for (const auto& row : table.rows) {
    out += "|";
    for (const Cell& cell : row) {
      std::string text = cell.best ? "**" + md_escape(cell.text) + "**" : md_escape(cell.text);
      if (!cell.undefined.empty()) text = fmt::format("\u2014 [{}]", note_number(notes, cell.undefined));
      out += " " + text + " |";
    }
    out += "\n";
  }
  out += "\n";
  for (size_t n = 0; n < notes.size(); ++n) out += fmt::format("- [{}] undefined: {}\n", n + 1, md_escape(notes[n]));
  if (!notes.empty()) out += "\n";
}

std::string markdown(const Report& report) {
  std::string out;
  out += fmt::format("# causticbench report: {}\n\n", report.name);
  std::string description = string_member(report.experiment, "description");
  if (!description.empty()) out += description + "\n\n";
  out += "Plots (trade-off, convergence, sweeps) are in report.html.\n\n";

  out += "## Environment\n\n```\n";
  std::vector<std::pair<std::string, std::string>> env;
  flatten(report.environment, "", env);
  size_t width = 0;
  for (const auto& [key, value] : env) width = std::max(width, key.size());
  for (const auto& [key, value] : env) out += fmt::format("{:<{}}  {}\n", key + ":", width + 1, value);
  if (env.empty()) out += "(environment.json missing)\n";
  out += "```\n\n";

  out += "## Experiment\n\n";
  for (const auto& [key, value] : experiment_facts(report)) out += fmt::format("- {}: {}\n", key, value);
  out += "\n";
  for (const std::string& note : report.notes) out += "> **Note:** " + note + "\n\n";
  out += "## Summary\n\n";
  for (const std::string& line : findings(report, false)) out += "- " + line + "\n";
  out += "\n";

  if (!report.claims.empty()) {
    out += "## Claims\n\n";
    out += "The paper's claims (experiment.json \"claims\") checked on the finished runs; see docs/reports.md.\n\n";
    Table claims;
    claims.header = {"claim", "verdict", "evidence"};
    for (const ClaimResult& result : report.claims)
      claims.rows.push_back({{string_member(result.claim, "text", "(no text)")},
                             {result.verdict},
                             {claim_evidence(report, result, Format::markdown)}});
    markdown_table(out, claims);
  }

  out += "## Results\n\n";
  Table results = results_table(report);
  if (results.rows.empty())
    out += "No run finished.\n\n";
  else {
    out +=
        "Bold: best of its column (for metrics the direction is in the header: \u2193 lower is better, "
        "\u2191 higher, \u2192x closest to x); \u25c6: on the Pareto front over all methods.";
    if (report.multi()) out += " With several scene variants, best values and fronts are within each variant.";
    out += "\n\n";
    markdown_table(out, results);
  }
  Table failed = failed_table(report);
  if (!failed.rows.empty()) {
    out += "## Failed runs\n\n";
    markdown_table(out, failed);
  }
  if (!report.missing.empty()) {
    out += "## Runs not run yet\n\n" + join(report.missing, ", ") + "\n\n";
  }
  const json& paper = member(report.experiment, "paper");
  if (paper.is_object()) {
    out += fmt::format("## Paper: {}\n\n", string_member(paper, "title", "published numbers"));
    markdown_table(out, paper_table(report));
  }
  if (!report.thumbnails.empty()) {
    out += "## Images\n\n";
    out += fmt::format(
        "E_c tone-mapped so that the reference's mean is {} grey{}; error = |test \u2212 reference| "
        "luminance, black = 0, yellow = {} or more.\n\n",
        kMiddleGrey, report.multi() ? " (each run exposed like, and compared with, its own variant's reference)" : "",
        report.error_scale_text.empty() ? "max" : report.error_scale_text);
    out += "| run | E_c | error | |\n|---|---|---|---|\n";
    for (const Thumbnail& thumb : report.thumbnails) {
      out += "| " + md_escape(thumb.title) + " | ";
      out += thumb.ec_png.empty() ? "" : "![" + md_escape(thumb.title) + "](report/" + thumb.ec_png + ")";
      out += " | ";
      out += thumb.error_png.empty() ? "" : "![error](report/" + thumb.error_png + ")";
      out += " | " + md_escape(thumb.caption) + (thumb.note.empty() ? "" : "; " + md_escape(thumb.note)) + " |\n";
    }
    out += "\n";
  }
  out += "Files: [report.html](report.html), [results.csv](results.csv), [results.json](results.json).\n";
  return out;
}

// ---------------------------------------------------------------------------------------------------
// HTML.

const char* const kStyle = R"CSS(
:root { --fg:#1d1d1f; --muted:#5f6368; --line:#e3e3e3; --best:#dff3e4; --bad:#fde8e8; --accent:#4c78a8; }
* { box-sizing: border-box; }
body { font: 14px/1.45 system-ui, -apple-system, "Segoe UI", Helvetica, Arial, sans-serif; color: var(--fg);
       margin: 0 auto; padding: 24px 32px 64px; max-width: 1500px; }
h1 { font-size: 24px; margin: 0 0 4px; }
h2 { font-size: 18px; margin: 36px 0 10px; padding-bottom: 4px; border-bottom: 1px solid var(--line); }
p.description { color: var(--muted); margin: 0 0 16px; max-width: 900px; }
nav a { margin-right: 14px; color: var(--accent); text-decoration: none; }
.env { display: grid; grid-template-columns: max-content 1fr; gap: 1px 18px; font: 12px/1.5 ui-monospace, Menlo,
       Consolas, monospace; background: #f7f7f8; border: 1px solid var(--line); border-radius: 6px; padding: 10px 14px; }
.env dt { color: var(--muted); } .env dd { margin: 0; }
.columns { display: grid; grid-template-columns: 1fr 1fr; gap: 16px; }
.note { background: #fff8e1; border: 1px solid #f1d58a; border-radius: 6px; padding: 8px 12px; margin: 8px 0; }
ul.findings { margin: 8px 0; padding-left: 20px; } ul.findings li { margin: 3px 0; }
.scroll { overflow-x: auto; }
table { border-collapse: collapse; font-size: 12.5px; }
th, td { padding: 4px 7px; border-bottom: 1px solid var(--line); text-align: left; white-space: nowrap; }
th { background: #f3f4f6; position: sticky; top: 0; font-weight: 600; white-space: normal; vertical-align: bottom;
     min-width: 48px; }
td.text { white-space: normal; min-width: 90px; max-width: 300px; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
td.best { background: var(--best); font-weight: 700; }
td.warn { background: var(--bad); color: #8a1c1c; white-space: normal; }
td.undefined { background: #f3f4f6; color: var(--muted); cursor: help; }
ol.undefined-notes { color: var(--muted); font-size: 12px; margin: 6px 0 0; padding-left: 22px; max-width: 900px; }
tr:hover td { background-color: #f0f5fb; } tr:hover td.best { background: #c9ebd2; }
.caption { color: var(--muted); font-size: 12px; margin: 6px 0 0; max-width: 900px; }
.plots { display: flex; flex-wrap: wrap; gap: 28px 32px; }
figure.plot { margin: 0; width: 640px; }
.plot-error { color: #8a1c1c; background: var(--bad); padding: 8px; white-space: pre-wrap; }
.grid { display: flex; flex-wrap: wrap; gap: 14px; }
.card { border: 1px solid var(--line); border-radius: 6px; padding: 8px; background: #fafafa; width: 354px; }
.card.reference { border-color: var(--accent); background: #f2f6fb; }
.card .title { font-weight: 600; font-size: 12px; overflow-wrap: anywhere; margin-bottom: 6px; }
.card .pair { display: flex; gap: 6px; }
.card img { width: 166px; image-rendering: pixelated; background: #000; display: block; }
.card .cap { color: var(--muted); font-size: 11px; margin-top: 5px; }
.card .label { color: var(--muted); font-size: 10px; }
.bar { display: flex; align-items: center; gap: 8px; font-size: 12px; color: var(--muted); margin: 4px 0 12px; }
.bar img { width: 256px; height: 12px; }
table.claims td { vertical-align: top; }
table.claims td.claim { white-space: normal; min-width: 220px; max-width: 380px; }
table.claims td.evidence { white-space: normal; min-width: 320px; max-width: 760px; }
table.claims .kind { color: var(--muted); font-size: 11px; }
table.claims code { font-size: 11.5px; background: #f3f4f6; padding: 0 3px; border-radius: 3px; }
.badge { display: inline-block; padding: 1px 9px; border-radius: 10px; font-weight: 600; font-size: 12px;
         color: #fff; white-space: nowrap; }
.badge.confirmed { background: #1e8e3e; } .badge.refuted { background: #d93025; }
.badge.unmeasured { background: #9aa0a6; }
footer { margin-top: 48px; color: var(--muted); font-size: 12px; }
)CSS";

void html_table(std::string& out, const Table& table) {
  out += "<div class=\"scroll\"><table><thead><tr>";
  for (size_t c = 0; c < table.header.size(); ++c) {
    const std::string& note = c < table.header_notes.size() ? table.header_notes[c] : "";
    out += note.empty() ? "<th>" : "<th title=\"" + html_escape(note) + "\">";
    out += html_escape(table.header[c]) + "</th>";
  }
  out += "</tr></thead><tbody>\n";
  const std::vector<std::string> notes = undefined_notes(table);
  for (const auto& row : table.rows) {
    out += "<tr>";
    for (const Cell& cell : row) {
      std::string classes;
      if (cell.numeric)
        classes += " num";
      else if (cell.text.size() > 24)
        classes += " text";
      if (cell.best) classes += " best";
      if (cell.warn) classes += " warn";
      if (!cell.undefined.empty()) classes += " undefined";
      out += classes.empty() ? "<td" : "<td class=\"" + classes.substr(1) + "\"";
      if (!cell.undefined.empty()) {
        // No value, only the footnote's number; hovering shows the reason.
        out += " title=\"undefined: " + html_escape(cell.undefined) + "\">";
        out += fmt::format("<sup>{}</sup></td>", note_number(notes, cell.undefined));
        continue;
      }
      out += ">" + html_escape(cell.text) + "</td>";
    }
    out += "</tr>\n";
  }
  out += "</tbody></table></div>\n";
  if (notes.empty()) return;
  out += "<ol class=\"undefined-notes\">";
  for (const std::string& note : notes) out += "<li>undefined: " + html_escape(note) + "</li>";
  out += "</ol>\n";
}

std::string html(const Report& report) {
  std::string out;
  out += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n";
  out += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  out += "<title>" + html_escape(report.name) + " \u2014 causticbench report</title>\n<style>" + std::string(kStyle) +
         "</style>\n";
  for (const char* file : kVendorFiles) out += fmt::format("<script src=\"report/vendor/{}\"></script>\n", file);
  out += "</head><body>\n";
  out += "<h1>causticbench report: " + html_escape(report.name) + "</h1>\n";
  std::string description = string_member(report.experiment, "description");
  if (!description.empty()) out += "<p class=\"description\">" + html_escape(description) + "</p>\n";
  out += "<nav><a href=\"#environment\">environment</a>";
  if (!report.claims.empty()) out += "<a href=\"#claims\">claims</a>";
  out += "<a href=\"#results\">results</a>";
  if (report.failed_count()) out += "<a href=\"#failed\">failed runs</a>";
  if (member(report.experiment, "paper").is_object()) out += "<a href=\"#paper\">paper</a>";
  if (!report.plots.empty()) out += "<a href=\"#plots\">plots</a>";
  if (!report.thumbnails.empty()) out += "<a href=\"#images\">images</a>";
  out +=
      "<a href=\"results.csv\">results.csv</a><a href=\"results.json\">results.json</a><a "
      "href=\"report.md\">report.md</a></nav>\n";

  out += "<h2 id=\"environment\">Environment</h2>\n<div class=\"columns\"><dl class=\"env\">";
  std::vector<std::pair<std::string, std::string>> env;
  flatten(report.environment, "", env);
  if (env.empty()) out += "<dt>environment</dt><dd>environment.json missing</dd>";
  for (const auto& [key, value] : env) out += "<dt>" + html_escape(key) + "</dt><dd>" + html_escape(value) + "</dd>";
  out += "</dl><dl class=\"env\">";
  for (const auto& [key, value] : experiment_facts(report))
    out += "<dt>" + html_escape(key) + "</dt><dd>" + html_escape(value) + "</dd>";
  out += "</dl></div>\n";
  for (const std::string& note : report.notes) out += "<div class=\"note\">" + html_escape(note) + "</div>\n";
  out += "<ul class=\"findings\">";
  for (const std::string& line : findings(report, true)) out += "<li>" + line + "</li>";
  out += "</ul>\n";

  if (!report.claims.empty()) {
    out += "<h2 id=\"claims\">Claims</h2>\n";
    out +=
        "<div class=\"scroll\"><table class=\"claims\"><thead><tr><th>claim</th><th>verdict</th><th>evidence</th>"
        "</tr></thead><tbody>\n";
    for (const ClaimResult& result : report.claims) {
      const char* badge = result.verdict == "confirmed"       ? "confirmed"
                          : result.verdict == "not confirmed" ? "refuted"
                                                              : "unmeasured";
      out += "<tr><td class=\"claim\">" + html_escape(string_member(result.claim, "text", "(no text)")) +
             "<div class=\"kind\">" + html_escape(result.kind) + "</div></td><td><span class=\"badge " + badge + "\">" +
             html_escape(result.verdict) + "</span></td><td class=\"evidence\">" +
             claim_evidence(report, result, Format::html) + "</td></tr>\n";
    }
    out += "</tbody></table></div>\n";
    out +=
        "<p class=\"caption\">The paper's claims (experiment.json \"claims\") checked on the finished runs: green "
        "confirmed, red not confirmed, grey not measured (too few finished runs match).</p>\n";
  }

  out += "<h2 id=\"results\">Results</h2>\n";
  Table results = results_table(report);
  if (results.rows.empty())
    out += "<p>No run finished.</p>\n";
  else {
    html_table(out, results);
    out +=
        "<p class=\"caption\">Green: best of its column (metric direction in the header: \u2193 lower is better, "
        "\u2191 higher, \u2192x closest to x; hover a header for its definition). \u25c6: on the Pareto front over "
        "all methods. Timings are over the repetitions after one warm-up; metrics are means over frames.";
    if (report.multi())
      out +=
          " With several scene variants, best values and fronts are within each variant (a run competes "
          "only with runs of its own variant).";
    out += "</p>\n";
  }
  Table failed = failed_table(report);
  if (!failed.rows.empty()) {
    out += "<h2 id=\"failed\">Failed runs</h2>\n";
    html_table(out, failed);
  }
  if (!report.missing.empty())
    out += "<p class=\"note\">Not run yet: " + html_escape(join(report.missing, ", ")) + "</p>\n";

  const json& paper = member(report.experiment, "paper");
  if (paper.is_object()) {
    out += "<h2 id=\"paper\">Paper: " + html_escape(string_member(paper, "title", "published numbers")) + "</h2>\n";
    html_table(out, paper_table(report));
    out +=
        "<p class=\"caption\">Each paper row beside the run(s) of that method whose resolved build and render "
        "knobs contain the row's match values. Timings compare the median.</p>\n";
  }

  if (!report.plots.empty()) {
    out += "<h2 id=\"plots\">Plots</h2>\n<div class=\"plots\">\n";
    for (const Plot& plot : report.plots) {
      out += "<figure class=\"plot\"><div class=\"vega-plot\" id=\"" + plot.id +
             "\"></div><figcaption class=\"caption\">" + html_escape(plot.caption) + "</figcaption></figure>\n";
    }
    out += "</div>\n";
  }

  if (!report.thumbnails.empty()) {
    out += "<h2 id=\"images\">Images (first frame)</h2>\n";
    out += fmt::format(
        "<p class=\"caption\">Left: E<sub>c</sub>, exposed so that the reference's mean over the receiver "
        "pixels is {} ({}), sRGB. Right: |test \u2212 reference| as luminance, clamped before resizing.</p>\n",
        kMiddleGrey,
        report.multi() ? "one reference per scene variant; every run is exposed like, and compared with, the "
                         "reference of its own variant"
                       : "same exposure for every run");
    if (!report.error_scale_text.empty()) {
      out += "<div class=\"bar\">error 0 <img src=\"report/error_colour_bar.png\" alt=\"inferno colour scale\"> " +
             html_escape(report.error_scale_text) + " or more</div>\n";
    }
    out += "<div class=\"grid\">\n";
    for (const Thumbnail& thumb : report.thumbnails) {
      out += std::string("<div class=\"card") + (thumb.reference ? " reference" : "") + "\"><div class=\"title\">" +
             html_escape(thumb.title) + "</div><div class=\"pair\">";
      if (!thumb.ec_png.empty())
        out += "<div><img src=\"report/" + thumb.ec_png + "\" alt=\"E_c " + html_escape(thumb.title) +
               "\"><div class=\"label\">E<sub>c</sub></div></div>";
      if (!thumb.error_png.empty())
        out += "<div><img src=\"report/" + thumb.error_png + "\" alt=\"error " + html_escape(thumb.title) +
               "\"><div class=\"label\">|test \u2212 reference|</div></div>";
      out += "</div><div class=\"cap\">" + html_escape(thumb.caption) +
             (thumb.note.empty() ? "" : "<br>" + html_escape(thumb.note)) + "</div></div>\n";
    }
    out += "</div>\n";
  }

  out +=
      "<footer>Written by <code>causticbench report</code> from the stored runs only. Plots: Vega-Lite, rendered "
      "offline by the bundles in report/vendor/.</footer>\n";

  if (!report.plots.empty()) {
    out += "<script>\nconst causticbenchPlots = [\n";
    for (const Plot& plot : report.plots) out += "  [\"" + plot.id + "\", " + script_json(plot.spec) + "],\n";
    out += R"JS(];
for (const [id, spec] of causticbenchPlots) {
  const element = document.getElementById(id);
  const fail = (text) => {
    const message = document.createElement("p");
    message.className = "plot-error";
    message.textContent = "Plot not drawn: " + text;
    element.replaceChildren(message);
  };
  if (typeof vegaEmbed === "undefined") {
    fail("report/vendor/vega*.min.js did not load");
    continue;
  }
  vegaEmbed(element, spec, {renderer: "svg", actions: false}).catch((failure) => fail(String(failure)));
}
</script>
)JS";
  }
  out += "</body></html>\n";
  return out;
}

// ---------------------------------------------------------------------------------------------------
// CSV and JSON.

std::string csv(const Report& report) {
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

std::string results_json(const Report& report) {
  // The records as stored, with the variant and reference each was compared with filled in when an older
  // record lacks them (receiver_pixels then null).
  json runs = json::array();
  for (const Run& run : report.runs) {
    json record = run.record;
    if (!record.contains("variant")) record["variant"] = run.variant;
    if (!record.contains("reference_key")) record["reference_key"] = run.reference_key;
    if (!record.contains("receiver_pixels")) record["receiver_pixels"] = nullptr;
    runs.push_back(record);
  }
  auto keys = [&](const std::vector<size_t>& indices) {
    json out = json::array();
    for (size_t i : indices) out.push_back(report.runs[i].key);
    return out;
  };
  // Fronts are computed within each variant; "overall" and "per_method" list every variant's, in order.
  json fronts = json::object(), per_variant = json::object(), variants = json::array();
  for (size_t v = 0; v < report.variants.size(); ++v) {
    const Variant& variant = report.variants[v];
    json methods = json::object();
    for (const auto& [method, front] : report.fronts[v].per_method) {
      methods[method] = keys(front);
      if (!fronts.contains(method)) fronts[method] = json::array();
      for (size_t i : front) fronts[method].push_back(report.runs[i].key);
    }
    per_variant[variant.name] = {{"overall", keys(report.fronts[v].overall)}, {"per_method", methods}};
    variants.push_back({{"name", variant.name},
                        {"reference_key", variant.reference_key},
                        {"resolution", variant.resolution},
                        {"overrides", variant.overrides},
                        {"listed", variant.listed},
                        {"noise_floor", variant.noise_floor ? json(*variant.noise_floor) : json(nullptr)},
                        {"reference", variant.reference}});
  }
  const Variant& first = report.variants.front();
  json out = {{"experiment", report.experiment},
              {"environment", report.environment},
              {"runs", runs},
              {"missing_runs", report.missing},
              {"reference", {{"key", first.reference_key}, {"record", first.reference}}},
              {"variants", variants},
              {"pareto_front",
               {{"metric", report.primary},
                {"time", "timings.frame_ms_median"},
                {"overall", keys(report.overall_fronts())},
                {"per_method", fronts},
                {"per_variant", per_variant}}}};
  json claims = json::array();
  for (const ClaimResult& result : report.claims) claims.push_back(claim_json(report, result));
  out["claims"] = claims;
  return out.dump(2) + "\n";
}

// ---------------------------------------------------------------------------------------------------

void copy_vendor(const fs::path& target) {
  fs::path source = fs::path(CAUSTICBENCH_SOURCE_DIR) / "reports" / "vendor";
  for (const char* file : kVendorFiles) {
    if (!fs::is_regular_file(source / file)) {
      throw std::runtime_error(
          fmt::format("the vendored Vega bundle {} is missing (report.html needs {} in {}; see "
                      "reports/vendor/README.md)",
                      (source / file).string(), join({"vega.min.js", "vega-lite.min.js", "vega-embed.min.js"}, ", "),
                      source.string()));
    }
  }
  ensure_folder(target.string());
  for (const char* file : kVendorFiles) {
    fs::path temporary = target / (std::string(file) + ".partial");
    fs::copy_file(source / file, temporary, fs::copy_options::overwrite_existing);
    fs::rename(temporary, target / file);
  }
}

}  // namespace

std::vector<size_t> pareto_front(const std::vector<TradeoffPoint>& points,
                                 const std::function<bool(double, double)>& better_value) {
  std::vector<size_t> front;
  auto usable = [&](size_t i) { return std::isfinite(points[i].time) && std::isfinite(points[i].value); };
  for (size_t i = 0; i < points.size(); ++i) {
    if (!usable(i)) continue;
    bool dominated = false;
    for (size_t j = 0; j < points.size() && !dominated; ++j) {
      if (j == i || !usable(j)) continue;
      bool as_fast = points[j].time <= points[i].time;
      bool as_good = !better_value(points[i].value, points[j].value);
      bool strictly = points[j].time < points[i].time || better_value(points[j].value, points[i].value);
      dominated = as_fast && as_good && strictly;
    }
    if (!dominated) front.push_back(i);
  }
  std::stable_sort(front.begin(), front.end(), [&](size_t a, size_t b) {
    if (points[a].time != points[b].time) return points[a].time < points[b].time;
    return better_value(points[a].value, points[b].value);
  });
  return front;
}

ReportSummary write_report(const std::string& experiment_folder) {
  Report report;
  load(report, experiment_folder);
  compute_fronts(report);
  evaluate_claims(report);

  fs::path images = report.folder / "report";
  ensure_folder(images.string());
  copy_vendor(images / "vendor");
  std::set<std::string> written;
  make_images(report, written);
  // Images of runs that are no longer part of the experiment would mislead: remove them.
  for (const auto& entry : fs::directory_iterator(images)) {
    if (entry.is_regular_file() && entry.path().extension() == ".png" &&
        !written.count(entry.path().filename().string()))
      fs::remove(entry.path());
  }
  make_tradeoff_plot(report);
  make_convergence_plot(report);
  make_sweep_plots(report);

  ReportSummary summary;
  summary.html = (report.folder / "report.html").string();
  summary.markdown = (report.folder / "report.md").string();
  summary.csv = (report.folder / "results.csv").string();
  summary.json = (report.folder / "results.json").string();
  summary.runs = report.runs.size();
  summary.failed = report.failed_count();
  summary.missing = report.missing.size();
  summary.plots = report.plots.size();
  summary.claims = report.claims.size();
  for (const ClaimResult& result : report.claims) {
    if (result.verdict == "confirmed") ++summary.claims_confirmed;
    if (result.verdict == "not confirmed") ++summary.claims_not_confirmed;
  }
  write_text_atomically(summary.csv, csv(report));
  write_text_atomically(summary.json, results_json(report));
  write_text_atomically(summary.markdown, markdown(report));
  write_text_atomically(summary.html, html(report));
  return summary;
}

}  // namespace causticbench
