// The G-buffer: what one primary ray per pixel sees. Every method writes caustic irradiance for these
// points, so every comparison is pixel for pixel.
#pragma once

#include <cstdint>
#include <vector>

#include "core/image.h"
#include "core/tracer.h"

namespace causticbench {

struct GBuffer {
  int width = 0, height = 0;
  std::vector<Vec3> position;
  std::vector<Vec3> normal;        // shading normal, turned to face the camera
  std::vector<Color> albedo;       // diffuse albedo (zero where the surface has no diffuse part)
  std::vector<int> object;         // -1 for background
  std::vector<uint8_t> receiver;   // 1 where the surface has a diffuse part: in E_c and in every metric
  std::vector<float> footprint;    // side of the pixel's footprint on the surface plane, scene units

  size_t pixel_count() const { return static_cast<size_t>(width) * height; }
  size_t receiver_count() const;
  // Zeroes the RGB of every pixel that is not a receiver: masked pixels carry no caustic value,
  // whatever a method wrote there.
  void clear_outside_receivers(Image& image) const;
  // position/normal/albedo/object/mask/footprint as a multi-channel EXR-ready image (12 channels).
  Image to_image() const;
  static constexpr int kReceiverChannel = 10;  // the receiver mask's channel in to_image()
};

// One primary ray per pixel through point (offset_x, offset_y) of the pixel (in [0, 1), from its top-left
// corner); the pixel centre by default.
GBuffer render_gbuffer(const Tracer& tracer, float offset_x = 0.5f, float offset_y = 0.5f);

}  // namespace causticbench
