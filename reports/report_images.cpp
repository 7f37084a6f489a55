// The pictures of the report under <experiment>/report/: a thumbnail of each variant's reference and
// of each ok run's first frame, exposed so that the reference's mean over the receivers is middle grey,
// an error map of each run against its own reference, and the colour bar of the error maps
// (docs/reports.md, "Images").
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <utility>

#include "core/errors.h"
#include "core/files.h"
#include "core/gbuffer.h"
#include "core/image.h"
#include "core/image_statistics.h"
#include "metrics/flip.h"
#include "reports/report_parts.h"
#include "reports/viewer_data.h"

namespace causticbench::report_detail {

namespace {

constexpr int kThumbnailWidth = 256;  // thumbnails are at most this wide (never enlarged)

cv::Mat to_mat(const Image& image) {
  cv::Mat mat(image.height(), image.width(), CV_32FC3);
  for (int y = 0; y < image.height(); ++y) {
    float* row = mat.ptr<float>(y);
    for (int x = 0; x < image.width(); ++x) {
      size_t pixel = static_cast<size_t>(y) * image.width() + x;
      for (int c = 0; c < 3; ++c) {
        float value = image.at(pixel, std::min(c, image.channels() - 1));
        row[3 * x + c] = std::isfinite(value) ? value : 0.0f;
      }
    }
  }
  return mat;
}

Image to_image(const cv::Mat& mat) {
  Image image(mat.cols, mat.rows, 3);
  for (int y = 0; y < mat.rows; ++y) {
    const float* row = mat.ptr<float>(y);
    for (int x = 0; x < mat.cols; ++x)
      for (int c = 0; c < 3; ++c) image.at(static_cast<size_t>(y) * mat.cols + x, c) = row[3 * x + c];
  }
  return image;
}

cv::Mat shrink(const cv::Mat& mat) {
  if (mat.cols <= kThumbnailWidth) return mat;
  int height = std::max(1, static_cast<int>(std::lround(mat.rows * static_cast<double>(kThumbnailWidth) / mat.cols)));
  cv::Mat small;
  cv::resize(mat, small, cv::Size(kThumbnailWidth, height), 0, 0, cv::INTER_AREA);
  return small;
}

// Pixels where the reference has caustic light (masked-out pixels are stored as zero): the fallback
// mask when a reference has no stored G-buffer.
std::vector<uint8_t> lit_mask(const Image& reference) {
  std::vector<uint8_t> mask(reference.pixel_count(), 0);
  for (size_t pixel = 0; pixel < reference.pixel_count(); ++pixel) {
    for (int c = 0; c < std::min(3, reference.channels()); ++c) {
      float value = reference.at(pixel, c);
      if (std::isfinite(value) && value > 0.0f) mask[pixel] = 1;
    }
  }
  return mask;
}

// The receiver mask of a reference frame, from its stored G-buffer (channel 10, "receiver"), so that
// the exposure matches `causticbench render`; the lit pixels when the G-buffer is missing.
std::vector<uint8_t> receiver_mask(const fs::path& reference_folder, int64_t frame, const Image& reference) {
  fs::path gbuffer_path = reference_folder / frame_file(frame, "gbuffer");
  if (fs::is_regular_file(gbuffer_path)) {
    Image gbuffer = GBuffer::read_image(gbuffer_path.string());
    if (gbuffer.channels() > GBuffer::kReceiverChannel && gbuffer.pixel_count() == reference.pixel_count()) {
      std::vector<uint8_t> mask(gbuffer.pixel_count(), 0);
      for (size_t pixel = 0; pixel < gbuffer.pixel_count(); ++pixel) {
        mask[pixel] = gbuffer.at(pixel, GBuffer::kReceiverChannel) > 0.5f;
      }
      return mask;
    }
  }
  return lit_mask(reference);
}

// Through the store's one atomic write (core/files.h): encoded in memory, then written and renamed.
void write_png_atomically(const cv::Mat& bgr, const fs::path& path) {
  std::vector<unsigned char> bytes;
  if (!cv::imencode(".png", bgr, bytes)) throw std::runtime_error("cannot encode " + path.string());
  write_file_atomically(path.string(), std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

void write_thumbnail(const Image& image, const fs::path& path, float exposure) {
  write_png(to_image(shrink(to_mat(image))), path.string(), exposure);
}

// |test - reference| as luminance, clamped to [0, scale], then shrunk, then coloured.
void write_error_map(const Image& test, const Image& reference, double scale, const fs::path& path) {
  cv::Mat error(reference.height(), reference.width(), CV_32F);
  for (int y = 0; y < reference.height(); ++y) {
    float* row = error.ptr<float>(y);
    for (int x = 0; x < reference.width(); ++x) {
      size_t pixel = static_cast<size_t>(y) * reference.width() + x;
      const float weights[3] = {0.2126f, 0.7152f, 0.0722f};
      double sum = 0.0;
      bool bad = false;
      for (int c = 0; c < 3; ++c) {
        float t = test.at(pixel, std::min(c, test.channels() - 1));
        float r = reference.at(pixel, std::min(c, reference.channels() - 1));
        if (!std::isfinite(t) || !std::isfinite(r)) bad = true;
        sum += weights[c] * std::abs(static_cast<double>(t) - r);
      }
      row[x] = bad ? 1.0f : static_cast<float>(std::clamp(sum, 0.0, scale) / scale);
    }
  }
  cv::Mat small = shrink(error), bytes, coloured;
  small.convertTo(bytes, CV_8U, 255.0);
  cv::applyColorMap(bytes, coloured, cv::COLORMAP_INFERNO);
  write_png_atomically(coloured, path);
}

// The HDR-FLIP map (values in [0, 1]: the metric's own scale, no clamping), shrunk, in magma as the
// FLIP tool shows it.
void write_flip_map(const Image& flip, const fs::path& path) {
  cv::Mat values(flip.height(), flip.width(), CV_32F);
  for (int y = 0; y < flip.height(); ++y) {
    float* row = values.ptr<float>(y);
    for (int x = 0; x < flip.width(); ++x) row[x] = flip.at(static_cast<size_t>(y) * flip.width() + x, 0);
  }
  cv::Mat small = shrink(values), bytes, coloured;
  small.convertTo(bytes, CV_8U, 255.0);
  cv::applyColorMap(bytes, coloured, cv::COLORMAP_MAGMA);
  write_png_atomically(coloured, path);
}

void write_colour_bar(const fs::path& path, int colour_map = cv::COLORMAP_INFERNO) {
  cv::Mat ramp(1, 256, CV_8U);
  for (int i = 0; i < 256; ++i) ramp.at<uint8_t>(0, i) = static_cast<uint8_t>(i);
  cv::Mat bar, coloured;
  cv::resize(ramp, bar, cv::Size(256, 12), 0, 0, cv::INTER_NEAREST);
  cv::applyColorMap(bar, coloured, colour_map);
  write_png_atomically(coloured, path);
}

struct ReferenceFrame {
  Image image;
  std::vector<uint8_t> mask;  // the receivers (or, without a stored G-buffer, the lit pixels)
  double mean = 0.0;  // masked mean (average of RGB) over the mask
  bool ok = false;
  std::string error;
};

std::string viewer_reference_id(const std::string& reference_key, int64_t frame) {
  return "reference/" + reference_key + "/" + std::to_string(frame);
}

// A reference frame in the viewer, once: its pixels and its receivers' mean (the runs' exposure and error
// scale come from it).
void add_reference_to_viewer(ViewerData& viewer, const ReferenceFrame& reference, const std::string& reference_key,
                             int64_t frame, const std::string& title) {
  const std::string id = viewer_reference_id(reference_key, frame);
  if (viewer.index()["references"].contains(id)) return;
  json entry = {{"id", id}, {"title", title}, {"frame", frame}, {"width", reference.image.width()},
                {"height", reference.image.height()}, {"mean", reference.mean}};
  entry["exposure_stops"] = reference.mean > 0.0 ? std::log2(kMiddleGrey / reference.mean) : 0.0;
  entry["pixels"] = viewer.add_pixels(id, "reference_" + file_safe(reference_key) + "_f" + std::to_string(frame),
                                      reference.image, 3);
  viewer.index()["references"][id] = entry;
}

// A reference that can be compared with `image`: readable, not black, of its size.
bool fits(const ReferenceFrame& reference, const Image& image) {
  return reference.ok && reference.mean > 0.0 && reference.image.width() == image.width() &&
         reference.image.height() == image.height();
}

// One frame of a run in the viewer: its E_c and, where there are any, its reference, FLIP map and spread
// over seeds. Its pixels are named "<key>" for the run's first frame and "<key>@<frame>" for the others.
json frame_view(ViewerData& viewer, const Report& report, const Run& run, size_t index, const Image& image,
                const ReferenceFrame& reference, const Image& flip) {
  const int64_t frame = run.record.frames.at(index).frame;
  const std::string id = index == 0 ? run.key : run.key + "@" + std::to_string(frame);
  const std::string stem = file_safe(run.key) + "_f" + std::to_string(frame);
  json view = {{"frame", frame}, {"id", id}};
  view["pixels"] = viewer.add_pixels(id, stem, image, 3);
  // Measured with several seeds: the per-pixel standard deviation over them, its own pane.
  if (run.record.seeds && index < run.record.seeds->stddev_images.size()) {
    const Image spread = read_exr((report.folder / "runs" / run.key / run.record.seeds->stddev_images[index]).string());
    view["stddev"] = viewer.add_pixels(id + "/stddev", stem + "_stddev", spread, 3);
  }
  if (fits(reference, image)) {
    add_reference_to_viewer(viewer, reference, run.reference_key, frame, "reference");
    view["reference"] = viewer_reference_id(run.reference_key, frame);
    if (flip.pixel_count() > 0) view["flip"] = viewer.add_pixels(id + "/flip", stem + "_flip", flip, 1);
  }
  return view;
}

// Frames beyond each run's first (docs/reports.md, "The viewer"): every k-th of its frames, k the least
// stride that keeps their estimated pixel files within Report::viewer_more_frames_bytes, the same frames for every
// run so that runs compare frame by frame. `runs`: (run index, its place in the viewer's index).
void add_more_frames(ViewerData& viewer, const Report& report, const std::vector<std::pair<size_t, size_t>>& runs,
                     bool with_flip, const std::function<ReferenceFrame&(const std::string&, int64_t)>& reference_frame) {
  double bytes = 0.0;
  for (const auto& [i, place] : runs) {
    const Run& run = report.runs[i];
    const json& entry = viewer.index()["runs"][place];
    // Base64 of half floats: 8/3 bytes a value; E_c, its reference and its spread 3 values a pixel, FLIP 1.
    const double values = 3.0 + 3.0 + (with_flip ? 1.0 : 0.0) + (run.record.seeds ? 3.0 : 0.0);
    bytes += static_cast<double>(run.record.frames.size() - 1) * entry["width"].get<double>() *
             entry["height"].get<double>() * values * 8.0 / 3.0;
  }
  if (bytes <= 0.0) return;
  const double budget = report.viewer_more_frames_bytes;
  // In double first: a budget of 1e-300 MB makes the ratio larger than any size_t, and its conversion
  // undefined (it once came out 0: every frame kept).
  const double ratio = budget > 0.0 ? std::ceil(bytes / budget) : std::numeric_limits<double>::infinity();
  const size_t stride = ratio >= 1e18 ? std::numeric_limits<size_t>::max() : std::max<size_t>(1, static_cast<size_t>(ratio));
  for (const auto& [i, place] : runs) {
    const Run& run = report.runs[i];
    json& entry = viewer.index()["runs"][place];
    const size_t count = run.record.frames.size();
    std::vector<std::string> notes;
    if (stride > 1 && count > 1)
      notes.push_back(stride >= count ? fmt::format("the first of its {} frames (report --viewer-mb 0)", count)
                                      : fmt::format("every {} frames of its {} (report --viewer-mb {:.0f}: what frames "
                                                    "beyond the first may take)", stride, count, budget / 1e6));
    // stride < count here, so index + stride cannot wrap.
    for (size_t index = stride; index < count; index += stride) {
      const FrameRecord& recorded = run.record.frames[index];
      const fs::path path = report.folder / "runs" / run.key / (recorded.image.empty() ? frame_file(recorded.frame) : recorded.image);
      try {
        const Image image = read_exr(path.string());
        const ReferenceFrame& reference = reference_frame(run.reference_key, recorded.frame);
        const Image flip = with_flip && fits(reference, image) ? flip_error_map(image, reference.image, reference.mask) : Image();
        entry["frames"].push_back(frame_view(viewer, report, run, index, image, reference, flip));
      } catch (const std::exception& failure) {
        notes.push_back(fmt::format("frame {} unreadable: {}", recorded.frame, failure.what()));
      }
    }
    if (!notes.empty()) entry["frames_note"] = join(notes, "; ");
  }
}

}  // namespace

void make_images(Report& report, std::set<std::string>& written) {
  fs::path images = report.folder / "report";
  ViewerData viewer(images / "view");
  // The FLIP map only where the experiment measures FLIP: its mean is then the flip column.
  const json& metrics = member(report.experiment, "metrics");
  const bool with_flip = metrics.is_array() && std::find(metrics.begin(), metrics.end(), json("flip")) != metrics.end();
  // Reference frames, keyed by (reference_key, frame): every run is compared with its own reference.
  std::map<std::pair<std::string, int64_t>, ReferenceFrame> references;
  auto reference_frame = [&](const std::string& key, int64_t frame) -> ReferenceFrame& {
    auto it = references.find({key, frame});
    if (it != references.end()) return it->second;
    ReferenceFrame& entry = references[{key, frame}];
    if (key.empty()) {
      entry.error = "no reference";
      return entry;
    }
    fs::path folder = report.reference_folder(key);
    fs::path path = folder / frame_file(frame);
    try {
      entry.image = read_exr(path.string());
      entry.mask = receiver_mask(folder, frame, entry.image);
      entry.mean = masked_mean(entry.image, entry.mask);
      entry.ok = true;
    } catch (const std::exception& failure) {
      entry.error = fmt::format("reference image {} unreadable: {}", path.string(), failure.what());
    }
    return entry;
  };

  int64_t first_frame = 0;
  const json& frames = member(report.experiment, "frames");
  if (frames.is_array() && !frames.empty() && frames[0].is_number_integer()) first_frame = frames[0].get<int64_t>();
  for (size_t i : report.ok_runs()) {
    if (!report.runs[i].record.frames.empty()) {
      first_frame = report.runs[i].record.frames.front().frame;
      break;
    }
  }

  // The references first: one per variant ("reference.png" when there is one variant).
  std::vector<std::string> scales;  // the error maps' saturation value of each variant
  for (const Variant& variant : report.variants) {
    ReferenceFrame& reference = reference_frame(variant.reference_key, first_frame);
    if (!reference.ok) {
      if (!variant.reference_key.empty())
        report.notes.push_back((report.multi() ? "Variant " + variant.name + ": " : std::string()) + reference.error +
                               ": thumbnails are exposed on their own mean and have no error maps.");
      continue;
    }
    Thumbnail thumb;
    thumb.reference = true;
    thumb.title = report.multi() ? "reference " + variant.name : "reference";
    std::string passes = member(variant.reference, "passes").is_number()
                             ? value_text(member(variant.reference, "passes")) + " passes"
                             : "";
    thumb.caption = fmt::format("frame {}{}{}", first_frame, passes.empty() ? "" : " \u00b7 " + passes,
                                variant.reference_error ? " \u00b7 reference error " + num(*variant.reference_error) : "");
    thumb.ec_png = report.multi() ? "reference_" + file_safe(variant.name) + ".png" : "reference.png";
    for (size_t n = 2; written.count(thumb.ec_png); ++n)
      thumb.ec_png = fmt::format("reference_{}_{}.png", file_safe(variant.name), n);
    float exposure = reference.mean > 0.0 ? static_cast<float>(kMiddleGrey / reference.mean) : 1.0f;
    write_thumbnail(reference.image, images / thumb.ec_png, exposure);
    written.insert(thumb.ec_png);
    add_reference_to_viewer(viewer, reference, variant.reference_key, first_frame, thumb.title);
    if (!(reference.mean > 0.0)) thumb.note = "black over the receivers: no error maps against it";
    report.thumbnails.push_back(thumb);
    if (!(reference.mean > 0.0)) continue;  // error maps need the reference's mean as their scale
    // The reference's own estimated error per pixel (error_<frame>.exr, docs/metrics.md), on the scale of
    // the runs' |test - reference| maps: where it is not dark, no run's error there can be resolved.
    const fs::path error_file = report.reference_folder(variant.reference_key) / frame_file(first_frame, "error");
    if (fs::is_regular_file(error_file)) {
      try {
        const Image error = read_exr(error_file.string());
        Thumbnail& shown = report.thumbnails.back();
        shown.error_png = shown.ec_png.substr(0, shown.ec_png.size() - 4) + "_error.png";
        write_error_map(error, Image(error.width(), error.height(), 3), kErrorScale * reference.mean, images / shown.error_png);
        written.insert(shown.error_png);
        shown.caption += " \u00b7 error map: its own estimated error";
      } catch (const std::exception& failure) {
        report.notes.push_back(fmt::format("The reference's error map {} is unreadable: {}", error_file.string(), failure.what()));
      }
    }
    scales.push_back((report.multi() ? variant.name + " " : std::string()) + num(kErrorScale * reference.mean) +
                     " W/m\u00b2");
  }
  if (scales.size() == 1 && !report.multi()) {
    report.error_scale_text = fmt::format("{} \u00d7 reference mean = {}", num(kErrorScale), scales.front());
  } else if (!scales.empty()) {
    report.error_scale_text =
        fmt::format("{} \u00d7 the mean of the run's own reference ({})", num(kErrorScale), join(scales, ", "));
  }

  // Runs grouped by method, in their order; each one in the viewer, with its place in the index.
  std::vector<std::pair<size_t, size_t>> viewer_runs;
  for (const std::string& method : report.methods) {
    for (size_t i : report.ok_runs()) {
      const Run& run = report.runs[i];
      if (run.method != method) continue;
      Thumbnail thumb;
      thumb.title = report.display(i);
      auto time = run.frame_ms();
      thumb.caption = primary_caption(report, run) + (time ? " \u00b7 " + num(*time) + " ms" : "");
      if (run.record.frames.empty()) {
        thumb.note = "no frames recorded";
        report.thumbnails.push_back(thumb);
        continue;
      }
      const FrameRecord& recorded = run.record.frames.front();
      int64_t frame = recorded.frame;
      std::string image_name = recorded.image.empty() ? frame_file(frame) : recorded.image;
      fs::path path = report.folder / "runs" / run.key / image_name;
      try {
        Image image = read_exr(path.string());
        ReferenceFrame& reference = reference_frame(run.reference_key, frame);
        // A black reference gives no exposure: the run is then exposed on its own light, so that light the
        // method puts where the reference has none shows.
        double mean = reference.ok && reference.mean > 0.0 ? reference.mean : masked_mean(image, lit_mask(image));
        float exposure = mean > 0.0 ? static_cast<float>(kMiddleGrey / mean) : 1.0f;
        std::string stem = file_safe(run.key);
        thumb.ec_png = stem + ".png";
        write_thumbnail(image, images / thumb.ec_png, exposure);
        written.insert(thumb.ec_png);
        json entry = {{"id", run.key}, {"title", thumb.title}, {"caption", thumb.caption}, {"method", run.method},
                      {"variant", run.variant}, {"frame", frame}, {"width", image.width()}, {"height", image.height()},
                      {"exposure_stops", std::log2(static_cast<double>(exposure))}};
        Image flip;
        if (reference.ok && reference.mean > 0.0) {
          if (fits(reference, image)) {
            thumb.error_png = stem + "_error.png";
            write_error_map(image, reference.image, kErrorScale * reference.mean, images / thumb.error_png);
            written.insert(thumb.error_png);
            if (with_flip) flip = flip_error_map(image, reference.image, reference.mask);
            if (flip.pixel_count() > 0) {
              thumb.flip_png = stem + "_flip.png";
              write_flip_map(flip, images / thumb.flip_png);
              written.insert(thumb.flip_png);
              report.has_flip_maps = true;
            }
          } else {
            thumb.note = fmt::format("{}x{} but the reference is {}x{}: no error map", image.width(), image.height(),
                                     reference.image.width(), reference.image.height());
          }
        }
        // Its first frame in the viewer; the top-level fields are that frame's (as an index before frames).
        const json view = frame_view(viewer, report, run, 0, image, reference, flip);
        entry.update(view);
        entry["frames"] = json::array({view});
        if (run.record.seeds) entry["seeds"] = run.record.seed_count();
        viewer_runs.push_back({i, viewer.index()["runs"].size()});
        viewer.index()["runs"].push_back(entry);
        thumb.viewer_id = run.key;
      } catch (const std::exception& failure) {
        thumb.note = fmt::format("image {} unreadable: {}", path.string(), failure.what());
      }
      report.thumbnails.push_back(thumb);
    }
  }
  if (!report.error_scale_text.empty()) {
    write_colour_bar(images / "error_colour_bar.png");
    written.insert("error_colour_bar.png");
  }
  if (report.has_flip_maps) {
    write_colour_bar(images / "flip_colour_bar.png", cv::COLORMAP_MAGMA);
    written.insert("flip_colour_bar.png");
  }
  add_more_frames(viewer, report, viewer_runs, with_flip, reference_frame);
  report.viewer_bytes = viewer.finish();
  if (!viewer.index()["runs"].empty()) {
    report.viewer = viewer.index();
    report.viewer["error_scale_factor"] = kErrorScale;
    report.viewer["colour_maps"] = {{"inferno", colour_map_table(cv::COLORMAP_INFERNO)},
                                    {"magma", colour_map_table(cv::COLORMAP_MAGMA)}};
  }
}

}  // namespace causticbench::report_detail
