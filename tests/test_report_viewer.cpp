// The report's image viewer (viewer.html, reports/viewer_data.h) on the synthetic results folder of
// report_test_support.h: its pixel files hold each run's E_c and its FLIP map as half floats (decoded here
// by an implementation of our own, independent of the page's), and in headless Chromium a scripted user
// zooms in, reads a known pixel's value under the cursor (equal to the EXR's within half precision), raises
// the exposure, flips to the reference and to the FLIP map, with no console error; a screenshot is kept
// when CAUSTICBENCH_KEEP_REPORT is set; the screenshot must show the FLIP pane painted.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <nlohmann/json.hpp>

#include "core/image.h"
#include "metrics/flip.h"
#include "reports/report.h"
#include "tests/report_test_support.h"

namespace causticbench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace report_testing;

// Base64 (RFC 4648) without the library the writer uses.
std::vector<uint8_t> decode_base64(const std::string& text) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::vector<uint8_t> bytes;
  uint32_t buffer = 0;
  int bits = 0;
  for (char c : text) {
    const int v = value(c);
    if (v < 0) continue;
    buffer = (buffer << 6) | static_cast<uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      bytes.push_back(static_cast<uint8_t>((buffer >> bits) & 0xff));
    }
  }
  return bytes;
}

float half_to_float(uint16_t h) {
  const int sign = h & 0x8000 ? -1 : 1, exponent = (h >> 10) & 31, mantissa = h & 1023;
  if (exponent == 0) return static_cast<float>(sign * mantissa * std::ldexp(1.0, -24));
  if (exponent == 31) return mantissa ? NAN : sign * INFINITY;
  return static_cast<float>(sign * (1.0 + mantissa / 1024.0) * std::ldexp(1.0, exponent - 15));
}

// The values of a pixel file: causticbenchViewer.receive("id", "<base64>");
std::vector<float> read_pixel_file(const fs::path& path, std::string* id = nullptr) {
  const std::string text = read_text(path);
  const size_t open = text.find('('), comma = text.find(", \"");
  if (id) *id = json::parse(text.substr(open + 1, comma - open - 1)).get<std::string>();
  const size_t begin = comma + 3, end = text.find('"', begin);
  const std::vector<uint8_t> bytes = decode_base64(text.substr(begin, end - begin));
  std::vector<float> values(bytes.size() / 2);
  for (size_t i = 0; i < values.size(); ++i) values[i] = half_to_float(static_cast<uint16_t>(bytes[2 * i] | (bytes[2 * i + 1] << 8)));
  return values;
}

json viewer_index(const fs::path& viewer_html) {
  const std::string page = read_text(viewer_html);
  const std::string marker = "const INDEX = ";
  const size_t begin = page.find(marker) + marker.size(), end = page.find(";\nconst errors", begin);
  return json::parse(page.substr(begin, end - begin));
}

// Half floats keep 11 significant bits: a relative error of at most 2^-11.
void expect_half_of(float half, float value, const std::string& what) {
  EXPECT_NEAR(half, value, std::abs(value) * 4.9e-4 + 6e-8) << what;
}

class ViewerTest : public ReportTest {
 protected:
  // The experiment measures flip too, so that its runs have FLIP maps.
  void with_flip() {
    json experiment = json::parse(read_text(folder / "experiment.json"));
    experiment["metrics"].push_back("flip");
    write_json(folder / "experiment.json", experiment);
  }
};

TEST_F(ViewerTest, PixelFilesHoldEveryRunsImageAndFlipMapInHalfFloats) {
  with_flip();
  const ReportSummary summary = write_report(folder.string());
  ASSERT_FALSE(summary.viewer.empty());
  const json index = viewer_index(summary.viewer);
  ASSERT_EQ(index.at("runs").size(), 6u);  // the ok runs; the failed one has no image
  const Image reference = read_exr((root / "results" / "references" / "ref123" / "frame_0000.exr").string());
  size_t bytes = 0;
  for (const json& run : index.at("runs")) {
    const std::string key = run.at("id");
    const Image image = read_exr((folder / "runs" / key / "frame_0000.exr").string());
    std::string id;
    const std::vector<float> values = read_pixel_file(folder / run.at("pixels").get<std::string>(), &id);
    EXPECT_EQ(id, key);
    ASSERT_EQ(values.size(), image.pixel_count() * 3) << key;
    for (size_t pixel = 0; pixel < image.pixel_count(); pixel += 997)
      for (int c = 0; c < 3; ++c) expect_half_of(values[3 * pixel + c], image.at(pixel, c), key);
    ASSERT_TRUE(run.contains("flip")) << key;
    const Image flip = flip_error_map(image, reference, std::vector<uint8_t>(reference.pixel_count(), 1));
    const std::vector<float> flip_values = read_pixel_file(folder / run.at("flip").get<std::string>());
    ASSERT_EQ(flip_values.size(), flip.pixel_count());
    for (size_t pixel = 0; pixel < flip.pixel_count(); pixel += 997) expect_half_of(flip_values[pixel], flip.at(pixel, 0), key + " flip");
    bytes += fs::file_size(folder / run.at("pixels").get<std::string>()) + fs::file_size(folder / run.at("flip").get<std::string>());
  }
  // One reference, shared by the runs; the page's exposure is the thumbnails' (middle grey at the mean).
  ASSERT_EQ(index.at("references").size(), 1u);
  const json& shown = index.at("references").begin().value();
  bytes += fs::file_size(folder / shown.at("pixels").get<std::string>());
  EXPECT_NEAR(std::exp2(shown.at("exposure_stops").get<double>()) * shown.at("mean").get<double>(), 0.18, 1e-9);
  EXPECT_EQ(summary.viewer_bytes, bytes);
  std::printf("viewer: %zu runs at 384 x 288, %.2f MB of pixel files\n", index.at("runs").size(), bytes / 1e6);
  // A run gone from the experiment loses its files at the next report.
  fs::remove_all(folder / "runs" / "pm_1e6");
  const ReportSummary again = write_report(folder.string());
  EXPECT_LT(again.viewer_bytes, bytes);
  for (const auto& entry : fs::directory_iterator(folder / "report" / "view"))
    EXPECT_EQ(entry.path().filename().string().find("pm_1e6"), std::string::npos) << entry.path();
}

TEST_F(ViewerTest, AScriptedUserZoomsReadsAPixelAndFlipsInChromium) {
  const char* chromium = "/usr/bin/chromium";
  if (!fs::exists(chromium)) GTEST_SKIP() << "chromium is not installed (scripts/setup.sh installs it)";
  with_flip();
  const ReportSummary summary = write_report(folder.string());
  ASSERT_FALSE(summary.viewer.empty());
  // Pixel (190, 130) lies in the blob's bright middle; pm_1e5 has noise there.
  const int x = 190, y = 130;
  const std::string dom = chromium_dom(summary.viewer + "#run=pm_1e5&selftest=" + std::to_string(x) + "," + std::to_string(y));
  ASSERT_FALSE(dom.empty()) << "chromium produced no DOM";
  const size_t open = dom.find("<pre id=\"selftest\">"), close = dom.find("</pre>", open);
  ASSERT_NE(open, std::string::npos) << "the scripted session did not finish";
  const json log = json::parse(dom.substr(open + 19, close - open - 19));
  std::printf("viewer session: %s\n", log.dump().c_str());
  EXPECT_TRUE(log.at("errors").empty()) << log.at("errors").dump();
  EXPECT_GT(log.at("scale").get<double>(), 4.0) << "zoomed in";
  EXPECT_EQ(log.at("cursor").at("x"), x);
  EXPECT_EQ(log.at("cursor").at("y"), y);
  const Image image = read_exr((folder / "runs" / "pm_1e5" / "frame_0000.exr").string());
  const Image reference = read_exr((root / "results" / "references" / "ref123" / "frame_0000.exr").string());
  const size_t pixel = static_cast<size_t>(y) * image.width() + x;
  for (int c = 0; c < 3; ++c) {
    expect_half_of(log.at("run_value")[c].get<float>(), image.at(pixel, c), "run under the cursor");
    expect_half_of(log.at("reference_value")[c].get<float>(), reference.at(pixel, c), "reference under the cursor");
  }
  const std::string readout = log.at("readout");
  EXPECT_NE(readout.find("pixel (190, 130)"), std::string::npos) << readout;
  EXPECT_NE(readout.find("W/m"), std::string::npos) << readout;
  EXPECT_TRUE(log.at("brighter").get<bool>()) << "two more stops brighten the pixel";
  const json index = viewer_index(summary.viewer);
  double stops = 0.0;
  for (const json& run : index.at("runs"))
    if (run.at("id") == "pm_1e5") stops = run.at("exposure_stops");
  EXPECT_NEAR(log.at("stops").get<double>(), std::round(stops * 10.0) / 10.0 + 2.0, 0.051) << "two stops up";
  EXPECT_EQ(log.at("steps")[0].at("solo"), "run");
  EXPECT_EQ(log.at("steps")[0].at("visible"), json::array({"run"}));
  EXPECT_EQ(log.at("steps")[1].at("solo"), "reference") << "f flips between the run and the reference";
  EXPECT_EQ(log.at("steps")[2].at("solo"), "error");
  const Image flip = flip_error_map(image, reference, std::vector<uint8_t>(reference.pixel_count(), 1));
  expect_half_of(log.at("flip_value").get<float>(), flip.at(pixel, 0), "FLIP under the cursor");
  EXPECT_EQ(log.at("error_label"), "HDR-FLIP map");
  // Measured once: no spread over seeds, and its pane stays hidden (a report written before seeds opens so).
  EXPECT_TRUE(log.at("spread_value").is_null());
  EXPECT_FALSE(log.at("spread_visible").get<bool>());
  // An index written before frames and seeds (each run's first frame on the run itself) still works.
  {
    std::string page = read_text(summary.viewer);
    json old_index = viewer_index(summary.viewer);
    for (json& run : old_index["runs"]) run.erase("frames");
    const std::string marker = "const INDEX = ";
    const size_t begin = page.find(marker) + marker.size(), end = page.find(";\nconst errors", begin);
    page = page.substr(0, begin) + old_index.dump() + page.substr(end);
    const fs::path older = fs::path(summary.viewer).parent_path() / "viewer_before_frames.html";
    std::ofstream(older, std::ios::binary) << page;
    const std::string old_dom = chromium_dom(older.string() + "#run=pm_1e5&selftest=" + std::to_string(x) + "," + std::to_string(y));
    const size_t at = old_dom.find("<pre id=\"selftest\">"), stop = old_dom.find("</pre>", at);
    ASSERT_NE(at, std::string::npos) << "the scripted session did not finish on the older index";
    const json old_log = json::parse(old_dom.substr(at + 19, stop - at - 19));
    EXPECT_TRUE(old_log.at("errors").empty()) << old_log.at("errors").dump();
    for (int c = 0; c < 3; ++c) expect_half_of(old_log.at("run_value")[c].get<float>(), image.at(pixel, c), "older index");
    expect_half_of(old_log.at("flip_value").get<float>(), flip.at(pixel, 0), "older index, FLIP");
  }
  // A screenshot of the session's end (the FLIP pane alone, zoomed in): the page paints its panes. Kept
  // (and its path printed) when CAUSTICBENCH_KEEP_REPORT is set.
  const std::string shot = (root / "viewer.png").string();
  std::string output;
  testing::run_command("timeout 60 /usr/bin/chromium --headless=new --no-sandbox --disable-gpu --window-size=1200,900 "
                       "--virtual-time-budget=10000 --screenshot='" + shot + "' 'file://" + summary.viewer +
                       "#run=pm_1e5&selftest=190,130' 2>/dev/null", output);
  const cv::Mat picture = cv::imread(shot, cv::IMREAD_COLOR);
  ASSERT_FALSE(picture.empty()) << "no screenshot at " << shot;
  EXPECT_EQ(picture.cols, 1200);
  // The FLIP values here are small (0.004 at the pixel): magma's dark end, bluer than red, unlike the page's
  // neutral grey or an unpainted black canvas; and its colour bar reaches magma's bright end.
  // The bar sits in the pane's lower corner, whose height follows the page's fonts (a horizontal scroll
  // bar under the self-test's log moved it below rows - 150 on one machine): it is looked for down to
  // the readout's bottom.
  size_t dark_magma = 0, bright = 0;
  for (int y = 100; y < picture.rows - 40; ++y)
    for (int x = 0; x < picture.cols; ++x) {
      const cv::Vec3b pixel = picture.at<cv::Vec3b>(y, x);  // B, G, R
      if (y < picture.rows - 150) dark_magma += pixel[0] > pixel[2] + 3;
      bright += pixel[2] > 200 && pixel[1] > 150 && pixel[0] < 200;
    }
  EXPECT_GT(dark_magma, 100000u) << "the FLIP pane is not painted in " << shot;
  EXPECT_GT(bright, 20u) << "no colour bar in " << shot;
  if (std::getenv("CAUSTICBENCH_KEEP_REPORT")) std::printf("screenshot: %s\n", shot.c_str());
}

}  // namespace
}  // namespace causticbench
