// Float RGB(A) images and their files: OpenEXR for HDR data (through OpenImageIO), PNG for pictures.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/math.h"

namespace causticbench {

class Image {
 public:
  Image() = default;
  Image(int width, int height, int channels = 3, float fill = 0.0f)
      : width_(width), height_(height), channels_(channels),
        pixels_(static_cast<size_t>(width) * height * channels, fill) {}

  int width() const { return width_; }
  int height() const { return height_; }
  int channels() const { return channels_; }
  size_t pixel_count() const { return static_cast<size_t>(width_) * height_; }
  float* data() { return pixels_.data(); }
  const float* data() const { return pixels_.data(); }
  std::vector<float>& values() { return pixels_; }
  const std::vector<float>& values() const { return pixels_; }

  float& at(size_t pixel, int channel) { return pixels_[pixel * channels_ + channel]; }
  float at(size_t pixel, int channel) const { return pixels_[pixel * channels_ + channel]; }
  Color rgb(size_t pixel) const {
    const float* p = &pixels_[pixel * channels_];
    return Color(p[0], p[1], p[2]);
  }
  void set_rgb(size_t pixel, const Color& c) {
    float* p = &pixels_[pixel * channels_];
    p[0] = c.r;
    p[1] = c.g;
    p[2] = c.b;
  }

 private:
  int width_ = 0, height_ = 0, channels_ = 3;
  std::vector<float> pixels_;
};

// channel_names may be empty (R, G, B, A...).
// EXR files: zip compression and no date in the header, so that the same pixels always give the same
// bytes (encode_exr is what write_exr writes, and what the results store checksums).
std::string encode_exr(const Image& image, const std::vector<std::string>& channel_names = {});
// std::runtime_error naming `path` when `bytes` is not a readable EXR image (truncated, damaged).
// With `channel_names`, it receives the file's channel names in the order of the image's channels (as
// OpenImageIO reads them: R, G, B, A first, then the others in the file's order, which is alphabetical).
Image decode_exr(const std::string& bytes, const std::string& path, std::vector<std::string>* channel_names = nullptr);
// An EXR's size as its header states it.
struct ExrShape {
  int width = 0, height = 0, channels = 0;
};
// decode_exr that first hands the header's shape to `check`, which throws to refuse it before any pixel
// memory is taken: a 96 KB file may claim 40000 x 40000 pixels.
Image decode_exr_checked(const std::string& bytes, const std::string& path, const std::function<void(const ExrShape&)>& check,
                         std::vector<std::string>* channel_names = nullptr);
// Written atomically (core/files.h): WriteError naming the file and the OS error, nothing half written.
void write_exr(const Image& image, const std::string& path, const std::vector<std::string>& channel_names = {});
Image read_exr(const std::string& path, std::vector<std::string>* channel_names = nullptr);
// 8-bit sRGB PNG of a linear image after tone mapping: exposure scaling then clamping. Written
// atomically, as write_exr.
void write_png(const Image& image, const std::string& path, float exposure = 1.0f);

}  // namespace causticbench
