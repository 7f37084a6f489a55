// The report's pictures and plots on the synthetic results folder of report_test_support.h: every file
// written, thumbnails and error maps, HDR-FLIP maps, the sweep plots' axes and lines, and (when Chromium
// is installed) that the Vega-Lite plots render offline.
#include <filesystem>
#include <map>
#include <set>
#include <vector>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "reports/report.h"
#include "tests/report_test_support.h"

namespace causticbench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace report_testing;

TEST_F(ReportTest, WritesEveryFile) {
  ReportSummary summary = write_report(folder.string());
  EXPECT_EQ(summary.runs, 7u);
  EXPECT_EQ(summary.failed, 1u);
  EXPECT_EQ(summary.missing, 1u);
  EXPECT_EQ(summary.plots, 7u);  // trade-off, total cost, convergence, error against time, sweeps of photons, k, samples
  for (const std::string& path : {summary.html, summary.markdown, summary.csv, summary.json})
    EXPECT_TRUE(fs::is_regular_file(path)) << path;
  for (const char* file :
       {"reference.png", "pm_1e5.png", "pm_1e5_error.png", "pin_100.png", "pin_100_error.png", "error_colour_bar.png",
        "vendor/vega.min.js", "vendor/vega-lite.min.js", "vendor/vega-embed.min.js"})
    EXPECT_TRUE(fs::is_regular_file(folder / "report" / file)) << file;
  EXPECT_FALSE(fs::exists(folder / "report" / "pin_1600.png")) << "failed runs have no pictures";
  EXPECT_FALSE(fs::exists(folder / "report" / "pm_1e5_flip.png")) << "no FLIP map where flip is not measured";
  // Thumbnails are shrunk to 256 pixels wide, keeping the aspect ratio.
  for (const char* file : {"reference.png", "pm_1e5.png", "pm_1e5_error.png"}) {
    cv::Mat picture = cv::imread((folder / "report" / file).string());
    EXPECT_EQ(picture.cols, 256) << file;
    EXPECT_EQ(picture.rows, 192) << file;
  }
}

// Where the experiment measures flip, every run with an error map also has its HDR-FLIP map, in [0, 1]
// as the metric defines it: black where test and reference agree, brighter where they differ more.
TEST_F(ReportTest, FlipMapsBesideTheErrorMapsWhenFlipIsMeasured) {
  json experiment = json::parse(read_text(folder / "experiment.json"));
  experiment["metrics"].push_back("flip");
  write_json(folder / "experiment.json", experiment);
  ReportSummary summary = write_report(folder.string());
  for (const char* file : {"pm_1e4_flip.png", "pm_1e6_flip.png", "pin_100_flip.png", "flip_colour_bar.png"})
    EXPECT_TRUE(fs::is_regular_file(folder / "report" / file)) << file;
  EXPECT_FALSE(fs::exists(folder / "report" / "reference_flip.png"));
  EXPECT_FALSE(fs::exists(folder / "report" / "pin_1600_flip.png")) << "failed runs have no pictures";
  // pm_1e4 (relmse 0.1) differs more from the reference than pm_1e6 (relmse 0.005): a brighter map.
  auto brightness = [&](const char* file) { return cv::mean(cv::imread((folder / "report" / file).string()))[0]; };
  EXPECT_GT(brightness("pm_1e4_flip.png"), brightness("pm_1e6_flip.png") + 1.0);
  std::string page = read_text(summary.html), md = read_text(summary.markdown);
  EXPECT_NE(page.find("src=\"report/pm_1e4_flip.png\""), std::string::npos);
  EXPECT_NE(page.find("Right: the HDR-FLIP error map"), std::string::npos);
  EXPECT_NE(md.find("| run | E_c | error | FLIP | |"), std::string::npos);
  EXPECT_NE(md.find("![FLIP](report/pm_1e4_flip.png)"), std::string::npos);
}

// The runner stores swept values as text ("400"); the sweep plot must still order them as numbers (400
// after 100, not as text), and runs that differ in a fixed knob (pinhole filtering) are separate lines.
TEST_F(ReportTest, SweepPlotsAreNumericAndSplitByEveryDifferingKnob) {
  for (const char* key : {"pin_100", "pin_400"}) {
    fs::path path = folder / "runs" / key / "record.json";
    json record = json::parse(read_text(path));
    record["swept"]["samples"] = record["swept"]["samples"].dump();  // as text, as the runner writes it
    record["frame"] = {{"samples", record["swept"]["samples"] == "100" ? 100 : 400}};
    record["build"]["filtering"] = std::string(key) == "pin_100" ? "none" : "anisotropic";
    write_json(path, record);
  }
  ReportSummary summary = write_report(folder.string());
  json spec = plot_spec(read_text(summary.html), "plot-sweep-samples");
  ASSERT_TRUE(spec.is_object());
  const json& line = spec["layer"][0];
  EXPECT_EQ(line["encoding"]["x"]["type"], "quantitative") << line["encoding"]["x"].dump();
  std::map<double, std::string> series;  // x -> series
  for (const json& row : line["data"]["values"]) series[row["x"].get<double>()] = row["series"];
  ASSERT_EQ(series.size(), 2u);
  EXPECT_EQ(series[100], "pinhole filtering=none");
  EXPECT_EQ(series[400], "pinhole filtering=anisotropic");
}

// Error against time: the runs that sweep their method's budget knob (photon_map's photons, pinhole's
// samples; MethodInfo::budget_knob), relMSE against precomputation plus the median frame, log axes, one
// line per method and setting of its other knobs, and the reference's own convergence dashed beside them.
TEST_F(ReportTest, ErrorAgainstTimeJoinsTheReferencesConvergence) {
  ReportSummary summary = write_report(folder.string());
  json spec = plot_spec(read_text(summary.html), "plot-error-time");
  ASSERT_TRUE(spec.is_object());
  const json& runs = spec["layer"][0];
  EXPECT_EQ(runs["encoding"]["x"]["scale"]["type"], "log");
  EXPECT_EQ(runs["encoding"]["y"]["scale"]["type"], "log");
  std::map<std::string, size_t> series;
  for (const json& row : runs["data"]["values"]) {
    ++series[row["series"].get<std::string>()];
    // prepare_seconds 0.5 in every fake record, plus the median frame.
    EXPECT_NEAR(row["seconds"].get<double>(), 0.5 + row["frame_ms"].get<double>() / 1000.0, 1e-12) << row.dump();
  }
  const std::map<std::string, size_t> expected = {{"photon_map k=50", 3}, {"photon_map k=10", 1}, {"pinhole", 2}};
  EXPECT_EQ(series, expected);
  const json& reference = spec["layer"][1];
  EXPECT_EQ(reference["data"]["values"].size(), 8u) << "the reference's eight passes";
  EXPECT_EQ(reference["data"]["values"][7]["error"].get<double>(), 4e-3 / 8);

  // Without relMSE among the metrics there is no such plot: the reference estimates no other error.
  json experiment = json::parse(read_text(folder / "experiment.json"));
  experiment["metrics"] = {"psnr", "energy_ratio"};
  experiment["primary_metric"] = "psnr";
  experiment["claims"] = json::array();
  write_json(folder / "experiment.json", experiment);
  EXPECT_FALSE(plot_spec(read_text(write_report(folder.string()).html), "plot-error-time").is_object());
}

// The total-cost plot's data, not only its presence: in the panel of N frames each run's point is its
// prepare seconds plus N times its median frame (the synthetic records: 0.5 s + N x frame_ms) at its
// stored relMSE, and each method's front holds exactly the runs of that method that no other of its runs
// beats on both axes in that panel (computed here from the fixture's own numbers).
TEST_F(ReportTest, TotalCostPlotHoldsEachRunsCostAndEachMethodsFront) {
  ReportSummary summary = write_report(folder.string());
  json spec = plot_spec(read_text(summary.html), "plot-total-cost");
  ASSERT_TRUE(spec.is_object());
  std::map<std::string, const FakeRun*> by_key;
  for (const FakeRun& run : runs)
    if (!run.failed) by_key[run.key] = &run;
  std::map<std::string, std::vector<json>> points, fronts;  // per panel
  for (const json& row : spec["data"]["values"]) (row["kind"] == "run" ? points : fronts)[row["panel"]].push_back(row);
  ASSERT_EQ(points.size(), 4u) << "one panel per default frame count";
  for (const auto& [panel, rows] : points) {
    ASSERT_EQ(rows.size(), by_key.size()) << panel;
    const double frames = rows.front()["frames"].get<double>();
    std::map<std::string, std::set<std::string>> expected_front;  // per method
    for (const json& row : rows) {
      const FakeRun& run = *by_key.at(row["key"]);
      const double total = 0.5 + frames * run.frame_ms / 1000.0;
      EXPECT_NEAR(row["total_s"].get<double>(), total, 1e-12 * total) << panel << " " << run.key;
      EXPECT_EQ(row["y"].get<double>(), run.relmse) << panel << " " << run.key;
      bool beaten = false;
      for (const auto& [key, other] : by_key) {
        const double other_total = 0.5 + frames * other->frame_ms / 1000.0;
        beaten = beaten || (other->method == run.method && other_total <= total && other->relmse <= run.relmse &&
                            (other_total < total || other->relmse < run.relmse));
      }
      if (!beaten) expected_front[run.method].insert(run.key);
    }
    std::map<std::string, std::set<std::string>> front;
    for (const json& row : fronts[panel]) front[row["method"]].insert(row["key"]);
    EXPECT_EQ(front, expected_front) << panel;
  }
}

// The reference's convergence plot holds the reference's history as stored: one point per pass, its
// seconds and estimated error in order (the fixture's eight passes: 0.4 s and 4e-3 / pass each), and the
// red rule at the best relMSE a run reached (pm_1e6's 0.005).
TEST_F(ReportTest, ConvergencePlotHoldsTheReferencesHistory) {
  ReportSummary summary = write_report(folder.string());
  json spec = plot_spec(read_text(summary.html), "plot-convergence");
  ASSERT_TRUE(spec.is_object());
  const json& rows = spec["layer"][0]["data"]["values"];
  ASSERT_EQ(rows.size(), 8u);
  for (int pass = 1; pass <= 8; ++pass) {
    const json& row = rows[pass - 1];
    EXPECT_EQ(row["pass"].get<int>(), pass);
    EXPECT_DOUBLE_EQ(row["seconds"].get<double>(), 0.4 * pass);
    EXPECT_DOUBLE_EQ(row["error_estimate"].get<double>(), 4e-3 / pass);
  }
  bool rule = false;
  for (const json& layer : spec["layer"]) {
    if (!layer.contains("data")) continue;
    for (const json& value : layer["data"]["values"])
      if (value.contains("error_estimate") && value["error_estimate"] == 0.005 && !value.contains("pass")) rule = true;
  }
  EXPECT_TRUE(rule) << "the best run's relMSE, 0.005, as a rule: " << spec["layer"].dump().substr(0, 2000);
}

// The plots must render from file:// with no network: run headless Chromium on report.html.
TEST_F(ReportTest, PlotsRenderOfflineInChromium) {
  const char* chromium = "/usr/bin/chromium";
  if (!fs::exists(chromium)) GTEST_SKIP() << "chromium is not installed (scripts/setup.sh installs it)";
  ReportSummary summary = write_report(folder.string());
  ASSERT_GE(summary.plots, 5u);
  std::string dom = chromium_dom(summary.html);
  ASSERT_FALSE(dom.empty()) << "chromium produced no DOM";
  EXPECT_GE(count(dom, "class=\"marks\""), summary.plots) << "every plot is drawn as an SVG";
  EXPECT_EQ(count(dom, "class=\"plot-error\""), 0u) << "vega-embed reported an error";
  EXPECT_EQ(dom.find("Error"), std::string::npos) << "vega-embed reported an error";
  // The SVG holds the plotted points (one path per symbol) and the reference error label.
  EXPECT_NE(dom.find("reference error"), std::string::npos);
}

}  // namespace
}  // namespace causticbench
