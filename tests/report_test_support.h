// Helpers shared by the report tests (test_report.cpp, test_report_variants.cpp): reading and
// writing the synthetic results folder, CSV cells, word counts, the DOM Chromium renders, test images.
#pragma once


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
#include "core/image.h"
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
//   1 best psnr among pinhole, expect samples=400: samples=100 has the higher PSNR       not confirmed
//   2 better frame_ms, photons=10000 (5 ms) than every pinhole run (best 8 ms)           confirmed
//   3 better relmse, samples=1600 (failed only) than photon_map                          not measured
//   4 linear render_ms in photons among photon_map: grouped by k; k=50 has 3 points,
//     R^2 = 256/259 >= 0.98; k=10 has 1 point and is not fitted                          confirmed
//   5 linear frame_ms in samples among pinhole: 2 ok points                              not measured
//   6 linear render_ms in photons among photon_map,k=50 with min_r2 0.99: 256/259 < 0.99 not confirmed
}  // namespace causticbench::report_testing
