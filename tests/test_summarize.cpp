// `causticbench summarize` on synthetic results with known answers: two experiments in one results
// folder, each with hand-placed runs, so that the best method per frame budget, the wins and failures
// of each method, the cost ranges, the break-even count and the claims' verdicts are known beforehand;
// and the command line's bad input (exit 2, nothing written).
#include <unistd.h>

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "store/run_record.h"
#include "reports/report.h"
#include "reports/summary.h"
#include "tests/report_test_support.h"

namespace causticbench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using report_testing::read_text;
using report_testing::write_json;

struct SyntheticRun {
  std::string key, method;
  json swept;
  double frame_ms = 0, error = 0, prepare_seconds = 0;
  int64_t memory_bytes = 0;
  std::string failure = {};  // non-empty: a failed run with this error
};

// Two experiments under <root>/results:
//   study_mirror, relmse (lower is better), budgets 1, 10, 50, 1000 ms:
//     pinhole samples=100  (5 ms, 0.2)     samples=1000 (40 ms, 0.05)    prepare 0 s
//     csl     rays=64      (8 ms, 0.1, 2 s) rays=512    (200 ms, 0.01, 5 s)
//     within 1 ms: none reached (fastest pinhole 5 ms); 10 ms: csl rays=64; 50 ms: pinhole samples=1000;
//     1000 ms: csl rays=512. Break-even: one entry, csl rays=64 (2 s, 8 ms) overtakes pinhole
//     samples=1000 (0 s, 40 ms, more accurate) after 2000 / (40 - 8) = 62.5, from frame 63; csl rays=512 has no
//     pinhole run as accurate, and pinhole precomputes nothing, so it never overtakes.
//   study_glass, ssim (higher is better), budgets 16.7, 100, 1000 ms:
//     lpi     every run failed (it refuses the glass)
//     photon_map photons=1e5 (20 ms, 0.9)  photons=1e6 (300 ms, 0.95)
//     pinhole    samples=100 (10 ms, 0.5): the worst best-error of the two measured methods
//     within 16.7 ms: pinhole; 100 ms: photon_map photons=1e5; 1000 ms: photon_map photons=1e6.
//   pinhole's best is the worse of the measured methods' in both scenes: a "worst error" failure in each.
//     claim "photon_map beats pinhole on ssim": confirmed; "pinhole beats photon_map": refuted.
class SummarizeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root = fs::temp_directory_path() / ("causticbench_summarize_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root);
    results = root / "results";
    write_experiment("study_mirror", "relmse", {1, 10, 50, 1000}, json::array(),
                     {{"pin_100", "pinhole", {{"samples", 100}}, 5, 0.2, 0, 1000},
                      {"pin_1000", "pinhole", {{"samples", 1000}}, 40, 0.05, 0, 1000},
                      {"csl_64", "csl", {{"rays", 64}}, 8, 0.1, 2, 4000000},
                      {"csl_512", "csl", {{"rays", 512}}, 200, 0.01, 5, 64000000}});
    write_experiment("study_glass", "ssim", {16.7, 100, 1000},
                     {{{"text", "Photon mapping beats pinhole on glass"},
                       {"kind", "better"},
                       {"metric", "ssim"},
                       {"run", "method=photon_map"},
                       {"than", "method=pinhole"}},
                      {{"text", "Pinhole beats photon mapping on glass"},
                       {"kind", "better"},
                       {"metric", "ssim"},
                       {"run", "method=pinhole"},
                       {"than", "method=photon_map"}}},
                     {{"lpi_a", "lpi", {{"order", 2}}, 0, 0, 0, 0, kRefusal},
                      {"lpi_b", "lpi", {{"order", 4}}, 0, 0, 0, 0, kRefusal},
                      {"pm_1e5", "photon_map", {{"photons", 100000}}, 20, 0.9, 0, 8000000},
                      {"pm_1e6", "photon_map", {{"photons", 1000000}}, 300, 0.95, 0, 80000000},
                      {"pin_100", "pinhole", {{"samples", 100}}, 10, 0.5, 0, 1000}});
  }

  void TearDown() override {
    if (!::testing::Test::HasFailure()) fs::remove_all(root);
  }

  static constexpr const char* kRefusal = "lpi cannot represent the scene: refraction (glass) is not supported";

  void write_experiment(const std::string& name, const std::string& primary, const std::vector<double>& budgets,
                        const json& claims, const std::vector<SyntheticRun>& runs) {
    const fs::path folder = results / name;
    json keys = json::array();
    for (const SyntheticRun& run : runs) keys.push_back(run.key);
    write_json(folder / "experiment.json", {{"name", name},
                                            {"source", "configs/experiments/" + name + ".yaml"},
                                            {"scene", "configs/scenes/" + name + ".yaml"},
                                            {"resolution", {64, 48}},
                                            {"frames", {0}},
                                            {"metrics", {"relmse", "ssim"}},
                                            {"primary_metric", primary},
                                            {"reference_key", "ref_" + name},
                                            {"runs", keys},
                                            {"budgets_ms", budgets},
                                            {"claims", claims}});
    write_json(folder / "environment.json", {{"machine", "test-host"}});
    write_json(results / "references" / ("ref_" + name) / "record.json",
               {{"method", "reference"}, {"passes", 4}, {"seconds", 1.0}, {"error_estimate", 1e-4}});
    for (const SyntheticRun& run : runs) {
      RunRecord record;
      record.key = run.key;
      record.method = run.method;
      record.label = run.method + " " + run.swept.dump();
      record.swept = run.swept;
      record.build = run.swept;
      record.git_revision = "abcdef123456";
      if (!run.failure.empty()) {
        record.status = "failed";
        record.error = run.failure;
      } else {
        record.metrics = {{primary, run.error}};
        record.timings = {0, 0, run.frame_ms, run.frame_ms, run.frame_ms, run.frame_ms, std::nullopt, std::nullopt};
        record.prepare.prepare_seconds = run.prepare_seconds;
        record.memory_bytes = run.memory_bytes;
        // The store counts an ok record only with its frame's image beside it.
        FrameRecord frame;
        frame.image = "frame_0000.exr";
        frame.render_ms = {run.frame_ms};
        frame.metrics = record.metrics;
        record.frames = {frame};
        fs::create_directories(folder / "runs" / run.key);
        write_exr(report_testing::blob(0.0, 16, 12), (folder / "runs" / run.key / "frame_0000.exr").string());
      }
      write_json(folder / "runs" / run.key / "record.json", record.to_json());
    }
  }

  std::vector<std::string> both() const { return {(results / "study_mirror").string(), (results / "study_glass").string()}; }

  // The "best" method of each budget of a scene in summary.json ("none" when none reached).
  static std::map<double, std::string> winners(const json& summary, const std::string& title) {
    std::map<double, std::string> out;
    for (const json& scene : summary.at("scenes"))
      if (scene.at("title") == title)
        for (const json& budget : scene.at("budgets"))
          out[budget.at("budget_ms").get<double>()] =
              budget.at("best").is_null() ? "none"
                                          : budget.at("best").at("method").get<std::string>() + " " +
                                                budget.at("best").at("knobs").dump();
    return out;
  }

  static const json& method_entry(const json& summary, const std::string& method) {
    for (const json& entry : summary.at("methods"))
      if (entry.at("method") == method) return entry;
    throw std::logic_error(method);
  }

  fs::path root, results;
};

TEST_F(SummarizeTest, BestMethodPerBudgetInEveryScene) {
  SummaryFiles files = write_summary(both(), (root / "out").string());
  EXPECT_EQ(files.experiments, 2u);
  EXPECT_EQ(files.scenes, 2u);
  const json summary = json::parse(read_text(files.json));
  const std::map<double, std::string> mirror = {{1, "none"},
                                                {10, "csl {\"rays\":64}"},
                                                // 1000 samples is pinhole's default: no knob to name.
                                                {50, "pinhole {}"},
                                                {1000, "csl {\"rays\":512}"}};
  EXPECT_EQ(winners(summary, "study_mirror"), mirror);
  const std::map<double, std::string> glass = {{16.7, "pinhole {\"samples\":100}"},
                                               {100, "photon_map {\"photons\":100000}"},
                                               {1000, "photon_map {\"photons\":1000000}"}};
  EXPECT_EQ(winners(summary, "study_glass"), glass);
  // None reached names the fastest run, to say by how much.
  const json& first = summary.at("scenes").at(0).at("budgets").at(0);
  EXPECT_EQ(first.at("none_reached").at("run"), "pin_100");

  // The documents say the same.
  const std::string markdown = read_text(files.markdown), html = read_text(files.html);
  for (const std::string* text : {&markdown, &html}) {
    EXPECT_NE(text->find("none reached (fastest: pinhole 5 ms)"), std::string::npos);
    EXPECT_NE(text->find("csl relmse 0.01 \u00b7 200 ms \u00b7 rays=512"), std::string::npos);
    EXPECT_NE(text->find("photon_map ssim 0.95 \u00b7 300 ms \u00b7 photons=1000000"), std::string::npos);
  }
  EXPECT_EQ(html.find("<script"), std::string::npos);  // one offline page
  ASSERT_EQ(files.headlines.size(), 2u);
  EXPECT_EQ(files.headlines[0], "study_mirror (relmse): 1 ms none, 10 ms csl, 50 ms pinhole, 1 s csl");
}

// A best run links into its experiment's viewer (docs/reports.md, "The viewer") where the experiment's
// report wrote one: here study_mirror's, not study_glass's.
TEST_F(SummarizeTest, BestRunsLinkIntoTheirExperimentsViewer) {
  ASSERT_FALSE(write_report((results / "study_mirror").string()).viewer.empty());
  const std::string html = read_text(write_summary(both(), (root / "out").string()).html);
  EXPECT_NE(html.find("<a href=\"../results/study_mirror/viewer.html#run="), std::string::npos);
  EXPECT_EQ(html.find("study_glass/viewer.html"), std::string::npos);
}

TEST_F(SummarizeTest, WhereEachMethodWinsAndFails) {
  const json summary = json::parse(read_text(write_summary(both(), (root / "out").string()).json));
  const json& pinhole = method_entry(summary, "pinhole");
  ASSERT_EQ(pinhole.at("wins").size(), 2u);  // mirror within 50 ms, glass within 16.7 ms
  EXPECT_EQ(pinhole.at("wins").at(0).at("scene"), "study_mirror");
  EXPECT_EQ(pinhole.at("wins").at(1).at("budget_ms"), 16.7);
  // Its best is the worse of the two measured methods in both scenes (0.05 against csl's 0.01; ssim 0.5
  // against photon_map's 0.95): winning a budget does not make it the method of the scene.
  ASSERT_EQ(pinhole.at("failures").size(), 2u);
  EXPECT_EQ(pinhole.at("failures").at(0).at("kind"), "worst error");
  EXPECT_EQ(pinhole.at("failures").at(0).at("scene"), "study_mirror");
  EXPECT_EQ(pinhole.at("failures").at(1).at("scene"), "study_glass");
  EXPECT_NE(pinhole.at("failures").at(1).at("text").get<std::string>().find("ssim 0.5"), std::string::npos);

  const json& lpi = method_entry(summary, "lpi");
  EXPECT_TRUE(lpi.at("wins").empty());
  ASSERT_EQ(lpi.at("failures").size(), 1u);
  EXPECT_EQ(lpi.at("failures").at(0).at("kind"), "refused");
  EXPECT_NE(lpi.at("failures").at(0).at("text").get<std::string>().find("2 of 2 runs failed: " + std::string(kRefusal)),
            std::string::npos);
  EXPECT_TRUE(lpi.at("costs").empty());

  const json& csl = method_entry(summary, "csl");
  EXPECT_EQ(csl.at("wins").size(), 2u);
  EXPECT_TRUE(csl.at("failures").empty());  // its best (0.01) is the best of the mirror scene
}

TEST_F(SummarizeTest, CostModelBreakEvenAndClaims) {
  const json summary = json::parse(read_text(write_summary(both(), (root / "out").string()).json));
  const json& cost = method_entry(summary, "csl").at("costs").at(0);
  EXPECT_EQ(cost.at("runs"), 2);
  EXPECT_EQ(cost.at("prepare_seconds"), json({2.0, 5.0}));
  EXPECT_EQ(cost.at("memory_bytes"), json({4000000.0, 64000000.0}));
  EXPECT_EQ(cost.at("frame_ms"), json({8.0, 200.0}));
  EXPECT_EQ(cost.at("best_error"), 0.01);

  // csl rays=64 (8 ms, 2 s) against pinhole samples=1000 (40 ms, 0 s, more accurate): 2000 / 32 = 62.5,
  // so from frame 63 on.
  const json& mirror = summary.at("scenes").at(0);
  ASSERT_EQ(mirror.at("break_even").size(), 1u);
  EXPECT_EQ(mirror.at("break_even").at(0).at("precomputing").at("run"), "csl_64");
  EXPECT_EQ(mirror.at("break_even").at(0).at("competitor").at("run"), "pin_1000");
  EXPECT_DOUBLE_EQ(mirror.at("break_even").at(0).at("frames").get<double>(), 63.0);

  const json& claims = summary.at("experiments").at(1).at("claims");
  ASSERT_EQ(claims.size(), 2u);
  EXPECT_EQ(claims.at(0).at("verdict"), "confirmed");
  EXPECT_EQ(claims.at(1).at("verdict"), "refuted");
  EXPECT_FALSE(claims.at(0).at("evidence").get<std::string>().empty());
}

TEST_F(SummarizeTest, ExperimentsOfTheSameNameInTwoResultsFoldersAreTitledByFolder) {
  fs::copy(results, root / "again", fs::copy_options::recursive);
  const std::string first = (results / "study_mirror").string(), second = (root / "again" / "study_mirror").string();
  const json summary = json::parse(read_text(write_summary({first, second}, (root / "out").string()).json));
  ASSERT_EQ(summary.at("scenes").size(), 2u);
  EXPECT_EQ(summary.at("scenes").at(0).at("title"), fs::path(first).lexically_normal().string());
  EXPECT_EQ(summary.at("scenes").at(1).at("title"), fs::path(second).lexically_normal().string());
}

TEST_F(SummarizeTest, BadInputIsRefusedAndNothingIsWritten) {
  const fs::path out = root / "out";
  EXPECT_THROW(write_summary({(results / "study_mirror").string(), (root / "no_such").string()}, out.string()),
               InputError);
  EXPECT_THROW(write_summary({(results / "study_mirror").string(), (results / "study_mirror").string()}, out.string()),
               InputError);
  EXPECT_FALSE(fs::exists(out));

  // The command line: exit 2, the folder named, nothing written; and a good call writes into RESULTS.
  std::string output;
  const std::string binary = CAUSTICBENCH_BINARY;
  int code = testing::run_command(binary + " summarize " + (results / "study_mirror").string() + " " +
                                      (root / "no_such").string() + " 2>&1",
                                  output);
  EXPECT_EQ(code, 2) << output;
  EXPECT_NE(output.find("no_such"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(results / "summary.html"));
  code = testing::run_command(binary + " summarize " + (results / "study_mirror").string() + " " +
                                  (results / "study_glass").string() + " 2>&1",
                              output);
  EXPECT_EQ(code, 0) << output;
  EXPECT_TRUE(fs::exists(results / "summary.html") && fs::exists(results / "summary.md") &&
              fs::exists(results / "summary.json"));
  EXPECT_NE(output.find("study_glass (ssim): 16.7 ms pinhole, 100 ms photon_map, 1 s photon_map"), std::string::npos)
      << output;
}

}  // namespace
}  // namespace causticbench
