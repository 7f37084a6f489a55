// The report generator on the synthetic results folder of report_test_support.h: CSV values, Markdown
// tables, the paper block, the claims, the Pareto front, undefined values. Pictures and plots:
// test_report_pictures.cpp; scene variants: test_report_variants.cpp.
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
#include "core/files.h"
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
  // Records written before scene variants have neither field: the columns are there, empty.
  size_t variant = column("variant"), pixels = column("receiver_pixels");
  ASSERT_LT(std::max(variant, pixels), header.size());
  for (size_t row = 1; row < lines.size(); ++row) {
    std::vector<std::string> cells = csv_cells(lines[row]);
    EXPECT_EQ(cells[variant], "") << lines[row];
    EXPECT_EQ(cells[pixels], "") << lines[row];
  }
}

// An experiment with its one variant listed (as the runner now writes it), and records that name it,
// reads exactly as one without: no variant column, reference.png, the same pages.
TEST_F(ReportTest, OneVariantLooksAsBefore) {
  ReportSummary before = write_report(folder.string());
  std::string md = read_text(before.markdown), page = read_text(before.html);
  json experiment = json::parse(read_text(folder / "experiment.json"));
  experiment["variants"] = json::array(
      {{{"name", "default"}, {"overrides", json::object()}, {"resolution", {384, 288}}, {"reference_key", "ref123"}}});
  write_json(folder / "experiment.json", experiment);
  for (const FakeRun& fake : runs) {
    json record = json::parse(read_text(folder / "runs" / fake.key / "record.json"));
    record.update({{"variant", "default"}, {"reference_key", "ref123"}, {"receiver_pixels", 55296}});
    write_json(folder / "runs" / fake.key / "record.json", record);
  }
  ReportSummary after = write_report(folder.string());
  EXPECT_EQ(read_text(after.markdown), md);
  EXPECT_EQ(read_text(after.html), page);
  EXPECT_TRUE(fs::is_regular_file(folder / "report" / "reference.png"));
  EXPECT_EQ(md.find("variant"), std::string::npos) << md;
  std::vector<std::string> lines = split(read_text(after.csv), '\n');
  std::vector<std::string> header = csv_cells(lines[0]);
  size_t pixels = std::find(header.begin(), header.end(), "receiver_pixels") - header.begin();
  ASSERT_LT(pixels, header.size());
  EXPECT_EQ(csv_cells(lines[1])[pixels], "55296");
  json results = json::parse(read_text(after.json));
  EXPECT_EQ(results["variants"].size(), 1u);
  EXPECT_EQ(results["pareto_front"]["overall"], json({"pm_1e4", "pin_100", "pm_1e5", "pm_1e6"}));
}

TEST_F(ReportTest, MarkdownHasTablesPaperAndFailures) {
  ReportSummary summary = write_report(folder.string());
  std::string md = read_text(summary.markdown);
  // The environment first, then the results table.
  EXPECT_LT(md.find("test-host"), md.find("## Results"));
  EXPECT_NE(md.find("cpu.model:"), std::string::npos);
  // One row per finished run, with method, label and swept knobs; best relmse (0.005) in bold.
  // (the diamond marks runs on the Pareto front over all methods)
  EXPECT_NE(md.find("| photon_map | photon_map k=50 photons=100000 \u25c6 | max_radius=0.1, photons=100000 | 0.01235 |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| photon_map | photon_map k=10 photons=100000 | k=10, max_radius=0.1, photons=100000 | 0.05 |"),
            std::string::npos);
  EXPECT_NE(md.find("| **0.005** |"), std::string::npos);
  EXPECT_NE(md.find("| pinhole | pinhole samples=400 | filtering=none, samples=400 | 0.04 |"), std::string::npos);
  // The failed run is listed with its error, never in the results table.
  EXPECT_NE(md.find("## Failed runs"), std::string::npos);
  EXPECT_NE(md.find("| pinhole | pinhole samples=1600 | filtering=none, samples=1600 | failed | " + std::string(kFailure) + " |"),
            std::string::npos);
  EXPECT_EQ(md.find("samples=1600 | 0."), std::string::npos);
  EXPECT_NE(md.find("never_ran"), std::string::npos);
  // Paper block: the paper's 135 ms beside our render median (8 * 0.75 = 6 ms), the note, the ratio.
  EXPECT_NE(md.find("## Paper: Wand 2003, Fig. 4"), std::string::npos);
  EXPECT_NE(md.find("| pinhole | samples=100 | pinhole (filtering=none, samples=100) | 135 | 6 | \u00d70.0444 | Radeon 9700 |"),
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
  EXPECT_EQ(summary.claims.total, 7u);
  EXPECT_EQ(summary.claims.of(Verdict::confirmed), 3u);
  EXPECT_EQ(summary.claims.of(Verdict::refuted), 2u);
  EXPECT_EQ(summary.claims.of(Verdict::partly), 0u);

  json results = json::parse(read_text(summary.json));
  const json& claims = results["claims"];
  ASSERT_EQ(claims.size(), 7u);
  std::vector<std::string> verdicts;
  for (const json& claim : claims) verdicts.push_back(claim["verdict"]);
  EXPECT_EQ(verdicts, (std::vector<std::string>{"confirmed", "refuted", "confirmed", "not measured", "confirmed",
                                                "not measured", "refuted"}));
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
  EXPECT_EQ(claims[2]["details"]["pairs"], 2);
  EXPECT_EQ(claims[2]["details"]["pairs_better"], 2);
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
  EXPECT_NE(md.find("- 3 of 7 claims confirmed (2 refuted, 2 not measured)."), std::string::npos) << md;
  EXPECT_NE(md.find("| claim | verdict | evidence |"), std::string::npos);
  for (const std::string& row : {
           std::string("| More photons at k=50 give the least error | confirmed | best of 4 runs matching "
                       "`method=photon_map`: photon_map (max_radius=0.1, photons=1000000) (relmse 0.005), which matches "
                       "`k=50`; best run not matching it: photon_map (k=10, max_radius=0.1, photons=100000) (relmse "
                       "0.05). relmse: lower is "
                       "better. |"),
           std::string("| 400 samples give the sharpest image | refuted | best of 2 runs matching "
                       "`method=pinhole` (1 failed run not counted): pinhole (filtering=none, samples=100) (psnr 35.23), "
                       "which does not match `samples=400`; best run matching it: pinhole (filtering=none, "
                       "samples=400) (psnr 33.98). psnr: "
                       "higher is better. |"),
           std::string("| 10^4 photons are faster than any pinhole run | confirmed | worst of 1 run matching "
                       "`method=photon_map,photons=10000`: photon_map (max_radius=0.1, photons=10000) (frame_ms 5); best "
                       "of 2 runs matching `method=pinhole` (1 failed run not counted): pinhole (filtering=none, "
                       "samples=100) (frame_ms "
                       "8). Better in 2 of 2 pairs. frame_ms: lower is better. |"),
           std::string("| 1600 samples beat photon mapping | not measured | 0 runs with a relmse value match "
                       "`samples=1600` (1 failed run not counted), 4 match `method=photon_map`: the check needs at "
                       "least 1 on each side. |"),
           std::string("| Render time grows linearly with photons | confirmed | render_ms against photons over 4 "
                       "runs matching `method=photon_map`, grouped by k: k=50: render_ms = 2.523e-05 \u00d7 photons "
                       "+ 4.917, R\u00b2 0.9884 \u2265 0.98, n = 3; k=10: 1 point, not fitted. |"),
           std::string("| Pinhole time is linear in samples | not measured | frame_ms against samples over 2 runs "
                       "matching `method=pinhole` (1 failed run not counted): no set has 3 points with different "
                       "samples values to fit. |"),
           std::string("| Render time is tightly linear in photons | refuted | render_ms against photons over "
                       "3 runs matching `method=photon_map,k=50`: render_ms = 2.523e-05 \u00d7 photons + 4.917, "
                       "R\u00b2 0.9884 < 0.99, n = 3. |")})
    EXPECT_NE(md.find(row), std::string::npos) << row << "\n" << md;

  // HTML: one coloured badge per claim, the section between the summary and the results.
  std::string page = read_text(summary.html);
  EXPECT_EQ(count(page, "<span class=\"badge confirmed\">confirmed</span>"), 3u);
  EXPECT_EQ(count(page, "<span class=\"badge refuted\">refuted</span>"), 2u);
  EXPECT_EQ(count(page, "<span class=\"badge unmeasured\">not measured</span>"), 2u);
  EXPECT_LT(page.find("class=\"findings\""), page.find("id=\"claims\""));
  EXPECT_LT(page.find("id=\"claims\""), page.find("id=\"results\""));
  EXPECT_NE(page.find("<code>method=photon_map,k=50</code>"), std::string::npos);
}

// Runs that differ in other knobs are fitted per group; every group with 3 points must pass for
// "confirmed", and when only some do the claim is "partly" confirmed.
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
  EXPECT_EQ(claim["verdict"], "partly") << claim.dump(2) << "one of the two fitted groups is linear";
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
  EXPECT_NE(md.find("- 0 of 1 claim confirmed (1 partly)."), std::string::npos) << md;
  EXPECT_NE(md.find("k=50: render_ms = 2.523e-05 \u00d7 photons + 4.917, R\u00b2 0.9884 \u2265 0.98, n = 3; k=10: "
                    "render_ms = "),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("Linear in 1 of 2 fitted groups."), std::string::npos) << md;
  EXPECT_NE(read_text(summary.html).find("<span class=\"badge partly\">partly</span>"), std::string::npos);
}

// ---------------------------------------------------------------------------------------------------
// Scene variants: one experiment at three resolutions, each with its own reference (of a different size
// and brightness). Every run records its variant, its reference_key and its receiver_pixels.
//
//   variant   receiver pixels  reference gain   pinhole samples=1000    photon_map photons=1e5
//   96x72           3000            1           (8 ms, 0.01)            (11 ms, 0.02)
//   192x144        12000            2           (26 ms, 0.03)           (41 ms, 0.02)
//   384x288        48000            4           (98 ms, 0.05)           (12 ms, 0.01)
//   plus pinhole samples=100 at 96x72: (9 ms, 0.5), dominated.
// (frame ms = 1 ms update + render ms.) The pinhole images equal their variant's reference exactly; the
// photon_map images are noisy. Pinhole render ms = 0.002 x receiver pixels + 1 (exactly linear);
// photon_map render ms 10, 40, 11 (not linear).
//
// Fronts within each variant: 96x72 {pin_96}, 192x144 {pin_192, pm_192}, 384x288 {pm_384}; per method
// every pinhole samples=1000 run and every photon_map run. Over all variants at once, pin_96 (8 ms,
// 0.01) would dominate every other run.
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
// Undefined values (docs/metrics.md, "Undefined values"): a metric the record lists under
// "metrics_undefined", and every metric of a run against an empty reference, is an empty cell with its
// reason as a footnote, and no best value, front, claim, plot or "best" line counts it. Timings still do.
TEST_F(ReportTest, UndefinedValuesAreEmptyCellsWithTheirReason) {
  const std::string relmse_reason = "the reference is 0 over the receivers (a reason for the test)";
  json best = json::parse(read_text(folder / "runs" / "pm_1e6" / "record.json"));  // the best relmse, 0.005
  best["metrics"].erase("relmse");
  best["metrics_undefined"] = {{"relmse", relmse_reason}};
  write_json(folder / "runs" / "pm_1e6" / "record.json", best);
  json empty = json::parse(read_text(folder / "runs" / "pin_400" / "record.json"));  // its metrics stay stored
  empty["empty_reference"] = {{"frames", {0}}, {"reason", "E_c summed over its 9 receiver pixels is 0 W/m^2"}};
  write_json(folder / "runs" / "pin_400" / "record.json", empty);
  const std::string empty_reason = "empty reference: E_c summed over its 9 receiver pixels is 0 W/m^2";

  ReportSummary summary = write_report(folder.string());
  std::string md = read_text(summary.markdown);
  EXPECT_NE(md.find("| photon_map | photon_map k=50 photons=1000000 | max_radius=0.1, photons=1000000 | \u2014 [1] |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("- [1] undefined: " + relmse_reason + "\n"), std::string::npos) << md;
  EXPECT_NE(md.find("| pinhole | pinhole samples=400 (empty reference) | filtering=none, samples=400 | \u2014 [2] | \u2014 [2] | "
                    "\u2014 [2] | \u2014 [2] |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("- [2] undefined: " + empty_reason + "\n"), std::string::npos) << md;
  EXPECT_EQ(md.find("| **0.005** |"), std::string::npos) << "an undefined value is never best";
  EXPECT_NE(md.find("| **0.01235** |"), std::string::npos) << "the best defined value is";
  EXPECT_NE(md.find("Best relmse: **photon_map (max_radius=0.1, photons=100000)** (relmse 0.01235, 12 ms)."), std::string::npos);
  EXPECT_NE(md.find("1 run against an empty reference"), std::string::npos) << md;
  EXPECT_NE(md.find("| relmse undefined \u00b7 40 ms |"), std::string::npos) << "the image caption says so";
  EXPECT_NE(md.find("| empty reference \u00b7 30 ms |"), std::string::npos);

  json results = json::parse(read_text(summary.json));
  EXPECT_EQ(results["pareto_front"]["overall"], json({"pm_1e4", "pin_100", "pm_1e5"}));
  EXPECT_EQ(results["pareto_front"]["per_method"]["photon_map"], json({"pm_1e4", "pm_1e5"}));
  const json& claims = results["claims"];
  // best relmse among photon_map: pm_1e6 does not count; pm_1e5 (k=50) still beats pm_1e5_k10.
  EXPECT_EQ(claims[0]["verdict"], "confirmed");
  EXPECT_EQ(claims[0]["details"]["best"]["key"], "pm_1e5");
  EXPECT_EQ(claims[0]["details"]["runs"], 3);
  EXPECT_EQ(claims[0]["details"]["undefined_runs"], 1);
  EXPECT_NE(claims[0]["evidence"].get<std::string>().find("(1 run with an undefined value not counted)"),
            std::string::npos)
      << claims[0]["evidence"];
  // best psnr among pinhole, expect samples=400: the only such run is against an empty reference.
  EXPECT_EQ(claims[1]["verdict"], "not measured");
  const std::string both_not_counted = "(1 failed run and 1 run with an undefined value not counted)";
  EXPECT_NE(claims[1]["evidence"].get<std::string>().find(both_not_counted), std::string::npos) << claims[1]["evidence"];
  // Timings of a run against an empty reference still count.
  EXPECT_EQ(claims[2]["verdict"], "confirmed");
  EXPECT_EQ(claims[2]["details"]["than_runs"], 2);
  // The trade-off plot has no point of either run.
  std::string page = read_text(summary.html);
  std::string tradeoff = page.substr(page.find("[\"plot-tradeoff\""), 20000);
  EXPECT_EQ(tradeoff.find("\"key\":\"pm_1e6\""), std::string::npos);
  EXPECT_EQ(tradeoff.find("\"key\":\"pin_400\""), std::string::npos);

  // HTML: no value in the cell, the reason on hover and as a numbered note.
  EXPECT_NE(page.find("<td class=\"num undefined\" title=\"undefined: " + relmse_reason + "\"><sup>1</sup></td>"),
            std::string::npos);
  EXPECT_NE(page.find("<li>undefined: " + empty_reason + "</li>"), std::string::npos);

  // CSV: empty metric cells, and the reasons in metrics_undefined.
  std::vector<std::string> lines = split(read_text(summary.csv), '\n');
  std::vector<std::string> header = csv_cells(lines[0]);
  auto column = [&](const std::string& name) {
    return static_cast<size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  ASSERT_LT(column("metrics_undefined"), header.size());
  for (size_t row = 1; row < lines.size(); ++row) {
    std::vector<std::string> cells = csv_cells(lines[row]);
    if (cells[column("key")] == "pm_1e6") {
      EXPECT_EQ(cells[column("relmse")], "");
      EXPECT_EQ(cells[column("metrics_undefined")], "relmse: " + relmse_reason);
      EXPECT_NE(cells[column("rmse")], "");
    } else if (cells[column("key")] == "pin_400") {
      for (const char* metric : {"relmse", "rmse", "psnr", "energy_ratio"})
        EXPECT_EQ(cells[column(metric)], "") << metric;
      EXPECT_NE(cells[column("metrics_undefined")].find("psnr: " + empty_reason), std::string::npos);
      EXPECT_NE(cells[column("frame_ms_median")], "");
    } else {
      EXPECT_EQ(cells[column("metrics_undefined")], "") << lines[row];
    }
  }
}

TEST_F(ReportTest, CopesWithoutReferenceAndWithoutFinishedRuns) {
  fs::remove_all(root / "results" / "references");
  ReportSummary summary = write_report(folder.string());
  std::string md = read_text(summary.markdown);
  EXPECT_NE(md.find("reference record"), std::string::npos) << md;
  EXPECT_FALSE(fs::exists(folder / "report" / "pm_1e5_error.png")) << "no error map without a reference";
  EXPECT_TRUE(fs::exists(folder / "report" / "pm_1e5.png"));
  EXPECT_EQ(summary.plots, 6u) << "no convergence plot without the reference's history (error against time has no reference curve)";

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


// Issue 30, defect 8: a report removed every PNG it had not written itself, another process's temporary
// file included (a run or a second report of the experiment at work), which then failed; and the vendored
// bundle was copied through one temporary name shared by every process. A temporary file of a write in
// progress stays; a stale image of a run no longer in the experiment goes; the bundle leaves no temporary.
TEST_F(ReportTest, AnotherProcessesTemporaryImageIsLeftAlone) {
  write_report(folder.string());
  const fs::path images = folder / "report";
  const std::string in_progress = "pm_1e4_ec.png.partial." + host_name() + "-" + std::to_string(::getpid()) + ".7.png";
  std::ofstream(images / in_progress) << "being written";
  std::ofstream(images / "a_run_no_longer_there.png") << "stale";
  write_report(folder.string());
  EXPECT_TRUE(fs::exists(images / in_progress));
  EXPECT_FALSE(fs::exists(images / "a_run_no_longer_there.png"));
  for (const auto& entry : fs::directory_iterator(images / "vendor"))
    EXPECT_FALSE(is_partial_file_name(entry.path().filename().string())) << entry.path();
  EXPECT_TRUE(is_partial_file_name(in_progress));
}

}  // namespace
}  // namespace causticbench
