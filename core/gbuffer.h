// The G-buffer: what one primary ray per pixel sees. Every method writes caustic irradiance for these
// points, so every comparison is pixel for pixel.
#pragma once

#include <cstdint>
#include <string>
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
  // The names of to_image()'s channels, in its order, as render's gbuffer.exr and the reference cache's
  // gbuffer_NNNN.exr carry them (position.X/Y/Z, normal.X/Y/Z, albedo.R/G/B, object, receiver, footprint),
  // so that tev and `oiiotool --info` say what each is.
  static const std::vector<std::string>& channel_names();
  // A stored G-buffer, its channels put back in to_image()'s order by name: EXR sorts channels by name
  // and OpenImageIO reads R, G, B, A first, so a file's order is not to_image()'s. Files written before
  // the channels had names (R, G, B, A, channel4 ... channel11) map those names to their index.
  // std::runtime_error naming `path` when it is unreadable or lacks a channel.
  static Image read_image(const std::string& path);
};

// What a G-buffer holds per pixel: position, normal and albedo, object id, receiver flag and footprint.
constexpr double kGBufferBytesPerPixel = 3 * sizeof(Vec3) + sizeof(int) + sizeof(uint8_t) + sizeof(float);

// One primary ray per pixel through point (offset_x, offset_y) of the pixel (in [0, 1), from its top-left
// corner); the pixel centre by default.
GBuffer render_gbuffer(const Tracer& tracer, float offset_x = 0.5f, float offset_y = 0.5f);

}  // namespace causticbench
