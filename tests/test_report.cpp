// The report generator on a synthetic results folder: files, CSV values, Markdown tables, the paper
// block, the claims, the Pareto front, and (when Chromium is installed) that the Vega-Lite plots render
// offline.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/image.h"
#include "metrics/metrics.h"
#include "reports/report.h"
#include "tests/test_support.h"

namespace causticbench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

void write_json(const fs::path& path, const json& value) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << value.dump(2);
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::string part;
  std::stringstream stream(text);
  while (std::getline(stream, part, separator)) parts.push_back(part);
  return parts;
}

// One CSV line (RFC 4180 quoting, no embedded newlines).
std::vector<std::string> csv_cells(const std::string& line) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    char c = line[i];
    if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
      cells.back() += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      cells.emplace_back();
    } else {
      cells.back() += c;
    }
  }
  return cells;
}

size_t count(const std::string& text, const std::string& word) {
  size_t n = 0;
  for (size_t at = text.find(word); at != std::string::npos; at = text.find(word, at + word.size())) ++n;
  return n;
}

// A caustic-like blob on a dark receiver; `noise` adds a deterministic per-pixel error.
// 384 x 288, so that thumbnails are shrunk to 256 x 192.
Image blob(double noise, int width = 384, int height = 288) {
  Image image(width, height, 3);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      double dx = (x - 0.47 * width) / (0.12 * width), dy = (y - 0.45 * height) / (0.1 * height);
      double value = 0.05 + 4.0 * std::exp(-(dx * dx + dy * dy));
      double jitter = noise * std::sin(12.9898 * x + 78.233 * y) * value;
      for (int c = 0; c < 3; ++c) image.at(static_cast<size_t>(y) * width + x, c) = static_cast<float>(value + jitter);
    }
  }
  return image;
}

struct FakeRun {
  std::string key, method;
  json build, render, swept;
  double relmse, frame_ms;
  bool failed = false;
};

// "photon_map k=50 photons=100000", as the experiment runner labels runs.
std::string label(const FakeRun& run) {
  std::string text = run.method;
  for (const auto& [name, value] : run.swept.items()) text += " " + name + "=" + value.dump();
  return text;
}

const char* const kFailure = "out of memory: photon buffer exceeded 2 GiB, at 1600 \"samples\"";

// The synthetic experiment: two methods with sweeps, one failed run, one run not yet run.
//   photon_map photons sweep at k=50:   (5 ms, 0.1)  (12 ms, 0.02)  (40 ms, 0.005)   all on the front
//   photon_map photons=1e5 k=10:        (14 ms, 0.05)                               dominated by (12, 0.02)
//   pinhole samples=100 / 400:          (8 ms, 0.03) (30 ms, 0.04)                   400 dominated by 100
//   pinhole samples=1600: failed
// (render_ms median = 0.75 x frame ms.) Its claims and their verdicts:
//   0 best relmse among photon_map, expect k=50: 0.005 (k=50) beats 0.05 (k=10)          confirmed
//   1 best psnr among pinhole, expect samples=400: samples=100 has the higher PSNR       not confirmed
//   2 better frame_ms, photons=10000 (5 ms) than every pinhole run (best 8 ms)           confirmed
//   3 better relmse, samples=1600 (failed only) than photon_map                          not measured
//   4 linear render_ms in photons among photon_map: grouped by k; k=50 has 3 points,
//     R^2 = 256/259 >= 0.98; k=10 has 1 point and is not fitted                          confirmed
//   5 linear frame_ms in samples among pinhole: 2 ok points                              not measured
//   6 linear render_ms in photons among photon_map,k=50 with min_r2 0.99: 256/259 < 0.99 not confirmed
class ReportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root = fs::temp_directory_path() / ("causticbench_report_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root);
    folder = root / "results" / "wand_cup";
    runs = {
        {"pm_1e4",
         "photon_map",
         {{"photons", 10000}, {"seed", 1}},
         {{"k", 50}, {"max_radius", 0.1}},
         {{"photons", 10000}, {"k", 50}},
         0.1,
         5.0},
        {"pm_1e5",
         "photon_map",
         {{"photons", 100000}, {"seed", 1}},
         {{"k", 50}, {"max_radius", 0.1}},
         {{"photons", 100000}, {"k", 50}},
         0.0123456789012345,
         12.0},
        {"pm_1e6",
         "photon_map",
         {{"photons", 1000000}, {"seed", 1}},
         {{"k", 50}, {"max_radius", 0.1}},
         {{"photons", 1000000}, {"k", 50}},
         0.005,
         40.0},
        {"pm_1e5_k10",
         "photon_map",
         {{"photons", 100000}, {"seed", 1}},
         {{"k", 10}, {"max_radius", 0.1}},
         {{"photons", 100000}, {"k", 10}},
         0.05,
         14.0},
        {"pin_100", "pinhole", {{"resolution", 64}}, {{"samples", 100}}, {{"samples", 100}}, 0.03, 8.0},
        {"pin_400", "pinhole", {{"resolution", 64}}, {{"samples", 400}}, {{"samples", 400}}, 0.04, 30.0},
        {"pin_1600", "pinhole", {{"resolution", 64}}, {{"samples", 1600}}, {{"samples", 1600}}, 0.0, 0.0, true},
    };
    json keys = json::array();
    for (const FakeRun& run : runs) keys.push_back(run.key);
    keys.push_back("never_ran");
    write_json(folder / "experiment.json", {{"name", "wand_cup"},
                                            {"source", "configs/experiments/wand_cup.yaml"},
                                            {"description", "Synthetic experiment of the report test."},
                                            {"scene", "configs/scenes/ring.yaml"},
                                            {"resolution", {384, 288}},
                                            {"frames", {0}},
                                            {"repetitions", 3},
                                            {"metrics", {"relmse", "rmse", "psnr", "energy_ratio"}},
                                            {"primary_metric", "relmse"},
                                            {"reference_key", "ref123"},
                                            {"runs", keys},
                                            {"paper",
                                             {{"title", "Wand 2003, Fig. 4"},
                                              {"columns", {"render_ms"}},
                                              {"rows",
                                               {{{"method", "pinhole"},
                                                 {"match", {{"samples", 100}}},
                                                 {"values", {{"render_ms", 135}}},
                                                 {"note", "Radeon 9700"}},
                                                {{"method", "pinhole"},
                                                 {"match", {{"samples", 6400}}},
                                                 {"values", {{"render_ms", 900}}},
                                                 {"note", "the largest cup"}},
                                                {{"method", "photon_map"},
                                                 {"match", {{"photons", 100000}, {"k", 50}}},
                                                 {"values", {{"render_ms", 20}}},
                                                 {"note", "CPU"}}}}}},
                                            {"claims", claims()}});
    write_json(folder / "environment.json", {{"machine", "test-host"},
                                             {"cpu", {{"model", "Synthetic CPU"}, {"cores", 16}}},
                                             {"threads", 16},
                                             {"compiler", "GCC 12"},
                                             {"build_type", "Release"},
                                             {"git_revision", "abcdef123456"}});
    fs::path reference = root / "results" / "references" / "ref123";
    json history = json::array();
    for (int pass = 1; pass <= 8; ++pass)
      history.push_back(
          {{"pass", pass}, {"photons", 2000000 * pass}, {"seconds", 0.4 * pass}, {"noise_floor", 4e-3 / pass}});
    write_json(reference / "record.json",
               {{"method", "reference"}, {"passes", 8}, {"seconds", 3.2}, {"noise_floor", 5e-4}, {"history", history}});
    fs::create_directories(reference);
    write_exr(blob(0.0), (reference / "frame_0000.exr").string());

    for (const FakeRun& run : runs) write_run(run);
  }

  static json claims() {
    return json::array(
        {{{"text", "More photons at k=50 give the least error"},
          {"kind", "best"},
          {"metric", "relmse"},
          {"among", "method=photon_map"},
          {"expect", "k=50"}},
         {{"text", "400 samples give the sharpest image"},
          {"kind", "best"},
          {"metric", "psnr"},
          {"among", "method=pinhole"},
          {"expect", "samples=400"}},
         {{"text", "10^4 photons are faster than any pinhole run"},
          {"kind", "better"},
          {"metric", "frame_ms"},
          {"run", "method=photon_map,photons=10000"},
          {"than", "method=pinhole"}},
         {{"text", "1600 samples beat photon mapping"},
          {"kind", "better"},
          {"metric", "relmse"},
          {"run", "samples=1600"},
          {"than", "method=photon_map"}},
         {{"text", "Render time grows linearly with photons"},
          {"kind", "linear"},
          {"x", "photons"},
          {"y", "render_ms"},
          {"among", "method=photon_map"},
          {"min_r2", 0.98}},
         {{"text", "Pinhole time is linear in samples"},
          {"kind", "linear"},
          {"x", "samples"},
          {"y", "frame_ms"},
          {"among", "method=pinhole"},
          {"min_r2", 0.98}},
         {{"text", "Render time is tightly linear in photons"},
          {"kind", "linear"},
          {"x", "photons"},
          {"y", "render_ms"},
          {"among", "method=photon_map,k=50"},
          {"min_r2", 0.99}}});
  }

  // runs/<key>/record.json (and the frame of an ok run), as the experiment runner stores them.
  void write_run(const FakeRun& run) const {
    fs::path run_folder = folder / "runs" / run.key;
    fs::create_directories(run_folder);
    json record = {{"key", run.key},     {"method", run.method}, {"label", label(run)},
                   {"build", run.build}, {"render", run.render}, {"swept", run.swept}};
    if (run.failed) {
      record["status"] = "failed";
      record["error"] = kFailure;
    } else {
      double render = run.frame_ms * 0.75;
      json metrics = {{"relmse", run.relmse},
                      {"rmse", std::sqrt(run.relmse)},
                      {"psnr", 20.0 - 10.0 * std::log10(run.relmse)},
                      {"energy_ratio", 1.0 - run.relmse},
                      {"nonfinite_pixels", 0}};
      record.update({{"status", "ok"},
                     {"error", ""},
                     {"frames",
                      {{{"frame", 0},
                        {"image", "frame_0000.exr"},
                        {"update_ms", {run.frame_ms * 0.25}},
                        {"render_ms", {render}},
                        {"metrics", metrics}}}},
                     {"prepare_seconds", 0.5},
                     {"timings",
                      {{"update_ms_min", run.frame_ms * 0.24},
                       {"update_ms_median", run.frame_ms * 0.25},
                       {"render_ms_min", render * 0.99},
                       {"render_ms_median", render},
                       {"frame_ms_min", run.frame_ms * 0.99},
                       {"frame_ms_median", run.frame_ms}}},
                     {"metrics", metrics},
                     {"memory_bytes", 4800000},
                     {"peak_rss_bytes", 123456789},
                     {"counters", {{"photons_emitted", 12345}}},
                     {"method_record", json::object()}});
      write_exr(blob(std::sqrt(run.relmse)), (run_folder / "frame_0000.exr").string());
    }
    write_json(run_folder / "record.json", record);
  }

  void TearDown() override {
    if (!::testing::Test::HasFailure() && !getenv("CAUSTICBENCH_KEEP_REPORT")) fs::remove_all(root);
  }

  const FakeRun& run(const std::string& key) const {
    for (const FakeRun& r : runs)
      if (r.key == key) return r;
    throw std::logic_error(key);
  }

  fs::path root, folder;
  std::vector<FakeRun> runs;
};

TEST_F(ReportTest, WritesEveryFile) {
  ReportSummary summary = write_report(folder.string());
  EXPECT_EQ(summary.runs, 7u);
  EXPECT_EQ(summary.failed, 1u);
  EXPECT_EQ(summary.missing, 1u);
  EXPECT_EQ(summary.plots, 5u);  // trade-off, convergence, sweeps of photons, k and samples
  for (const std::string& path : {summary.html, summary.markdown, summary.csv, summary.json})
    EXPECT_TRUE(fs::is_regular_file(path)) << path;
  for (const char* file :
       {"reference.png", "pm_1e5.png", "pm_1e5_error.png", "pin_100.png", "pin_100_error.png", "error_colour_bar.png",
        "vendor/vega.min.js", "vendor/vega-lite.min.js", "vendor/vega-embed.min.js"})
    EXPECT_TRUE(fs::is_regular_file(folder / "report" / file)) << file;
  EXPECT_FALSE(fs::exists(folder / "report" / "pin_1600.png")) << "failed runs have no pictures";
  // Thumbnails are shrunk to 256 pixels wide, keeping the aspect ratio.
  for (const char* file : {"reference.png", "pm_1e5.png", "pm_1e5_error.png"}) {
    cv::Mat picture = cv::imread((folder / "report" / file).string());
    EXPECT_EQ(picture.cols, 256) << file;
    EXPECT_EQ(picture.rows, 192) << file;
  }
}

TEST_F(ReportTest, CsvHasOneRowPerRunInFullPrecision) {
  ReportSummary summary = write_report(folder.string());
  std::vector<std::string> lines = split(read_text(summary.csv), '\n');
  ASSERT_EQ(lines.size(), 1u + 7u) << "a header and one row per run with a record";
  std::vector<std::string> header = csv_cells(lines[0]);
  auto column = [&](const std::string& name) {
    auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name << " missing from " << lines[0];
    return static_cast<size_t>(it - header.begin());
  };
  EXPECT_EQ(header[0], "key");
  size_t key = column("key"), status = column("status"), method = column("method"), photons = column("build.photons"),
         k = column("render.k"), relmse = column("relmse"), frame = column("frame_ms_median"),
         render = column("render_ms_median"), rss = column("peak_rss_bytes"), error = column("error");
  for (size_t row = 1; row < lines.size(); ++row) {
    std::vector<std::string> cells = csv_cells(lines[row]);
    ASSERT_EQ(cells.size(), header.size()) << lines[row];
    const FakeRun& expected = run(cells[key]);
    EXPECT_EQ(cells[method], expected.method);
    EXPECT_EQ(cells[column("label")], label(expected));
    if (expected.failed) {
      EXPECT_EQ(cells[status], "failed");
      EXPECT_EQ(cells[error], kFailure) << "quoted: " << lines[row];
      EXPECT_EQ(cells[relmse], "");
      continue;
    }
    EXPECT_EQ(cells[status], "ok");
    EXPECT_EQ(std::stod(cells[relmse]), expected.relmse) << "full precision: " << cells[relmse];
    EXPECT_EQ(std::stod(cells[frame]), expected.frame_ms);
    EXPECT_EQ(std::stod(cells[render]), expected.frame_ms * 0.75);
    EXPECT_EQ(cells[rss], "123456789");
    if (expected.method == "photon_map") {
      EXPECT_EQ(cells[photons], expected.build["photons"].dump());
      EXPECT_EQ(cells[k], expected.render["k"].dump());
    } else {
      EXPECT_EQ(cells[photons], "");
    }
  }
  EXPECT_NE(read_text(summary.csv).find("0.0123456789012345"), std::string::npos);
}

TEST_F(ReportTest, MarkdownHasTablesPaperAndFailures) {
  ReportSummary summary = write_report(folder.string());
  std::string md = read_text(summary.markdown);
  // The environment first, then the results table.
  EXPECT_LT(md.find("test-host"), md.find("## Results"));
  EXPECT_NE(md.find("cpu.model:"), std::string::npos);
  // One row per finished run, with method, label and swept knobs; best relmse (0.005) in bold.
  // (the diamond marks runs on the Pareto front over all methods)
  EXPECT_NE(md.find("| photon_map | photon_map k=50 photons=100000 \u25c6 | k=50, photons=100000 | 0.01235 |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| photon_map | photon_map k=10 photons=100000 | k=10, photons=100000 | 0.05 |"),
            std::string::npos);
  EXPECT_NE(md.find("| **0.005** |"), std::string::npos);
  EXPECT_NE(md.find("| pinhole | pinhole samples=400 | samples=400 | 0.04 |"), std::string::npos);
  // The failed run is listed with its error, never in the results table.
  EXPECT_NE(md.find("## Failed runs"), std::string::npos);
  EXPECT_NE(md.find("| pinhole | pinhole samples=1600 | samples=1600 | failed | " + std::string(kFailure) + " |"),
            std::string::npos);
  EXPECT_EQ(md.find("samples=1600 | 0."), std::string::npos);
  EXPECT_NE(md.find("never_ran"), std::string::npos);
  // Paper block: the paper's 135 ms beside our render median (8 * 0.75 = 6 ms), the note, the ratio.
  EXPECT_NE(md.find("## Paper: Wand 2003, Fig. 4"), std::string::npos);
  EXPECT_NE(md.find("| pinhole | samples=100 | pinhole samples=100 | 135 | 6 | \u00d70.0444 | Radeon 9700 |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| pinhole | samples=6400 | not run | 900 | not run |"), std::string::npos);
  EXPECT_NE(md.find("| 20 | 9 | \u00d70.45 | CPU |"), std::string::npos);
  // Images linked from report/.
  EXPECT_NE(md.find("](report/reference.png)"), std::string::npos);
  EXPECT_NE(md.find("](report/pm_1e6_error.png)"), std::string::npos);
  EXPECT_NE(md.find("report.html"), std::string::npos);
}

TEST_F(ReportTest, ParetoFrontIsTheExpectedSubset) {
  ReportSummary summary = write_report(folder.string());
  json results = json::parse(read_text(summary.json));
  EXPECT_EQ(results["runs"].size(), 7u);
  EXPECT_EQ(results["experiment"]["name"], "wand_cup");
  EXPECT_EQ(results["environment"]["machine"], "test-host");
  const json& front = results["pareto_front"];
  EXPECT_EQ(front["overall"], json({"pm_1e4", "pin_100", "pm_1e5", "pm_1e6"}));
  EXPECT_EQ(front["per_method"]["photon_map"], json({"pm_1e4", "pm_1e5", "pm_1e6"}));
  EXPECT_EQ(front["per_method"]["pinhole"], json({"pin_100"}));
}

// R^2 of render_ms (0.75 x frame ms) against photons over the k=50 sweep, by hand: x = 1e4, 1e5, 1e6,
// y = 3.75, 9, 30; mean x = 370000, mean y = 14.25; Sxx = 5.994e11, Sxy = 1.512e7, Syy = 385.875;
// R^2 = Sxy^2 / (Sxx Syy) = 2.286144e14 / 2.31293475e14 = 256/259; slope = Sxy / Sxx = 2.5225e-5;
// intercept = 14.25 - slope x 370000 = 59/12.
constexpr double kPhotonsR2 = 256.0 / 259.0;

TEST_F(ReportTest, ClaimsAreCheckedOnTheOkRuns) {
  ReportSummary summary = write_report(folder.string());
  EXPECT_EQ(summary.claims, 7u);
  EXPECT_EQ(summary.claims_confirmed, 3u);
  EXPECT_EQ(summary.claims_not_confirmed, 2u);

  json results = json::parse(read_text(summary.json));
  const json& claims = results["claims"];
  ASSERT_EQ(claims.size(), 7u);
  std::vector<std::string> verdicts;
  for (const json& claim : claims) verdicts.push_back(claim["verdict"]);
  EXPECT_EQ(verdicts, (std::vector<std::string>{"confirmed", "not confirmed", "confirmed", "not measured", "confirmed",
                                                "not measured", "not confirmed"}));
  EXPECT_EQ(claims[0]["text"], "More photons at k=50 give the least error") << "the claim as stated is kept";
  EXPECT_EQ(claims[0]["among"], "method=photon_map");
  // best: the best run and the best run not matching `expect`.
  EXPECT_EQ(claims[0]["details"]["best"]["key"], "pm_1e6");
  EXPECT_EQ(claims[0]["details"]["best"]["value"], 0.005);
  EXPECT_EQ(claims[0]["details"]["best_not_matching_expect"]["key"], "pm_1e5_k10");
  EXPECT_EQ(claims[0]["details"]["runs"], 4);
  // PSNR is higher-is-better: samples=100 wins, so the claim for 400 fails; the failed 1600 is not counted.
  EXPECT_EQ(claims[1]["details"]["best"]["key"], "pin_100");
  EXPECT_EQ(claims[1]["details"]["best_matching_expect"]["key"], "pin_400");
  EXPECT_EQ(claims[1]["details"]["runs"], 2);
  EXPECT_EQ(claims[1]["details"]["failed_runs"], 1);
  // better: the worst of `run` against the best of `than`.
  EXPECT_EQ(claims[2]["details"]["worst_of_run"]["value"], 5.0);
  EXPECT_EQ(claims[2]["details"]["best_of_than"]["key"], "pin_100");
  EXPECT_EQ(claims[2]["details"]["best_of_than"]["value"], 8.0);
  EXPECT_EQ(claims[3]["details"]["run_runs"], 0);
  EXPECT_EQ(claims[3]["details"]["failed_runs"], 1);
  // linear, grouped by k: the k=50 sweep is fitted, the single k=10 run is not.
  const json& linear = claims[4]["details"];
  EXPECT_EQ(linear["group_by"], json({"k"}));
  ASSERT_EQ(linear["groups"].size(), 2u);
  EXPECT_EQ(linear["groups"][0]["knobs"], json({{"k", 50}}));
  EXPECT_EQ(linear["groups"][0]["n"], 3);
  EXPECT_NEAR(linear["groups"][0]["r2"].get<double>(), kPhotonsR2, 1e-12);
  EXPECT_NEAR(linear["groups"][0]["slope"].get<double>(), 1.512e7 / 5.994e11, 1e-15);
  EXPECT_NEAR(linear["groups"][0]["intercept"].get<double>(), 59.0 / 12.0, 1e-9);
  EXPECT_EQ(linear["groups"][1]["knobs"], json({{"k", 10}}));
  EXPECT_EQ(linear["groups"][1]["fitted"], false);
  EXPECT_NEAR(linear["r2"].get<double>(), kPhotonsR2, 1e-12) << "one fitted group: its fit at the top";
  EXPECT_EQ(claims[5]["details"]["n"], 2);
  // The same points without grouping, against a stricter threshold.
  EXPECT_EQ(claims[6]["details"]["group_by"], json::array());
  EXPECT_NEAR(claims[6]["details"]["r2"].get<double>(), kPhotonsR2, 1e-12);
  EXPECT_EQ(claims[6]["details"]["n"], 3);
  EXPECT_NE(claims[6]["evidence"].get<std::string>().find("R\u00b2 0.9884 < 0.99, n = 3"), std::string::npos)
      << claims[6]["evidence"];

  std::string md = read_text(summary.markdown);
  // After the summary, before the results; the count in the summary.
  EXPECT_LT(md.find("## Summary"), md.find("## Claims"));
  EXPECT_LT(md.find("## Claims"), md.find("## Results"));
  EXPECT_NE(md.find("- 3 of 7 claims confirmed (2 not confirmed, 2 not measured)."), std::string::npos) << md;
  EXPECT_NE(md.find("| claim | verdict | evidence |"), std::string::npos);
  for (const std::string& row : {
           std::string("| More photons at k=50 give the least error | confirmed | best of 4 runs matching "
                       "`method=photon_map`: photon_map k=50 photons=1000000 (relmse 0.005), which matches `k=50`; "
                       "best run not matching it: photon_map k=10 photons=100000 (relmse 0.05). relmse: lower is "
                       "better. |"),
           std::string("| 400 samples give the sharpest image | not confirmed | best of 2 runs matching "
                       "`method=pinhole` (1 failed run not counted): pinhole samples=100 (psnr 35.23), which does "
                       "not match `samples=400`; best run matching it: pinhole samples=400 (psnr 33.98). psnr: "
                       "higher is better. |"),
           std::string("| 10^4 photons are faster than any pinhole run | confirmed | worst of 1 run matching "
                       "`method=photon_map,photons=10000`: photon_map k=50 photons=10000 (frame_ms 5); best of 2 "
                       "runs matching `method=pinhole` (1 failed run not counted): pinhole samples=100 (frame_ms "
                       "8). frame_ms: lower is better. |"),
           std::string("| 1600 samples beat photon mapping | not measured | 0 runs with a relmse value match "
                       "`samples=1600` (1 failed run not counted), 4 match `method=photon_map`: the check needs at "
                       "least 1 on each side. |"),
           std::string("| Render time grows linearly with photons | confirmed | render_ms against photons over 4 "
                       "runs matching `method=photon_map`, grouped by k: k=50: render_ms = 2.523e-05 \u00d7 photons "
                       "+ 4.917, R\u00b2 0.9884 \u2265 0.98, n = 3; k=10: 1 point, not fitted. |"),
           std::string("| Pinhole time is linear in samples | not measured | frame_ms against samples over 2 runs "
                       "matching `method=pinhole` (1 failed run not counted): no set has 3 points with different "
                       "samples values to fit. |"),
           std::string("| Render time is tightly linear in photons | not confirmed | render_ms against photons over "
                       "3 runs matching `method=photon_map,k=50`: render_ms = 2.523e-05 \u00d7 photons + 4.917, "
                       "R\u00b2 0.9884 < 0.99, n = 3. |")})
    EXPECT_NE(md.find(row), std::string::npos) << row << "\n" << md;

  // HTML: one coloured badge per claim, the section between the summary and the results.
  std::string page = read_text(summary.html);
  EXPECT_EQ(count(page, "<span class=\"badge confirmed\">confirmed</span>"), 3u);
  EXPECT_EQ(count(page, "<span class=\"badge refuted\">not confirmed</span>"), 2u);
  EXPECT_EQ(count(page, "<span class=\"badge unmeasured\">not measured</span>"), 2u);
  EXPECT_LT(page.find("class=\"findings\""), page.find("id=\"claims\""));
  EXPECT_LT(page.find("id=\"claims\""), page.find("id=\"results\""));
  EXPECT_NE(page.find("<code>method=photon_map,k=50</code>"), std::string::npos);
}

// Runs that differ in other knobs are fitted per group; every group with 3 points must pass.
TEST_F(ReportTest, LinearClaimsFitEveryGroupOfTheOtherKnobs) {
  // Two more k=10 runs: render_ms 30, 10.5, 15 at 1e4, 1e5, 1e6 photons is far from a line.
  std::vector<FakeRun> more = {{"pm_1e4_k10",
                                "photon_map",
                                {{"photons", 10000}, {"seed", 1}},
                                {{"k", 10}, {"max_radius", 0.1}},
                                {{"photons", 10000}, {"k", 10}},
                                0.2,
                                40.0},
                               {"pm_1e6_k10",
                                "photon_map",
                                {{"photons", 1000000}, {"seed", 1}},
                                {{"k", 10}, {"max_radius", 0.1}},
                                {{"photons", 1000000}, {"k", 10}},
                                0.01,
                                20.0}};
  json experiment = json::parse(read_text(folder / "experiment.json"));
  for (const FakeRun& run : more) {
    write_run(run);
    experiment["runs"].push_back(run.key);
  }
  experiment["claims"] = json::array({claims()[4]});
  write_json(folder / "experiment.json", experiment);

  ReportSummary summary = write_report(folder.string());
  json results = json::parse(read_text(summary.json));
  ASSERT_EQ(results["claims"].size(), 1u);
  const json& claim = results["claims"][0];
  EXPECT_EQ(claim["verdict"], "not confirmed") << claim.dump(2);
  const json& groups = claim["details"]["groups"];
  ASSERT_EQ(groups.size(), 2u);
  EXPECT_NEAR(groups[0]["r2"].get<double>(), kPhotonsR2, 1e-12);
  EXPECT_EQ(groups[0]["passed"], true);
  // k=10: x = 1e4, 1e5, 1e6, y = 30, 10.5, 15: Sxy = -360000 x 11.5 - 270000 x (-8) + 630000 x (-3.5)
  // = -4.185e6, Syy = 132.25 + 64 + 12.25 = 208.5, R^2 = Sxy^2 / (5.994e11 x 208.5).
  EXPECT_EQ(groups[1]["knobs"], json({{"k", 10}}));
  EXPECT_EQ(groups[1]["n"], 3);
  EXPECT_NEAR(groups[1]["r2"].get<double>(), 4.185e6 * 4.185e6 / (5.994e11 * 208.5), 1e-12);
  EXPECT_EQ(groups[1]["passed"], false);
  EXPECT_FALSE(claim["details"].contains("r2")) << "two fitted groups: no single fit at the top";
  std::string md = read_text(summary.markdown);
  EXPECT_NE(md.find("- 0 of 1 claim confirmed (1 not confirmed)."), std::string::npos) << md;
  EXPECT_NE(md.find("k=50: render_ms = 2.523e-05 \u00d7 photons + 4.917, R\u00b2 0.9884 \u2265 0.98, n = 3; k=10: "
                    "render_ms = "),
            std::string::npos)
      << md;
}

TEST(ParetoFront, FollowsTheMetricDirection) {
  std::vector<TradeoffPoint> points = {
      {10, 0.5}, {20, 0.2}, {15, 0.6}, {20, 0.2}, {5, 0.9}, {30, 0.1}, {std::nan(""), 0.01}, {1, std::nan("")}};
  auto lower = [](double a, double b) { return a < b; };
  EXPECT_EQ(pareto_front(points, lower), (std::vector<size_t>{4, 0, 1, 3, 5}));  // equal points both stay
  // PSNR: higher is better, so the slow high-PSNR points win instead.
  const MetricInfo& psnr = find_metric("psnr");
  std::vector<TradeoffPoint> psnr_points = {{10, 30}, {20, 35}, {15, 28}, {5, 20}, {30, 34}};
  EXPECT_EQ(pareto_front(psnr_points, [&](double a, double b) { return metric_better(psnr, a, b); }),
            (std::vector<size_t>{3, 0, 1}));
  // energy_ratio: closest to 1 is best.
  const MetricInfo& energy = find_metric("energy_ratio");
  std::vector<TradeoffPoint> energy_points = {{10, 1.3}, {20, 0.95}, {30, 1.02}, {40, 1.1}};
  EXPECT_EQ(pareto_front(energy_points, [&](double a, double b) { return metric_better(energy, a, b); }),
            (std::vector<size_t>{0, 1, 2}));
}

// Without the reference (or with every run failed) the report is still written, with what it lacks said.
TEST_F(ReportTest, CopesWithoutReferenceAndWithoutFinishedRuns) {
  fs::remove_all(root / "results" / "references");
  ReportSummary summary = write_report(folder.string());
  std::string md = read_text(summary.markdown);
  EXPECT_NE(md.find("reference record"), std::string::npos) << md;
  EXPECT_FALSE(fs::exists(folder / "report" / "pm_1e5_error.png")) << "no error map without a reference";
  EXPECT_TRUE(fs::exists(folder / "report" / "pm_1e5.png"));
  EXPECT_EQ(summary.plots, 4u) << "no convergence plot without the reference's history";

  for (const FakeRun& run : runs) {
    json record = json::parse(read_text(folder / "runs" / run.key / "record.json"));
    record["status"] = "failed";
    record["error"] = "crashed";
    write_json(folder / "runs" / run.key / "record.json", record);
  }
  summary = write_report(folder.string());
  EXPECT_EQ(summary.failed, 7u);
  EXPECT_EQ(summary.plots, 0u);
  EXPECT_NE(read_text(summary.markdown).find("No run finished."), std::string::npos);
  EXPECT_FALSE(fs::exists(folder / "report" / "pm_1e5.png")) << "stale pictures are removed";
}

TEST_F(ReportTest, RejectsFoldersThatAreNotExperiments) {
  try {
    write_report((root / "results").string());
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    std::string message = error.what();
    EXPECT_NE(message.find("not an experiment results folder"), std::string::npos) << message;
    EXPECT_NE(message.find("wand_cup"), std::string::npos) << "names the experiment folders inside: " << message;
  }
  EXPECT_THROW(write_report((root / "nowhere").string()), InputError);
  EXPECT_THROW(write_report((folder / "experiment.json").string()), InputError);
  std::ofstream(folder / "experiment.json") << "{ not json";
  EXPECT_THROW(write_report(folder.string()), InputError);
}

// The plots must render from file:// with no network: run headless Chromium on report.html.
TEST_F(ReportTest, PlotsRenderOfflineInChromium) {
  const char* chromium = "/usr/bin/chromium";
  if (!fs::exists(chromium)) GTEST_SKIP() << "chromium is not installed (scripts/setup.sh installs it)";
  ReportSummary summary = write_report(folder.string());
  ASSERT_GE(summary.plots, 5u);
  std::string dom;
  for (const char* headless : {"--headless=new", "--headless"}) {
    std::string command = std::string("timeout 60 ") + chromium + " " + headless +
                          " --no-sandbox --disable-gpu --disable-dev-shm-usage --no-first-run"
                          " --virtual-time-budget=10000 --dump-dom 'file://" +
                          summary.html + "' 2>/dev/null";
    std::string output;
    int code = testing::run_command(command, output);
    if (code == 0 && output.find("</html>") != std::string::npos) {
      dom = output;
      break;
    }
  }
  ASSERT_FALSE(dom.empty()) << "chromium produced no DOM";
  EXPECT_GE(count(dom, "class=\"marks\""), summary.plots) << "every plot is drawn as an SVG";
  EXPECT_EQ(count(dom, "class=\"plot-error\""), 0u) << "vega-embed reported an error";
  EXPECT_EQ(dom.find("Error"), std::string::npos) << "vega-embed reported an error";
  // The SVG holds the plotted points (one path per symbol) and the noise floor label.
  EXPECT_NE(dom.find("reference noise floor"), std::string::npos);
}

}  // namespace
}  // namespace causticbench
