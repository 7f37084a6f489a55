// Seeds with confidence (an experiment's `seeds: N`; experiments/seed_replicas.h, metrics/confidence.h):
// the Student-t quantile against the table it extends; the interval's coverage, measured on photon_map at
// few photons, where a run's error varies from seed to seed; and a seeded experiment end to end: every
// stochastic run measured with its N seeds under its unchanged key (each seed's image the one a run with
// that seed alone gives), a deterministic run measured once with an interval of zero width, the
// standard-deviation images, a run stored with fewer seeds measured again, the report's intervals and
// "not separated" verdicts, and the viewer's spread pane in headless Chromium.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/image.h"
#include "metrics/confidence.h"
#include "metrics/metrics.h"
#include "reports/report_text.h"
#include "tests/report_test_support.h"
#include "tests/test_support.h"

namespace causticbench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

TEST(Confidence, StudentQuantileExtendsItsTableSmoothly) {
  // The table's first entries (any statistics book) and the normal quantile far out.
  EXPECT_NEAR(student_t_975(1), 12.706, 1e-3);
  EXPECT_NEAR(student_t_975(4), 2.776, 1e-3);
  EXPECT_NEAR(student_t_975(30), 2.042, 1e-3);
  // The expansion from 31 on agrees with exact values (R: qt(0.975, n)) to 2e-6.
  EXPECT_NEAR(student_t_975(31), 2.0395134, 2e-6);
  EXPECT_NEAR(student_t_975(40), 2.0210754, 2e-6);
  EXPECT_NEAR(student_t_975(100), 1.9839715, 2e-6);
  EXPECT_NEAR(student_t_975(100000), 1.9599877, 1e-6);
  for (int n = 1; n < 200; ++n) EXPECT_GT(student_t_975(n), student_t_975(n + 1)) << n;
}

TEST(Confidence, IntervalOfKnownValues) {
  // 1, 2, 3, 4: mean 2.5, s = sqrt(5/3), half-width t(3) s / 2.
  const MetricInterval interval = interval_of({1.0, 2.0, 3.0, 4.0});
  EXPECT_DOUBLE_EQ(interval.mean, 2.5);
  EXPECT_NEAR(interval.standard_deviation, std::sqrt(5.0 / 3.0), 1e-12);
  EXPECT_NEAR(interval.half_width, 3.1824463 * std::sqrt(5.0 / 3.0) / 2.0, 1e-6);
  EXPECT_EQ(interval.count, 4);
  const MetricInterval one = interval_of({0.7});
  EXPECT_EQ(one.half_width, 0.0);
  EXPECT_TRUE(intervals_overlap(interval, MetricInterval{2.5 + interval.half_width + 0.1, 0.1, 0, 4}));
  EXPECT_FALSE(intervals_overlap(interval, MetricInterval{2.5 + interval.half_width + 0.1, 0.05, 0, 4}));
}

// The interval a run with N seeds reports covers the expected error at its stated rate. photon_map at 300
// photons on the small glass sphere, scored with relMSE against one fixed image: the mean of 400 seeds
// stands for the expectation (its standard error is a thirtieth of a 2-seed interval's half-width), and
// 200 disjoint pairs of consecutive seeds (base and base + 1, as the runner takes them) each give an
// interval (interval_of, as the runner's). With exact 95 % coverage, from 181 to 199 of them cover it with
// probability 0.997 (binomial). Two seeds tell the quantile apart best: the normal quantile in place of
// Student's (t = 12.7 at one degree of freedom) covers about 150, an interval without 1/sqrt(N) all 200.
// Measured: 186 (at 4 seeds 97 of 100; the relMSE over seeds is skewed, 0.53 to 1.47 around 0.86).
TEST(Confidence, TwoSeedIntervalsCoverTheMeanOfManySeedsAtTheirRate) {
  const Scene scene = testing::scene_from_yaml(
      testing::replace_once(testing::kSmallGlassSphere, "resolution: [40, 40]", "resolution: [24, 24]"));
  const FrameResult fixed = testing::render(scene, "photon_map", {"photons=200000", "seed=99999"});
  const Image& reference = fixed.caustic;
  std::vector<uint8_t> mask(fixed.gbuffer.receiver.begin(), fixed.gbuffer.receiver.end());
  auto error_of = [&](int seed) {
    const FrameResult result = testing::render(scene, "photon_map", {"photons=300", "seed=" + std::to_string(seed)});
    return compute_metrics(result.caustic, reference, mask, {"relmse"}).values.at("relmse");
  };
  std::vector<double> many;
  for (int seed = 1; seed <= 400; ++seed) many.push_back(error_of(seed));
  const MetricInterval expected = interval_of(many);
  int covered = 0, groups = 200;
  double mean_half_width = 0.0;
  for (int g = 0; g < groups; ++g) {
    const MetricInterval interval = interval_of({error_of(1000 + 2 * g), error_of(1001 + 2 * g)});
    covered += interval.contains(expected.mean);
    mean_half_width += interval.half_width / groups;
  }
  std::printf("relmse over 400 seeds %.4f (s %.4f, standard error %.5f); 2-seed intervals: mean half-width %.4f, "
              "%d of %d cover it\n",
              expected.mean, expected.standard_deviation, expected.standard_deviation / 20.0, mean_half_width, covered,
              groups);
  EXPECT_LT(expected.standard_deviation / 20.0, 0.05 * mean_half_width) << "the large sample's own spread is small";
  EXPECT_GE(covered, 181);
  EXPECT_LE(covered, 199);
}

class SeededExperiment : public ::testing::Test {
 protected:
  void SetUp() override {
    folder.write("scene.yaml", testing::replace_once(testing::kSmallGlassSphere, "resolution: [40, 40]", "resolution: [24, 24]"));
  }
  std::string experiment(const std::string& name, int seeds, const std::string& methods) const {
    return folder.write(name + ".yaml", "name: " + name + R"(
scene: scene.yaml
reference: {photons_per_pass: 100000, max_passes: 2, target_error: 0}
repetitions: 1
metrics: [relmse, flip]
seeds: )" + std::to_string(seeds) + "\nmethods:\n" + methods);
  }
  int run(const std::string& file, std::string& output) const {
    return testing::run_command(std::string(CAUSTICBENCH_BINARY) + " run " + file + " --results " + results(), output);
  }
  std::string results() const { return folder.path("results"); }
  json record_of(const std::string& experiment_name, const std::string& label) const {
    for (const auto& entry : fs::directory_iterator(results() + "/" + experiment_name + "/runs")) {
      json record = json::parse(report_testing::read_text(entry.path() / "record.json"));
      if (record["label"] == label) {
        record["folder"] = entry.path().string();
        return record;
      }
    }
    return json();
  }
  // One folder per test: CTest runs the tests of this fixture as processes side by side.
  testing::TemporaryFolder folder{std::string("seeds_") + ::testing::UnitTest::GetInstance()->current_test_info()->name()};
};

constexpr const char* kMethods = R"(  - method: photon_map
    sweep: {photons: [250, 1000, 1100, 8000]}
  - method: caustic_mapping
claims:
  - {text: "8000 photons beat 250", kind: better, metric: relmse, run: "photons=8000", than: "photons=250"}
  - {text: "1100 photons beat 1000", kind: better, metric: relmse, run: "photons=1100", than: "photons=1000"}
)";

TEST_F(SeededExperiment, EveryStochasticRunIsMeasuredWithItsSeedsUnderItsKey) {
  std::string output;
  const std::string file = experiment("seeded", 3, kMethods);
  ASSERT_EQ(run(file, output), 0) << output;
  EXPECT_NE(output.find("5 run now, 0 failed"), std::string::npos) << output;
  const json record = record_of("seeded", "photon_map photons=1000");
  ASSERT_TRUE(record.is_object());
  const fs::path run_folder = record["folder"].get<std::string>();
  ASSERT_TRUE(record.contains("seeds"));
  const json& seeds = record["seeds"];
  ASSERT_EQ(seeds["runs"].size(), 3u);
  EXPECT_EQ(record["build"]["seed"], 1) << "the run's own knobs keep its seed";
  std::vector<double> errors;
  std::vector<Image> images;
  for (int s = 0; s < 3; ++s) {
    const json& one = seeds["runs"][s];
    EXPECT_EQ(one["seed"], 1 + s);
    errors.push_back(one["metrics"]["relmse"].get<double>());
    images.push_back(read_exr((run_folder / one["frames"][0]["image"].get<std::string>()).string()));
  }
  EXPECT_EQ(seeds["runs"][0]["frames"][0]["image"], "frame_0000.exr");
  EXPECT_NE(errors[0], errors[1]) << "independent seeds give other errors";
  const MetricInterval interval = interval_of(errors);
  EXPECT_NEAR(record["metrics"]["relmse"].get<double>(), interval.mean, 1e-12);
  EXPECT_NEAR(seeds["intervals"]["relmse"]["half_width"].get<double>(), interval.half_width, 1e-12);
  EXPECT_NEAR(record["frames"][0]["metrics"]["relmse"].get<double>(), interval.mean, 1e-12) << "frame metrics: means too";

  // The per-pixel standard deviation over the seeds.
  const Image spread = read_exr((run_folder / seeds["stddev_images"][0].get<std::string>()).string());
  double largest = 0.0;
  for (size_t i = 0; i < spread.values().size(); ++i) {
    double mean = 0.0, squares = 0.0;
    for (const Image& image : images) mean += image.values()[i] / 3.0;
    for (const Image& image : images) squares += (image.values()[i] - mean) * (image.values()[i] - mean);
    EXPECT_NEAR(spread.values()[i], std::sqrt(squares / 2.0), 1e-5 * (1.0 + std::sqrt(squares))) << i;
    largest = std::max(largest, static_cast<double>(spread.values()[i]));
  }
  EXPECT_GT(largest, 0.0);

  // Seed 2's image is what a run with seed 2 alone gives.
  const std::string alone = experiment("alone", 1, "  - method: photon_map\n    build: {photons: 1000, seed: 2}\n");
  ASSERT_EQ(run(alone + " --no-report", output), 0) << output;
  const json second = record_of("alone", "photon_map");
  const Image seed_two = read_exr((fs::path(second["folder"].get<std::string>()) / "frame_0000.exr").string());
  EXPECT_EQ(seed_two.values(), images[1].values());

  // The deterministic method: measured once, with an interval of zero width in the report.
  const json mapping = record_of("seeded", "caustic_mapping");
  EXPECT_FALSE(mapping.contains("seeds"));
  const json stored = json::parse(report_testing::read_text(results() + "/seeded/results.json"));
  const std::string csv = report_testing::read_text(results() + "/seeded/results.csv");
  EXPECT_NE(csv.find("seeds,"), std::string::npos);
  EXPECT_NE(csv.find("relmse.ci95"), std::string::npos);
  const std::string markdown = report_testing::read_text(results() + "/seeded/report.md");
  using report_detail::num;
  const std::string shown = num(interval.mean) + " \u00b1 " + num(interval.half_width);
  EXPECT_NE(markdown.find(shown), std::string::npos) << shown << "\n" << markdown.substr(0, 4000);
  const size_t mapping_row = markdown.find("| caustic_mapping | caustic_mapping");
  ASSERT_NE(mapping_row, std::string::npos);
  EXPECT_NE(markdown.substr(mapping_row, markdown.find('\n', mapping_row) - mapping_row).find(" \u00b1 0 |"),
            std::string::npos)
      << "a deterministic run's interval has zero width";
  // Error against time: photon_map's line along its photons, with its seed band around the means.
  const std::string page = report_testing::read_text(results() + "/seeded/report.html");
  const json plot = report_testing::plot_spec(page, "plot-error-time");
  ASSERT_TRUE(plot.is_object());
  EXPECT_EQ(plot["layer"][0]["mark"]["type"], "area");
  EXPECT_EQ(plot["layer"][0]["encoding"]["y2"]["field"], "high");
  size_t banded = 0;
  for (const json& row : plot["layer"][0]["data"]["values"]) {
    if (!row.contains("low")) continue;
    ++banded;
    EXPECT_LT(row["low"].get<double>(), row["error"].get<double>());
    EXPECT_GT(row["high"].get<double>(), row["error"].get<double>());
  }
  EXPECT_EQ(banded, 4u) << "photon_map's four photon counts";
  if (fs::exists("/usr/bin/chromium")) {
    const std::string dom = report_testing::chromium_dom(results() + "/seeded/report.html");
    EXPECT_EQ(dom.find("class=\"plot-error\""), std::string::npos) << "vega-embed reported an error";
  }
  std::map<std::string, std::string> verdicts;
  for (const json& claim : stored["claims"]) verdicts[claim["text"]] = claim["verdict"];
  EXPECT_EQ(verdicts["8000 photons beat 250"], "confirmed");
  EXPECT_EQ(verdicts["1100 photons beat 1000"], "not separated");

  // Stored with 3 seeds: a second run with 3 does nothing; with 4, the stochastic runs are measured again
  // under the same keys, the deterministic one is not.
  ASSERT_EQ(run(file + " --no-report", output), 0) << output;
  EXPECT_NE(output.find("0 run now"), std::string::npos) << output;
  const std::string more = folder.write("more.yaml", testing::replace_once(report_testing::read_text(file), "seeds: 3", "seeds: 4"));
  ASSERT_EQ(run(more + " --no-report", output), 0) << output;
  EXPECT_NE(output.find("4 run now, 0 failed"), std::string::npos) << output;
  EXPECT_EQ(record_of("seeded", "photon_map photons=1000")["seeds"]["runs"].size(), 4u);
  // `status` counts the same way: with 5 seeds asked, the four stochastic runs are pending.
  const std::string experiment_json = results() + "/seeded/experiment.json";
  json asked = json::parse(report_testing::read_text(experiment_json));
  asked["seeds"] = 5;
  report_testing::write_json(experiment_json, asked);
  EXPECT_EQ(testing::run_command(std::string(CAUSTICBENCH_BINARY) + " status " + results() + "/seeded", output), 3) << output;
  EXPECT_NE(output.find("1 stored ok, 0 failed, 4 pending"), std::string::npos) << output;
  asked["seeds"] = 4;
  report_testing::write_json(experiment_json, asked);

  // The viewer shows the standard deviation over the seeds in its own pane (read back under the cursor);
  // a deterministic run has none, and its pane stays hidden.
  if (!fs::exists("/usr/bin/chromium")) GTEST_SKIP() << "chromium is not installed (scripts/setup.sh installs it)";
  ASSERT_EQ(testing::run_command(std::string(CAUSTICBENCH_BINARY) + " report " + results() + "/seeded", output), 0) << output;
  const json four = record_of("seeded", "photon_map photons=1000");
  const Image spread_four = read_exr((fs::path(four["folder"].get<std::string>()) / "stddev_0000.exr").string());
  size_t pixel = 0;
  for (size_t i = 0; i < spread_four.pixel_count(); ++i)
    if (spread_four.at(i, 1) > spread_four.at(pixel, 1)) pixel = i;
  const int x = static_cast<int>(pixel % 24), y = static_cast<int>(pixel / 24);
  const std::string viewer = results() + "/seeded/viewer.html";
  for (const std::string& label : {std::string("photon_map photons=1000"), std::string("caustic_mapping")}) {
    const std::string key = fs::path(record_of("seeded", label)["folder"].get<std::string>()).filename().string();
    const std::string dom =
        report_testing::chromium_dom(viewer + "#run=" + key + "&selftest=" + std::to_string(x) + "," + std::to_string(y));
    const size_t open = dom.find("<pre id=\"selftest\">"), close = dom.find("</pre>", open);
    ASSERT_NE(open, std::string::npos) << "the scripted session did not finish";
    const json log = json::parse(dom.substr(open + 19, close - open - 19));
    EXPECT_TRUE(log.at("errors").empty()) << log.at("errors").dump();
    if (label == "caustic_mapping") {
      EXPECT_TRUE(log.at("spread_value").is_null());
      EXPECT_FALSE(log.at("spread_visible").get<bool>());
      continue;
    }
    EXPECT_TRUE(log.at("spread_visible").get<bool>());
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(log.at("spread_value")[c].get<double>(), spread_four.at(pixel, c), 4.9e-4 * spread_four.at(pixel, c) + 6e-8);
    EXPECT_NE(log.at("readout").get<std::string>().find("\u03c3(E_c)"), std::string::npos) << log.at("readout");
  }
}

// The viewer's index, as viewer.html holds it.
json viewer_index(const std::string& page) {
  const std::string marker = "const INDEX = ";
  const size_t begin = page.find(marker) + marker.size(), end = page.find(";\nconst errors", begin);
  return json::parse(page.substr(begin, end - begin));
}

// An animation in the viewer: every frame of every run within the budget (here both), each with its own
// reference and spread over the seeds, chosen by the frame list (&frame=N); with `--viewer-mb 0` the first
// frame alone, and a note that says so.
TEST_F(SeededExperiment, TheViewerShowsEveryFrameOfAnAnimation) {
  folder.write("scene.yaml", testing::small_glass_sphere_turning(testing::replace_once(
                                 testing::kSmallGlassSphere, "resolution: [40, 40]", "resolution: [24, 24]")));
  std::string output;
  const std::string file = experiment("animated", 2, "  - method: photon_map\n    build: {photons: 3000}\n");
  const std::string text = testing::replace_once(report_testing::read_text(file), "repetitions: 1", "repetitions: 1\nframes: [0, 1]");
  ASSERT_EQ(run(folder.write("animated.yaml", text), output), 0) << output;
  const json record = record_of("animated", "photon_map");
  const fs::path run_folder = record["folder"].get<std::string>();
  const std::string key = run_folder.filename().string();
  const std::string viewer = results() + "/animated/viewer.html";
  json index = viewer_index(report_testing::read_text(viewer));
  ASSERT_EQ(index["runs"].size(), 1u);
  const json& frames = index["runs"][0]["frames"];
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[1]["frame"], 1);
  EXPECT_EQ(frames[1]["id"], key + "@1");
  EXPECT_NE(frames[0]["reference"], frames[1]["reference"]) << "each frame against its own reference";
  EXPECT_TRUE(frames[1].contains("stddev"));
  EXPECT_TRUE(frames[1].contains("flip"));

  if (fs::exists("/usr/bin/chromium")) {
    const Image image = read_exr((run_folder / "frame_0001.exr").string());
    const Image spread = read_exr((run_folder / "stddev_0001.exr").string());
    size_t pixel = 0;
    for (size_t i = 0; i < spread.pixel_count(); ++i)
      if (spread.at(i, 1) > spread.at(pixel, 1)) pixel = i;
    const int x = static_cast<int>(pixel % 24), y = static_cast<int>(pixel / 24);
    const std::string dom = report_testing::chromium_dom(viewer + "#run=" + key + "&frame=1&selftest=" + std::to_string(x) +
                                                         "," + std::to_string(y));
    const size_t open = dom.find("<pre id=\"selftest\">"), close = dom.find("</pre>", open);
    ASSERT_NE(open, std::string::npos) << "the scripted session did not finish";
    const json log = json::parse(dom.substr(open + 19, close - open - 19));
    EXPECT_TRUE(log.at("errors").empty()) << log.at("errors").dump();
    EXPECT_EQ(log.at("frame"), 1);
    EXPECT_EQ(log.at("frames"), json::array({0, 1}));
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(log.at("run_value")[c].get<double>(), image.at(pixel, c), 4.9e-4 * image.at(pixel, c) + 6e-8);
      EXPECT_NEAR(log.at("spread_value")[c].get<double>(), spread.at(pixel, c), 4.9e-4 * spread.at(pixel, c) + 6e-8);
    }
  }

  ASSERT_EQ(testing::run_command(std::string(CAUSTICBENCH_BINARY) + " report " + results() + "/animated --viewer-mb 0", output), 0)
      << output;
  index = viewer_index(report_testing::read_text(viewer));
  EXPECT_EQ(index["runs"][0]["frames"].size(), 1u);
  EXPECT_NE(index["runs"][0].value("frames_note", "").find("the first of its 2 frames"), std::string::npos) << index["runs"][0];
  for (const auto& entry : fs::directory_iterator(results() + "/animated/report/view"))
    EXPECT_EQ(entry.path().filename().string().find("_f1"), std::string::npos) << "frame 1's files are gone";
}

}  // namespace
}  // namespace causticbench
