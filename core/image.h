// Float RGB(A) images and their files: OpenEXR for HDR data (through OpenImageIO), PNG for pictures.
#pragma once

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

// Writes through a temporary file and a rename, so that a reader never sees half an image.
// channel_names may be empty (R, G, B, A...). Throws std::runtime_error on failure.
void write_exr(const Image& image, const std::string& path, const std::vector<std::string>& channel_names = {});
Image read_exr(const std::string& path);
// 8-bit sRGB PNG of a linear image after tone mapping: exposure scaling then clamping.
void write_png(const Image& image, const std::string& path, float exposure = 1.0f);

}  // namespace causticbench
