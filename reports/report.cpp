// write_report (reports/report.h): the report pipeline from the stored results to the files — load,
// fronts, claims, images, plots, then the four writers — and the copy of the vendored Vega bundles.
// The parts and their order: report_model.h.
#include "reports/report.h"

#include <fmt/format.h>

#include <filesystem>
#include <set>
#include <stdexcept>

#include "core/assets.h"
#include "core/errors.h"
#include "core/files.h"
#include "reports/report_parts.h"

namespace causticbench {

using namespace report_detail;

namespace {

// The vendored bundles: in the source tree this causticbench was built from, or, for an installed one
// whose tree is gone, beside it under share/causticbench/vendor (cmake/sdk.cmake installs them there).
fs::path vendor_folder() {
  const fs::path tree = fs::path(CAUSTICBENCH_SOURCE_DIR) / "reports" / "vendor";
  if (fs::is_directory(tree)) return tree;
  const std::string installed = installed_data_folder();
  return !installed.empty() && fs::is_directory(installed + "/vendor") ? fs::path(installed) / "vendor" : tree;
}

void copy_vendor(const fs::path& target) {
  const fs::path source = vendor_folder();
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
    // Through the store's atomic write: a temporary name of this process's own (two reports of one
    // experiment at once used to share one and fail), a full disk named as ENOSPC and nothing left behind.
    write_file_atomically_with((target / file).string(), [&](const std::string& temporary) {
      fs::copy_file(source / file, temporary, fs::copy_options::overwrite_existing);
    });
  }
}

}  // namespace

ReportSummary write_report(const std::string& experiment_folder, double viewer_megabytes) {
  Report report;
  report.viewer_more_frames_bytes = std::max(0.0, viewer_megabytes) * 1e6;
  load_report(report, experiment_folder);
  score_variant_baselines(report);
  compute_fronts(report);
  compute_views(report);
  evaluate_claims(report);

  fs::path images = report.folder / "report";
  ensure_folder(images.string());
  copy_vendor(images / "vendor");
  std::set<std::string> written;
  make_images(report, written);
  // Images of runs that are no longer part of the experiment would mislead: remove them. Not the
  // temporary files of a write in progress, which may be another process's (a run or report at work).
  for (const auto& entry : fs::directory_iterator(images)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && entry.path().extension() == ".png" && !written.count(name) && !is_partial_file_name(name))
      fs::remove(entry.path());
  }
  make_plots(report);

  ReportSummary summary;
  summary.html = (report.folder / "report.html").string();
  summary.markdown = (report.folder / "report.md").string();
  summary.csv = (report.folder / "results.csv").string();
  summary.json = (report.folder / "results.json").string();
  summary.runs = report.runs.size();
  summary.failed = report.failed_count();
  summary.missing = report.missing.size();
  summary.plots = report.plots.size();
  summary.claims = count_claims(report);
  write_text_atomically(summary.csv, results_csv(report));
  write_text_atomically(summary.json, results_json(report));
  write_text_atomically(summary.markdown, markdown_document(report));
  write_text_atomically(summary.html, html_document(report));
  const fs::path viewer = report.folder / "viewer.html";
  if (!report.viewer.empty()) {
    write_text_atomically(viewer.string(), viewer_document(report));
    summary.viewer = viewer.string();
    summary.viewer_bytes = report.viewer_bytes;
  } else if (fs::exists(viewer)) {
    fs::remove(viewer);
  }
  return summary;
}


}  // namespace causticbench
