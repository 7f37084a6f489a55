// The report's model: what write_report (report.cpp) reads from the stored results and computes before
// any file is written — the runs, the scene variants with their references, the Pareto fronts, the
// checked claims, the thumbnails and the plots. Every part of the pipeline fills or reads a Report:
//   report_loading.cpp   experiment.json, environment.json, the run records and the references
//   pareto_fronts.cpp    the fronts within each variant
//   claims.cpp           the claims of experiment.json checked on the runs
//   report_images.cpp    thumbnails, error maps and the colour bar under report/
//   plots.cpp            the Vega-Lite plots
// and then the writers (markdown_writer.cpp, html_writer.cpp, csv_writer.cpp, json_writer.cpp) turn it
// into files, with the tables (tables.cpp), the summary (findings.cpp) and the claims' evidence
// (claim_evidence.cpp) they share. The functions between these parts: report_parts.h; the helpers
// all of them use: report_text.h (JSON members, numbers as text, escaping) and methods/quantity_registry.h (directions).
// Internal to reports/; the public interface is reports/report.h.
#pragma once

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "store/result_paths.h"
#include "store/run_record.h"
#include "experiments/light_account.h"
#include "metrics/baselines.h"
#include "metrics/confidence.h"
#include "metrics/metrics.h"
#include "reports/cost_views.h"
#include "methods/quantity_registry.h"
#include "reports/claim_verdicts.h"
#include "reports/report_text.h"

namespace causticbench::report_detail {

namespace fs = std::filesystem;
using nlohmann::json;

// Constants of the pictures (docs/reports.md).
constexpr double kMiddleGrey = 0.18;  // the reference's masked mean maps to this after exposure
constexpr double kErrorScale = 1.0;   // error maps saturate at kErrorScale x reference mean
// The vendored Vega bundles (reports/vendor/), copied to report/vendor/ and loaded by report.html.
inline constexpr const char* kVendorFiles[] = {"vega.min.js", "vega-lite.min.js", "vega-embed.min.js"};
// A linear claim needs this many points (with different x) in a group to fit a line.
constexpr size_t kLinearMinPoints = 3;

struct Run {
  std::string key;
  RunRecord record;  // as read (upgraded to the current version); a damaged one: failed, with why
  bool ok = false;   // an ok record of the experiment's current reference: compared with the others
  std::string status, method, label, error;  // status: ok, failed, or stale (ok, but see `stale`)
  // The experiment entry it came from (record "entry"; its label, the method's name by default): the
  // column, front, legend and summary line it belongs to, so that two entries of one method are two.
  std::string entry;
  // Its knobs that differ from its method's declared defaults (report_loading.cpp; the swept ones when
  // this build does not register the method): what names it beside its entry.
  json changed = json::object();
  // Where its light went (experiments/light_account.h), against its variant's reference record: the run's
  // account and each frame's, computed once as the report loads (report_loading.cpp); none for a run that
  // is not ok, against an empty reference, without energy_ratio or a reference with the joint split, or of
  // a method this build does not register.
  std::optional<LightAccount> light_account;
  std::vector<FrameLightAccount> frame_light_accounts;
  // Measured against another reference than the experiment's current one (its settings changed since):
  // listed with the runs that are not compared, never mixed into fronts, claims or views.
  bool stale = false;
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
    return record.metric(name);
  }
  // Why the run has no value of the metric (docs/metrics.md, "Undefined values"); empty when it has one or
  // the record gives no reason.
  std::string undefined_reason(const std::string& name) const {
    if (empty_reference && metric_info(name) && name != "nonfinite_pixels") {
      const std::string& why = record.empty_reference_reason;
      return why.empty() ? "empty reference" : "empty reference: " + why;
    }
    auto found = record.metrics_undefined.find(name);
    return found == record.metrics_undefined.end() ? "" : found->second;
  }
  // The 95 % interval of a metric's value (store/run_record.h): over the run's seeds, zero width when it
  // is deterministic, none for a stochastic run measured once or a metric without a value.
  std::optional<MetricInterval> interval(const std::string& name) const {
    if (!metric(name)) return std::nullopt;
    return record.interval(name);
  }
  // Any registered quantity (methods/quantity_registry.h); a metric through metric() above.
  std::optional<double> quantity(const std::string& name) const {
    if (metric_info(name)) return metric(name);
    return record.quantity(name);
  }
  std::optional<double> timing(const std::string& name) const { return record.timings.field(name); }
  const json& swept() const { return record.swept; }
  std::string swept_text() const { return knobs_text(swept()); }
  std::optional<double> frame_ms() const { return record.quantity("frame_ms"); }
  // Its changed knobs as a person reads them ("its defaults" when none).
  std::string changed_text() const;
  // Its entry and changed knobs, "lpi grid vector (grid_resolution=128, orientation=vector)": how every
  // table, summary line and plot that picks one run names it.
  std::string name() const;
};

// One scene variant of the experiment (experiment.json "variants"; a plain experiment has one,
// "default") with its reference.
struct Variant {
  std::string name, reference_key;
  json resolution, overrides;  // as experiment.json states them (null when it does not)
  bool listed = true;          // false: named by a run record only
  json reference;              // the reference's record.json, or null
  std::optional<double> reference_error;
  json history = json::array();
  // The trivial baselines scored against this variant's reference (metrics/baselines.h), in
  // baselines() order; empty when its reference images cannot be read.
  std::vector<BaselineScores> baselines;
  // The black image's value of a metric, when scored and defined.
  std::optional<double> black(const std::string& metric) const {
    if (baselines.empty()) return std::nullopt;
    auto found = baselines.front().values.find(metric);
    return found == baselines.front().values.end() ? std::nullopt : std::optional<double>(found->second);
  }
};

// Pareto fronts (indices into Report::runs) within one variant: over all runs, and per experiment entry
// (Run::entry: two entries of one method have a front each; results.json keeps the name "per_method").
struct Fronts {
  std::vector<size_t> overall;
  std::map<std::string, std::vector<size_t>> per_method;
};

// A trade-off the experiment names (experiment.json "tradeoffs": [x, y]), with its Pareto fronts per
// variant (index as in Report::variants).
struct Tradeoff {
  std::string x, y;
  std::vector<Fronts> fronts;
};

// The equal-time, equal-error and break-even views of one variant (reports/cost_views.h) on the
// primary metric: `runs[p]` is the run of `points[p]`.
struct VariantViews {
  std::vector<size_t> runs;
  std::vector<CostPoint> points;
  std::vector<double> targets;  // the experiment's error_targets, or default_error_targets()
  std::vector<EqualTimeRow> equal_time;
  std::vector<EqualErrorRow> equal_error;
  std::vector<BreakEven> break_even;
};

struct Thumbnail {
  std::string title, caption, ec_png, error_png, flip_png, note;
  std::string viewer_id;  // a run's entry in the viewer (its key), "" when it has none
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
  std::string kind;
  Verdict verdict = Verdict::not_measured;
  std::string quantity;      // metric (best, better, same) or y (linear, ratio)
  std::string problem;       // a malformed claim: what is wrong with it
  // best: the runs matching `among` (with a value), split by `expect`.
  // better, same, ratio: the runs matching `run` (first) and `than` (other).
  size_t first_count = 0, other_count = 0, failed_first = 0, failed_other = 0;
  size_t undefined_first = 0, undefined_other = 0;  // ok runs that match but whose value is undefined
  std::optional<ClaimPoint> first, other;  // best: best matching / not matching `expect`;
                                           // better: worst of `run`, best of `than`;
                                           // same: the pair farthest beyond (or nearest to) its tolerance;
                                           // ratio: the one run on each side
  // better, same: every (run, than) pair, and how many of them hold (beat / lie within the tolerance).
  size_t pairs = 0, pairs_holding = 0;
  // better, best: the pairs whose 95 % intervals overlap (several seeds): not separated.
  size_t pairs_not_separated = 0;
  // same: the tolerances (absolute, relative to the larger magnitude of the pair; 0 when not given).
  double absolute_tolerance = 0.0, relative_tolerance = 0.0;
  // linear
  std::vector<std::string> group_by;
  std::vector<LinearGroup> groups;
  size_t points = 0;
  double min_r2 = 0.98;
  // ratio: first's value over other's (NAN when not measured), and the bound it must not exceed
  double ratio = NAN, at_most = NAN;
};

struct Report {
  fs::path folder;
  json experiment, environment;
  std::string name, primary;
  std::vector<std::string> metrics;  // metric columns of the tables
  std::vector<Run> runs;             // records found, in the experiment's order
  int seeds = 1;                     // experiment.json "seeds": intervals are shown when above 1
  std::vector<std::string> missing;  // run keys without a record.json
  std::vector<std::string> methods;  // in order of first appearance
  std::vector<std::string> entries;  // the runs' entries (Run::entry), in order of first appearance
  std::vector<Variant> variants;     // never empty; experiment.json's order, then any only runs name
  std::vector<std::string> notes;    // warnings shown at the top of the report

  // Pareto fronts of the primary metric against frame time, one set per variant (index as in variants):
  // a run competes only within its variant. The table's diamond and the summary's front are these.
  std::vector<Fronts> fronts;
  // The experiment's trade-offs (default: frame_ms against the primary metric), each with its fronts.
  std::vector<Tradeoff> tradeoffs;
  // What the views compare (experiment.json; the defaults of experiments/report_settings.h when an older
  // experiment.json has none) and the views, one per variant.
  std::vector<double> budgets_ms, error_targets, total_cost_frames;
  std::vector<VariantViews> views;

  std::vector<Thumbnail> thumbnails;
  std::string error_scale_text;  // what the brightest colour of the error maps means
  bool has_flip_maps = false;    // some run has an HDR-FLIP map (the experiment measures flip)
  // The viewer's index (reports/viewer_data.h): its runs and references; empty when no run has an image.
  json viewer = json::object();
  size_t viewer_bytes = 0;  // the bytes of its pixel files (report/view/)
  double viewer_more_frames_bytes = 100e6;  // what frames beyond each run's first may add (write_report)
  std::vector<Plot> plots;
  std::vector<ClaimResult> claims;

  std::vector<size_t> ok_runs() const {
    std::vector<size_t> indices;
    for (size_t i = 0; i < runs.size(); ++i)
      if (runs[i].ok) indices.push_back(i);
    return indices;
  }
  size_t failed_count() const {
    return static_cast<size_t>(
        std::count_if(runs.begin(), runs.end(), [](const Run& run) { return !run.ok && !run.stale; }));
  }
  size_t stale_count() const {
    return static_cast<size_t>(std::count_if(runs.begin(), runs.end(), [](const Run& run) { return run.stale; }));
  }
  bool multi() const { return variants.size() > 1; }
  fs::path reference_folder(const std::string& key) const {
    return key.empty() ? fs::path() : fs::path(ResultPaths{folder.parent_path().string()}.reference(key));
  }
  bool on_front(size_t run) const {
    if (fronts.empty()) return false;
    const auto& per_method = fronts[runs[run].variant_index].per_method;
    auto it = per_method.find(runs[run].entry);
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
  // The run as a person reads it: its entry and the knobs that differ from its method's defaults
  // (Run::name), and its variant when the experiment has several.
  std::string display(size_t run) const {
    const Run& r = runs[run];
    return multi() ? r.name() + " @" + r.variant : r.name();
  }
};

// Whether two runs' values of a metric are told apart at 95 %: their intervals do not overlap. Without an
// interval on either side (a stochastic run measured once) nothing says otherwise: separated.
inline bool separated(const Run& a, const Run& b, const std::string& metric) {
  const std::optional<MetricInterval> first = a.interval(metric), second = b.interval(metric);
  return !first || !second || !intervals_overlap(*first, *second);
}

// The run's resolved knobs as record_matches_filter sees them, with the variant the report assigned
// (an older record names none).
json run_knobs(const Run& run);
// The record's knobs whose values differ from its method's declared defaults (every set knob of a
// family); the swept knobs when this build does not register the method.
json knobs_changed_from_defaults(const RunRecord& record);

}  // namespace causticbench::report_detail
