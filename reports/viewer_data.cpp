#include "reports/viewer_data.h"

#include <Imath/half.h>
#include <OpenImageIO/strutil.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "core/files.h"

namespace causticbench::report_detail {

namespace fs = std::filesystem;

ViewerData::ViewerData(fs::path folder) : folder_(std::move(folder)) { ensure_folder(folder_.string()); }

std::string ViewerData::add_pixels(const std::string& id, const std::string& stem, const Image& image, int channels) {
  const size_t count = image.pixel_count() * static_cast<size_t>(channels);
  std::string bytes(count * 2, '\0');
  size_t at = 0;
  for (size_t pixel = 0; pixel < image.pixel_count(); ++pixel)
    for (int c = 0; c < channels; ++c) {
      float value = image.at(pixel, std::min(c, image.channels() - 1));
      // Half floats hold up to 65504; a larger value shows as infinity, which the page reads as such.
      const uint16_t half = imath_float_to_half(value);
      bytes[at++] = static_cast<char>(half & 0xff);  // little-endian, as every browser's Uint16Array
      bytes[at++] = static_cast<char>(half >> 8);
    }
  const std::string name = stem + ".js";
  const nlohmann::json quoted_id = id;
  std::string script = "causticbenchViewer.receive(" + quoted_id.dump() + ", \"" +
                       OIIO::Strutil::base64_encode(bytes) + "\");\n";
  write_text_atomically((folder_ / name).string(), script);
  written_.push_back(name);
  bytes_ += script.size();
  return "report/view/" + name;
}

size_t ViewerData::finish() {
  for (const auto& entry : fs::directory_iterator(folder_)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && entry.path().extension() == ".js" &&
        std::find(written_.begin(), written_.end(), name) == written_.end() && !is_partial_file_name(name))
      fs::remove(entry.path());
  }
  return bytes_;
}

nlohmann::json colour_map_table(int colour_map) {
  cv::Mat ramp(1, 256, CV_8U), coloured;
  for (int i = 0; i < 256; ++i) ramp.at<uint8_t>(0, i) = static_cast<uint8_t>(i);
  cv::applyColorMap(ramp, coloured, colour_map);
  nlohmann::json table = nlohmann::json::array();
  for (int i = 0; i < 256; ++i) {
    const cv::Vec3b bgr = coloured.at<cv::Vec3b>(0, i);
    table.push_back(bgr[2]), table.push_back(bgr[1]), table.push_back(bgr[0]);
  }
  return table;
}

}  // namespace causticbench::report_detail
