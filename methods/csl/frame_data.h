// One csl frame as the Vulkan backend consumes it: the receivers, each specular object's map into its
// build space, the frame's spot lights (a static set's, or those the dynamic light's interpolation
// made on the CPU for this frame) and their intensity images with the tables of the on-axis
// integration, as flat arrays. Free of the project's other dependencies so that causticbench-gpubench
// (which links only the Vulkan loader) can read it from a `--dump-frame` folder.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "methods/frame_dump.h"  // method.txt and the float32 arrays of every dump folder

namespace causticbench {

struct CslFrameData {
  // Strides of the records (see the members).
  static constexpr size_t kObjectFloats = 28, kLightFloats = 36, kLightWords = 4, kImageWords = 6, kImageFloats = 4;
  static constexpr size_t kMaxSources = 3;

  uint32_t width = 0, height = 0;
  std::vector<float> receiver_positions;  // 4 per pixel: x, y, z (world), 1 for a receiver (0: masked)
  std::vector<float> receiver_normals;    // 4 per pixel: x, y, z (world, unit), the side of its footprint (world)
  // Per specular object, 7 x 4 floats: the three columns of the world-to-build-space linear map (w 0),
  // its offset (w: the build-space length of a unit world length), the three columns of the normals'
  // map (w of the first: on_axis epsilon's distance, build space; 0 and 0).
  std::vector<float> objects;
  std::vector<uint32_t> object_lights;  // per object: its first spot light, its count
  // Per spot light, 9 x 4 floats: origin, kappa; axis, beta; u, the largest radius of its image; v,
  // channels (1 or 3); the light's irradiance rgb, 0; the weights of its up to three source images, 0;
  // per source the 2x2 map from its plane into the source's (x' = m0 x + m1 y, y' = m2 x + m3 y).
  std::vector<float> lights;
  std::vector<uint32_t> light_images;  // per spot light: source count, then three image indices
  // Per image, 6 words: offset of its first texel word, texels per side, channels, precision (0 float32,
  // 1 uint16, two texels a word, the first in the low half), offset of its tables in `radial`, bins.
  std::vector<uint32_t> images;
  std::vector<float> image_scalars;  // per image: half size of its square, uint16's scale per channel
  std::vector<uint32_t> texels;
  // Per image, (bins + 1) x channels of IntensityImage::radial_flux(), then as many of ring_integral().
  std::vector<float> radial;
  uint32_t intensity_correction = 1;  // Eq. 4
  uint32_t on_axis = 0;               // 0 integrate, 1 epsilon

  uint32_t pixel_count() const { return width * height; }
  bool is_receiver(uint32_t pixel) const { return receiver_positions[4ull * pixel + 3] != 0.0f; }
  uint32_t object_count() const { return static_cast<uint32_t>(object_lights.size() / 2); }
  uint32_t light_count() const { return static_cast<uint32_t>(light_images.size() / kLightWords); }
  uint32_t image_count() const { return static_cast<uint32_t>(images.size() / kImageWords); }
};

// The folder holds csl_frame.txt (the scalars, one `name value` a line, written last: its presence
// marks a complete frame), one float32 .bin file per float array (write_floats) and one little-endian
// uint32 .bin file per word array. Throws std::runtime_error naming the file on any defect, including
// records that point outside their arrays. method.txt is the caller's (write_dump_method).
void write_csl_frame_data(const CslFrameData& frame, const std::string& folder);
CslFrameData read_csl_frame_data(const std::string& folder);
// The same checks on a frame in memory (what read_csl_frame_data runs; also before an upload).
void check_frame_data(const CslFrameData& frame, const std::string& where);

}  // namespace causticbench
