// Reports of a finished experiment: tables, the paper's numbers beside ours, image grids with error
// maps, and Vega-Lite plots of the speed-versus-error trade-off. Reads only the stored results (see
// docs/results-format.md); what each part shows and how it is computed: docs/reports.md.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "reports/claim_verdicts.h"

namespace causticbench {

struct ReportSummary {
  // Paths of the files written into the experiment folder.
  std::string html, markdown, csv, json;
  std::string viewer;       // viewer.html, "" when no run has an image
  size_t viewer_bytes = 0;  // the viewer's pixel files under report/view/
  size_t runs = 0;     // runs with a record.json (ok and failed)
  size_t failed = 0;   // of those, runs whose status is not "ok"
  size_t missing = 0;  // runs named in experiment.json without a record.json (not run yet)
  size_t plots = 0;    // Vega-Lite plots embedded in report.html
  ClaimCounts claims;  // the claims of experiment.json checked, by verdict
};

// Reads experiment.json, environment.json, runs/*/record.json, runs/*/frame_*.exr and the reference
// (../references/<reference_key>/record.json and frame_*.exr), then writes report.html, report.md,
// results.csv, results.json, viewer.html and the report/ folder (thumbnails, error maps, vendored Vega
// bundles, the viewer's pixels under report/view/) into the experiment folder. Throws InputError when the folder is not an experiment results folder,
// std::runtime_error when the vendored Vega bundles are missing from the source tree.
// `viewer_megabytes`: what the viewer's pixel files of frames beyond each run's first may take (docs/reports.md,
// "The viewer"): every k-th frame of every run, the least k that fits; 0 keeps the first frames only.
inline constexpr double kDefaultViewerMegabytes = 100.0;
ReportSummary write_report(const std::string& experiment_folder, double viewer_megabytes = kDefaultViewerMegabytes);

// One run on the error-versus-time plane.
struct TradeoffPoint {
  double time = 0.0;   // frame milliseconds (median)
  double value = 0.0;  // the primary metric
};

// The Pareto front: indices of the points that no other point dominates, sorted by time (then by
// value, best first). Point j dominates point i when j is at least as fast and at least as good
// (!better(i.value, j.value)), and strictly faster or strictly better. `better(a, b)` says whether
// value a is strictly better than b (quantity_better for a registered quantity). Points with a
// non-finite time or value are never on the front.
std::vector<size_t> pareto_front(const std::vector<TradeoffPoint>& points,
                                 const std::function<bool(double, double)>& better);
// The same on any two axes: `better_time` says which x is better (a cost: smaller; psnr: larger).
std::vector<size_t> pareto_front(const std::vector<TradeoffPoint>& points,
                                 const std::function<bool(double, double)>& better_time,
                                 const std::function<bool(double, double)>& better);

}  // namespace causticbench
