// Helpers shared by the report tests (test_report.cpp, test_report_pictures.cpp,
// test_report_variants.cpp): the synthetic results folder and its fixture ReportTest, reading and
// writing it, CSV cells, word counts, the DOM Chromium renders, test images.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/gbuffer.h"
#include "core/image.h"
#include "store/run_record.h"
#include "metrics/metrics.h"
#include "reports/report.h"
#include "tests/test_support.h"

#include <gtest/gtest.h>

namespace causticbench::report_testing {

namespace fs = std::filesystem;
using nlohmann::json;

inline std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

inline void write_json(const fs::path& path, const json& value) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << value.dump(2);
}

inline std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::string part;
  std::stringstream stream(text);
  while (std::getline(stream, part, separator)) parts.push_back(part);
  return parts;
}

// One CSV line (RFC 4180 quoting, no embedded newlines).
inline std::vector<std::string> csv_cells(const std::string& line) {
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

inline size_t count(const std::string& text, const std::string& word) {
  size_t n = 0;
  for (size_t at = text.find(word); at != std::string::npos; at = text.find(word, at + word.size())) ++n;
  return n;
}

// report.html as headless Chromium leaves it after the scripts ran (empty when Chromium fails).
inline std::string chromium_dom(const std::string& html) {
  std::string dom;
  for (const char* headless : {"--headless=new", "--headless"}) {
    std::string command = std::string("timeout 60 /usr/bin/chromium ") + headless +
                          " --no-sandbox --disable-gpu --disable-dev-shm-usage --no-first-run"
                          " --virtual-time-budget=10000 --dump-dom 'file://" +
                          html + "' 2>/dev/null";
    std::string output;
    int code = testing::run_command(command, output);
    if (code == 0 && output.find("</html>") != std::string::npos) return output;
  }
  return dom;
}

// The spec of one plot of report.html, as the page's script gets it; null when the page has no such plot.
inline json plot_spec(const std::string& page, const std::string& id) {
  size_t at = page.find("[\"" + id + "\", ");
  if (at == std::string::npos) return nullptr;
  std::string line = page.substr(at, page.find('\n', at) - at);
  if (!line.empty() && line.back() == ',') line.pop_back();
  return json::parse(line)[1];
}

// A caustic-like blob on a dark receiver; `noise` adds a deterministic per-pixel error.
// 384 x 288, so that thumbnails are shrunk to 256 x 192.
inline Image blob(double noise, int width = 384, int height = 288) {
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
inline std::string label(const FakeRun& run) {
  std::string text = run.method;
  for (const auto& [name, value] : run.swept.items()) text += " " + name + "=" + value.dump();
  return text;
}

inline const char* const kFailure = "out of memory: photon buffer exceeded 2 GiB, at 1600 \"samples\"";

// The synthetic experiment: two methods with sweeps, one failed run, one run not yet run.
//   photon_map photons sweep at k=50:   (5 ms, 0.1)  (12 ms, 0.02)  (40 ms, 0.005)   all on the front
//   photon_map photons=1e5 k=10:        (14 ms, 0.05)                               dominated by (12, 0.02)
//   pinhole samples=100 / 400:          (8 ms, 0.03) (30 ms, 0.04)                   400 dominated by 100
//   pinhole samples=1600: failed
// (render_ms median = 0.75 x frame ms.) Its claims and their verdicts:
//   0 best relmse among photon_map, expect k=50: 0.005 (k=50) beats 0.05 (k=10)          confirmed
//   1 best psnr among pinhole, expect samples=400: samples=100 has the higher PSNR       refuted
//   2 better frame_ms, photons=10000 (5 ms) than every pinhole run (best 8 ms)           confirmed
//   3 better relmse, samples=1600 (failed only) than photon_map                          not measured
//   4 linear render_ms in photons among photon_map: grouped by k; k=50 has 3 points,
//     R^2 = 256/259 >= 0.98; k=10 has 1 point and is not fitted                          confirmed
//   5 linear frame_ms in samples among pinhole: 2 ok points                              not measured
//   6 linear render_ms in photons among photon_map,k=50 with min_r2 0.99: 256/259 < 0.99 refuted
// The synthetic results folder above, written afresh for each test (removed after a passing one, unless
// CAUSTICBENCH_KEEP_REPORT is set).
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
        {"pin_100", "pinhole", {{"filtering", "none"}}, {{"samples", 100}}, {{"samples", 100}}, 0.03, 8.0},
        {"pin_400", "pinhole", {{"filtering", "none"}}, {{"samples", 400}}, {{"samples", 400}}, 0.04, 30.0},
        {"pin_1600", "pinhole", {{"filtering", "none"}}, {{"samples", 1600}}, {{"samples", 1600}}, 0.0, 0.0, true},
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
          {{"pass", pass}, {"photons", 2000000 * pass}, {"seconds", 0.4 * pass}, {"error_estimate", 4e-3 / pass}});
    write_json(reference / "record.json",
               {{"method", "reference"}, {"passes", 8}, {"seconds", 3.2}, {"error_estimate", 5e-4}, {"history", history}});
    fs::create_directories(reference);
    write_exr(blob(0.0), (reference / "frame_0000.exr").string());
    // Its G-buffer as the reference cache stores it (GBuffer::to_image): every pixel a receiver. The
    // report scores its baselines against it.
    GBuffer gbuffer;
    gbuffer.width = 384;
    gbuffer.height = 288;
    gbuffer.position.assign(gbuffer.pixel_count(), Vec3(0.0f));
    gbuffer.normal.assign(gbuffer.pixel_count(), Vec3(0.0f, 1.0f, 0.0f));
    gbuffer.albedo.assign(gbuffer.pixel_count(), Color(0.8f));
    gbuffer.object.assign(gbuffer.pixel_count(), 0);
    gbuffer.receiver.assign(gbuffer.pixel_count(), 1);
    gbuffer.footprint.assign(gbuffer.pixel_count(), 0.01f);
    write_exr(gbuffer.to_image(), (reference / "gbuffer_0000.exr").string());

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

  // runs/<key>/record.json (and the frame of an ok run), built as the experiment runner builds it
  // (store/run_record.h). Like a record from before scene variants, it names no variant or
  // reference: the report assigns the experiment's.
  RunRecord fake_record(const FakeRun& run) const {
    RunRecord record;
    record.key = run.key;
    record.method = run.method;
    record.label = label(run);
    record.build = run.build;
    record.render = run.render;
    record.swept = run.swept;
    record.git_revision = "abcdef123456";
    if (run.failed) {
      record.status = "failed";
      record.error = kFailure;
      return record;
    }
    const double render = run.frame_ms * 0.75;
    const std::map<std::string, double> metrics = {{"relmse", run.relmse},
                                                   {"rmse", std::sqrt(run.relmse)},
                                                   {"psnr", 20.0 - 10.0 * std::log10(run.relmse)},
                                                   {"energy_ratio", 1.0 - run.relmse},
                                                   {"nonfinite_pixels", 0}};
    FrameRecord frame;
    frame.image = "frame_0000.exr";
    frame.update_ms = {run.frame_ms * 0.25};
    frame.render_ms = {render};
    frame.metrics = metrics;
    record.frames = {frame};
    record.prepare.prepare_seconds = 0.5;
    record.timings = {run.frame_ms * 0.24, run.frame_ms * 0.25, render * 0.99, render, run.frame_ms * 0.99, run.frame_ms,
                      std::nullopt, std::nullopt};
    record.metrics = metrics;
    record.memory_bytes = 4800000;
    record.peak_rss_bytes = 123456789;
    record.counters = {{"photons_emitted", 12345}};
    return record;
  }

  void write_run(const FakeRun& run) const {
    fs::path run_folder = folder / "runs" / run.key;
    fs::create_directories(run_folder);
    if (!run.failed) write_exr(blob(std::sqrt(run.relmse)), (run_folder / "frame_0000.exr").string());
    write_json(run_folder / "record.json", fake_record(run).to_json());
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

}  // namespace causticbench::report_testing
