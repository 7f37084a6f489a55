// The report generator with scene variants: each run compared with its own variant's reference,
// Pareto fronts within each variant, linear claims over receiver_pixels, the variant in the CSV and
// tables, and the plots rendering offline. The rest of the report: test_report.cpp.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/errors.h"
#include "core/image.h"
#include "metrics/metrics.h"
#include "reports/report.h"
#include "tests/report_test_support.h"
#include "tests/test_support.h"

namespace causticbench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace report_testing;

struct VariantSpec {
  std::string name;
  int width, height;
  int receiver_pixels;
  float gain;
  std::string reference_key;
  double reference_error;
};

struct VariantFakeRun {
  std::string key, method;
  size_t variant;
  json build, render, swept;
  double relmse, render_ms, noise;
};

Image scaled(Image image, float gain) {
  for (size_t pixel = 0; pixel < image.pixel_count(); ++pixel)
    for (int c = 0; c < image.channels(); ++c) image.at(pixel, c) *= gain;
  return image;
}

class VariantReportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root = fs::temp_directory_path() / ("causticbench_variant_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root);
    folder = root / "results" / "scales";
    variants = {{"96x72", 96, 72, 3000, 1.0f, "ref96", 1e-4},
                {"192x144", 192, 144, 12000, 2.0f, "ref192", 2e-4},
                {"384x288", 384, 288, 48000, 4.0f, "ref384", 4e-4}};
    const double pm_render[] = {10.0, 40.0, 11.0}, pm_relmse[] = {0.02, 0.02, 0.01}, pin_relmse[] = {0.01, 0.03, 0.05};
    const char* const suffix[] = {"96", "192", "384"};
    for (size_t v = 0; v < variants.size(); ++v) {
      runs.push_back({std::string("pin_") + suffix[v],
                      "pinhole",
                      v,
                      {{"filtering", "none"}},
                      {{"samples", 1000}},
                      {{"samples", 1000}},
                      pin_relmse[v],
                      0.002 * variants[v].receiver_pixels + 1.0,
                      0.0});
      runs.push_back({std::string("pm_") + suffix[v],
                      "photon_map",
                      v,
                      {{"photons", 100000}},
                      {{"k", 50}},
                      {{"photons", 100000}},
                      pm_relmse[v],
                      pm_render[v],
                      0.1});
    }
    runs.push_back(
        {"pin100_96", "pinhole", 0, {{"filtering", "none"}}, {{"samples", 100}}, {{"samples", 100}}, 0.5, 8.0, 0.3});

    json keys = json::array(), listed = json::array();
    for (const VariantFakeRun& run : runs) keys.push_back(run.key);
    for (const VariantSpec& variant : variants) {
      listed.push_back({{"name", variant.name},
                        {"overrides", {{"resolution", {variant.width, variant.height}}}},
                        {"resolution", {variant.width, variant.height}},
                        {"reference_key", variant.reference_key}});
      fs::path reference = root / "results" / "references" / variant.reference_key;
      json history = json::array();
      for (int pass = 1; pass <= 4; ++pass)
        history.push_back({{"pass", pass}, {"seconds", 0.5 * pass}, {"error_estimate", 4.0 * variant.reference_error / pass}});
      write_json(reference / "record.json", {{"method", "reference"},
                                             {"passes", 4},
                                             {"seconds", 2.0},
                                             {"error_estimate", variant.reference_error},
                                             {"history", history}});
      write_exr(scaled(blob(0.0, variant.width, variant.height), variant.gain),
                (reference / "frame_0000.exr").string());
    }
    const VariantSpec& first = variants.front();
    write_json(folder / "experiment.json", {{"name", "scales"},
                                            {"scene", "configs/scenes/ring.yaml"},
                                            {"resolution", {first.width, first.height}},
                                            {"overrides", listed[0]["overrides"]},
                                            {"variants", listed},
                                            {"frames", {0}},
                                            {"repetitions", 3},
                                            {"metrics", {"relmse"}},
                                            {"primary_metric", "relmse"},
                                            {"reference_key", first.reference_key},
                                            {"runs", keys},
                                            {"claims", claims()}});
    write_json(folder / "environment.json", {{"machine", "test-host"}});
    for (const VariantFakeRun& run : runs) write_run(run);
  }

  //   0 render_ms linear in receiver_pixels over the pinhole samples=1000 runs: exact, one group   confirmed
  //   1 render_ms linear in receiver_pixels over photon_map: 10, 40, 11                          refuted
  //   2 frame_ms linear in samples over pinhole: grouped by variant (not by receiver_pixels);
  //     at most 2 points per group                                                               not measured
  //   3 better frame_ms: variant=96x72 pinhole samples=1000 (8 ms) than any 384x288 run (12 ms)  confirmed
  static json claims() {
    return json::array({{{"text", "Pinhole render time is linear in the receiver pixels"},
                         {"kind", "linear"},
                         {"x", "receiver_pixels"},
                         {"y", "render_ms"},
                         {"among", "method=pinhole,samples=1000"}},
                        {{"text", "Photon map render time is linear in the receiver pixels"},
                         {"kind", "linear"},
                         {"x", "receiver_pixels"},
                         {"y", "render_ms"},
                         {"among", "method=photon_map"}},
                        {{"text", "Pinhole time is linear in samples"},
                         {"kind", "linear"},
                         {"x", "samples"},
                         {"y", "frame_ms"},
                         {"among", "method=pinhole"}},
                        {{"text", "Small pinhole beats every large run"},
                         {"kind", "better"},
                         {"metric", "frame_ms"},
                         {"run", "variant=96x72,method=pinhole,samples=1000"},
                         {"than", "variant=384x288"}}});
  }

  std::string label(const VariantFakeRun& run) const {
    std::string text = run.method;
    for (const auto& [name, value] : run.swept.items()) text += " " + name + "=" + value.dump();
    return text + " @" + variants[run.variant].name;  // as the runner labels runs of several variants
  }

  void write_run(const VariantFakeRun& run) const {
    const VariantSpec& variant = variants[run.variant];
    fs::path run_folder = folder / "runs" / run.key;
    fs::create_directories(run_folder);
    const double frame_ms = run.render_ms + 1.0;
    RunRecord record;  // as the runner builds it (store/run_record.h)
    record.key = run.key;
    record.method = run.method;
    record.label = label(run);
    record.variant = variant.name;
    record.reference_key = variant.reference_key;
    record.receiver_pixels = variant.receiver_pixels;
    record.build = run.build;
    record.render = run.render;
    record.swept = run.swept;
    FrameRecord frame;
    frame.image = "frame_0000.exr";
    frame.update_ms = {1.0};
    frame.render_ms = {run.render_ms};
    frame.metrics = {{"relmse", run.relmse}};
    record.frames = {frame};
    record.timings = {1.0, 1.0, run.render_ms, run.render_ms, frame_ms, frame_ms, std::nullopt, std::nullopt};
    record.metrics = frame.metrics;
    write_json(run_folder / "record.json", record.to_json());
    write_exr(scaled(blob(run.noise, variant.width, variant.height), variant.gain),
              (run_folder / "frame_0000.exr").string());
  }

  void TearDown() override {
    if (!::testing::Test::HasFailure() && !getenv("CAUSTICBENCH_KEEP_REPORT")) fs::remove_all(root);
  }

  fs::path root, folder;
  std::vector<VariantSpec> variants;
  std::vector<VariantFakeRun> runs;
};

// Largest channel value of a PNG (an inferno error map is (4, 0, 0) in BGR where the error is zero).
int brightest(const fs::path& path) {
  cv::Mat picture = cv::imread(path.string());
  if (picture.empty()) return -1;
  double low = 0.0, high = 0.0;
  cv::minMaxLoc(picture.reshape(1), &low, &high);
  return static_cast<int>(high);
}

TEST_F(VariantReportTest, EachRunIsComparedWithItsOwnVariantsReference) {
  ReportSummary summary = write_report(folder.string());
  std::string md = read_text(summary.markdown), page = read_text(summary.html);
  EXPECT_EQ(md.find("but the reference is"), std::string::npos) << md;
  EXPECT_EQ(page.find("but the reference is"), std::string::npos);
  EXPECT_FALSE(fs::exists(folder / "report" / "reference.png")) << "one reference thumbnail per variant instead";
  for (const VariantSpec& variant : variants) {
    fs::path reference = folder / "report" / ("reference_" + variant.name + ".png");
    ASSERT_TRUE(fs::is_regular_file(reference)) << reference;
    EXPECT_NE(md.find("| reference " + variant.name + " | ![reference " + variant.name + "](report/reference_" +
                      variant.name + ".png)"),
              std::string::npos)
        << md;
    EXPECT_NE(page.find(">reference " + variant.name + "</div>"), std::string::npos);
  }
  for (const VariantFakeRun& run : runs) {
    fs::path error = folder / "report" / (run.key + "_error.png");
    ASSERT_TRUE(fs::is_regular_file(error)) << run.key << " has an error map against its own reference";
    if (run.noise == 0.0) {
      // Identical to its own reference: a black error map, and the same thumbnail as that reference
      // (the same exposure, from its own reference's mean).
      EXPECT_LE(brightest(error), 5) << run.key;
      EXPECT_EQ(read_text(folder / "report" / (run.key + ".png")),
                read_text(folder / "report" / ("reference_" + variants[run.variant].name + ".png")))
          << run.key;
    } else {
      EXPECT_GT(brightest(error), 50) << run.key << " is noisy";
    }
  }
  // The colour bar names each variant's saturation value: the reference means differ by the gains.
  EXPECT_NE(md.find("the mean of the run's own reference (96x72 "), std::string::npos) << md;
  // Each variant's reference error in the facts, the findings and the plots.
  EXPECT_NE(md.find("- variant 192x144: 192 x 144; overrides {\"resolution\":[192,144]}; reference ref192, "
                    "reference error 0.0002, 4 passes, 2 s"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("The reference's estimated error (variant 384x288) 0.0004 is well below the best relMSE"),
            std::string::npos)
      << md;
  for (const VariantSpec& variant : variants)
    EXPECT_NE(page.find("reference error " + variant.name), std::string::npos) << variant.name;
  json results = json::parse(read_text(summary.json));
  ASSERT_EQ(results["variants"].size(), 3u);
  EXPECT_EQ(results["variants"][1]["reference_key"], "ref192");
  EXPECT_EQ(results["variants"][1]["error_estimate"], 2e-4);
  EXPECT_EQ(results["reference"]["key"], "ref96") << "the first variant's, as before";
}

TEST_F(VariantReportTest, ParetoFrontsAreWithinEachVariant) {
  ReportSummary summary = write_report(folder.string());
  std::vector<std::string> lines = split(read_text(summary.csv), '\n');
  ASSERT_EQ(lines.size(), 1u + runs.size());
  std::vector<std::string> header = csv_cells(lines[0]);
  auto column = [&](const std::string& name) {
    auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name << " missing from " << lines[0];
    return static_cast<size_t>(it - header.begin());
  };
  size_t key = column("key"), membership = column("pareto_front");
  ASSERT_LT(std::max(key, membership), header.size());
  std::map<std::string, std::string> expected = {{"pin_96", "overall"},  {"pm_96", "method"},   {"pin100_96", ""},
                                                 {"pin_192", "overall"}, {"pm_192", "overall"}, {"pin_384", "method"},
                                                 {"pm_384", "overall"}};
  for (size_t row = 1; row < lines.size(); ++row) {
    std::vector<std::string> cells = csv_cells(lines[row]);
    ASSERT_EQ(cells.size(), header.size()) << lines[row];
    EXPECT_EQ(cells[membership], expected.at(cells[key])) << cells[key];
  }

  json results = json::parse(read_text(summary.json));
  const json& front = results["pareto_front"];
  EXPECT_EQ(front["overall"], json({"pin_96", "pin_192", "pm_192", "pm_384"}));
  EXPECT_EQ(front["per_method"]["pinhole"], json({"pin_96", "pin_192", "pin_384"}));
  EXPECT_EQ(front["per_method"]["photon_map"], json({"pm_96", "pm_192", "pm_384"}));
  ASSERT_TRUE(front.contains("per_variant")) << front.dump(2);
  EXPECT_EQ(front["per_variant"]["96x72"]["overall"], json({"pin_96"}));
  EXPECT_EQ(front["per_variant"]["192x144"]["overall"], json({"pin_192", "pm_192"}));
  EXPECT_EQ(front["per_variant"]["384x288"]["overall"], json({"pm_384"}));
  EXPECT_EQ(front["per_variant"]["384x288"]["per_method"]["pinhole"], json({"pin_384"}));

  // The table marks the fronts and the fastest frame within each variant.
  std::string md = read_text(summary.markdown);
  EXPECT_NE(md.find("| pinhole | pinhole samples=1000 @192x144 \u25c6 | filtering=none | 192x144 | 12000 | 0.03 | \u2014 | "
                    "**26** |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("Pareto front over all methods (variant 192x144) (fastest first, \u25c6 in the table): "
                    "**pinhole (filtering=none) @192x144** (relmse 0.03, 26 ms) \u2192 **photon_map (photons=100000) "
                    "@192x144** (relmse 0.02, 41 ms)."),
            std::string::npos)
      << md;
}

TEST_F(VariantReportTest, LinearClaimsOverReceiverPixels) {
  ReportSummary summary = write_report(folder.string());
  json results = json::parse(read_text(summary.json));
  const json& claims = results["claims"];
  ASSERT_EQ(claims.size(), 4u);
  std::vector<std::string> verdicts;
  for (const json& claim : claims) verdicts.push_back(claim["verdict"]);
  EXPECT_EQ(verdicts, (std::vector<std::string>{"confirmed", "refuted", "not measured", "confirmed"}));
  // Exactly linear: one group over the three variants (the variant does not split it).
  const json& exact = claims[0]["details"];
  EXPECT_EQ(exact["group_by"], json::array()) << exact.dump(2);
  EXPECT_EQ(exact["n"], 3);
  EXPECT_NEAR(exact["slope"].get<double>(), 0.002, 1e-12);
  EXPECT_NEAR(exact["intercept"].get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(exact["r2"].get<double>(), 1.0, 1e-12);
  // 10, 40, 11 ms at 3000, 12000, 48000 pixels (means 21000, 61/3): Sxy = 18000 x 31/3 - 9000 x 59/3
  // - 27000 x 28/3 = -243000, Sxx = 1.134e9, Syy = (961 + 3481 + 784) / 9 = 5226/9: R^2 = 0.0897.
  const json& bent = claims[1]["details"];
  EXPECT_EQ(bent["group_by"], json::array());
  EXPECT_EQ(bent["n"], 3);
  EXPECT_NEAR(bent["r2"].get<double>(), 243000.0 * 243000.0 / (1.134e9 * (5226.0 / 9.0)), 1e-12);
  EXPECT_EQ(claims[1]["details"]["groups"][0]["passed"], false);
  // Against samples the variants do split the runs; receiver_pixels (measured) never groups.
  EXPECT_EQ(claims[2]["details"]["group_by"], json({"variant"}));
  EXPECT_EQ(claims[2]["details"]["groups"].size(), 3u);
  // Filters may name the variant.
  EXPECT_EQ(claims[3]["details"]["worst_of_run"]["key"], "pin_96");
  EXPECT_EQ(claims[3]["details"]["best_of_than"]["key"], "pm_384");
  EXPECT_EQ(claims[3]["details"]["best_of_than"]["variant"], "384x288");
  std::string md = read_text(summary.markdown);
  EXPECT_NE(md.find("| Pinhole render time is linear in the receiver pixels | confirmed | render_ms against "
                    "receiver_pixels over 3 runs matching `method=pinhole,samples=1000`: render_ms = 0.002 \u00d7 "
                    "receiver_pixels + 1, R\u00b2 1 \u2265 0.98, n = 3. |"),
            std::string::npos)
      << md;
}

TEST_F(VariantReportTest, CsvAndTablesHaveTheVariant) {
  ReportSummary summary = write_report(folder.string());
  std::vector<std::string> lines = split(read_text(summary.csv), '\n');
  std::vector<std::string> header = csv_cells(lines[0]);
  size_t key = std::find(header.begin(), header.end(), "key") - header.begin();
  size_t variant = std::find(header.begin(), header.end(), "variant") - header.begin();
  size_t pixels = std::find(header.begin(), header.end(), "receiver_pixels") - header.begin();
  ASSERT_LT(variant, header.size()) << lines[0];
  ASSERT_LT(pixels, header.size()) << lines[0];
  ASSERT_EQ(lines.size(), 1u + runs.size());
  for (size_t row = 1; row < lines.size(); ++row) {
    std::vector<std::string> cells = csv_cells(lines[row]);
    auto run = std::find_if(runs.begin(), runs.end(), [&](const VariantFakeRun& r) { return r.key == cells[key]; });
    ASSERT_NE(run, runs.end()) << lines[row];
    EXPECT_EQ(cells[variant], variants[run->variant].name);
    EXPECT_EQ(cells[pixels], std::to_string(variants[run->variant].receiver_pixels));
  }
  std::string md = read_text(summary.markdown);
  EXPECT_NE(md.find("| method | label | knobs | variant | receiver pixels | relmse \u2193 |"), std::string::npos)
      << md;
  EXPECT_NE(md.find("| photon_map | photon_map photons=100000 @96x72 | photons=100000 | 96x72 | 3000 | 0.02 |"),
            std::string::npos)
      << md;
  json results = json::parse(read_text(summary.json));
  EXPECT_EQ(results["runs"][0]["variant"], "96x72");
  EXPECT_EQ(results["runs"][0]["receiver_pixels"], 3000);
}

TEST_F(VariantReportTest, PlotsRenderOfflineInChromium) {
  if (!fs::exists("/usr/bin/chromium")) GTEST_SKIP() << "chromium is not installed (scripts/setup.sh installs it)";
  ReportSummary summary = write_report(folder.string());
  EXPECT_EQ(summary.plots, 4u);  // trade-off, convergence (three lines), error against time, the sweep of samples
  std::string dom = chromium_dom(summary.html);
  ASSERT_FALSE(dom.empty()) << "chromium produced no DOM";
  EXPECT_GE(count(dom, "class=\"marks\""), summary.plots) << "every plot is drawn as an SVG";
  EXPECT_EQ(count(dom, "class=\"plot-error\""), 0u) << "vega-embed reported an error";
  EXPECT_EQ(dom.find("Error"), std::string::npos) << "vega-embed reported an error";
  EXPECT_NE(dom.find("reference error 384x288"), std::string::npos);
}

}  // namespace
}  // namespace causticbench
