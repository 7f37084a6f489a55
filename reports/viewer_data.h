// The pixels behind the report's image viewer (viewer.html beside report.html, docs/reports.md, "The
// viewer"): every ok run's first frame, its reference and its HDR-FLIP map at full resolution, as half
// floats in script files under report/view/ that the page loads with <script src> (a page opened from
// file:// may not fetch). Each file is one call, causticbenchViewer.receive(id, "<base64>"), the little-
// endian half floats of the image row by row, top row first, channels interleaved. The page's index of
// entries (their ids, sizes, files, exposures and error scales) is written into viewer.html itself.
#pragma once

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "core/image.h"

namespace causticbench::report_detail {

class ViewerData {
 public:
  // Files go under `folder` (report/view/); their names relative to the experiment's folder are
  // "report/view/<name>". Files of entries not added again are removed by finish().
  explicit ViewerData(std::filesystem::path folder);

  // Writes `image` (its first `channels` channels, 3 for E_c, 1 for a FLIP map) as entry `id`, in file
  // `<stem>.js`; returns the file's path relative to the experiment's folder.
  std::string add_pixels(const std::string& id, const std::string& stem, const Image& image, int channels);

  // The index the page reads: the entries of runs and references, in order.
  nlohmann::json& index() { return index_; }
  const nlohmann::json& index() const { return index_; }
  // Removes the files under the folder that this report did not write, and returns the bytes written.
  size_t finish();

 private:
  std::filesystem::path folder_;
  nlohmann::json index_ = {{"runs", nlohmann::json::array()}, {"references", nlohmann::json::object()}};
  std::vector<std::string> written_;
  size_t bytes_ = 0;
};

// The 256 RGB entries (0 to 255 each) of OpenCV's colour map `colour_map` (cv::COLORMAP_INFERNO, ...):
// the error views use the thumbnails' maps.
nlohmann::json colour_map_table(int colour_map);

}  // namespace causticbench::report_detail
