// One pinhole frame as the Vulkan backend consumes it: receivers, reflector samples, materials and the
// light cube map as flat float arrays. Free of the project's other dependencies so that
// causticbench-gpubench (which links only the Vulkan loader) can read it from a `--dump-frame` folder.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "methods/frame_dump.h"  // method.txt and the float32 arrays of every dump folder

namespace causticbench {

struct PinholeFrameData {
  uint32_t width = 0, height = 0;
  std::vector<float> receiver_positions;  // 4 per pixel: x, y, z, 1 for a receiver (0: masked)
  std::vector<float> receiver_normals;    // 4 per pixel: x, y, z, 0
  std::vector<float> sample_positions;    // 4 per sample: x, y, z, 1 when two-sided
  std::vector<float> sample_normals;      // 4 per sample: x, y, z, material index
  std::vector<float> materials;           // 12 per material: reflectance rgb, kind (0 constant, 1 conductor,
                                          // 2 glass); eta rgb, ior; k rgb, 0
  std::vector<float> cube_map;            // 6 x resolution^2 x rgb, LightCubeMap's layout
  std::vector<float> differentials;       // 16 per sample when filtering: u, v directions, dn/du, dn/dv (xyz, 0)
  int32_t resolution = 0;
  float epsilon = 0.0f;
  float area = 0.0f;
  uint32_t attenuation = 1, fresnel = 1, refraction = 0;
  uint32_t filtering = 0;  // 0 none, 1 isotropic, 2 anisotropic
  float footprint_radius = 0.0f;  // r of the differential point samples
  // When filtering: 1 for the method's own filter on `filter_levels` (CubeFilter::texels()), 0 for the
  // device's textureGrad on a cube texture made from cube_map.
  uint32_t own_filter = 0;
  std::vector<float> filter_levels;

  uint32_t pixel_count() const { return width * height; }
  bool is_receiver(uint32_t pixel) const { return receiver_positions[4ull * pixel + 3] != 0.0f; }
  uint32_t sample_count() const { return static_cast<uint32_t>(sample_positions.size() / 4); }
};

// The folder holds frame.txt (the scalars, one `name value` a line, written last: its presence marks a
// complete frame) and one float32 .bin file per array (write_floats). Throws std::runtime_error naming
// the file on any defect. method.txt is the caller's (write_dump_method).
void write_frame_data(const PinholeFrameData& frame, const std::string& folder);
PinholeFrameData read_frame_data(const std::string& folder);

}  // namespace causticbench
