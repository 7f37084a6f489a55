// One lpi frame as the Vulkan backend consumes it (methods/lpi/lpi.comp): the receivers, per specular
// object its record (build-space map, layout, where its values and tables start), per light its reads
// of the object's light samples, and the stored values themselves, raw, in the build's precision.
// Free of the project's other dependencies so that causticbench-gpubench (which links only the Vulkan
// loader) can read it from a `--dump-frame` folder. Filled by methods/lpi/gpu_frame.cpp.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "methods/frame_dump.h"  // method.txt and the float32 arrays of every dump folder

namespace causticbench {

// Words of one object's record in LpiFrameData::objects (32-bit: floats as their bits, or unsigned).
namespace lpi_record {
constexpr uint32_t kLinear = 0;      // 9 floats: build-space map, column-major (point = linear p + offset)
constexpr uint32_t kOffset = 9;      // 3 floats
constexpr uint32_t kNormals = 12;    // 9 floats: the map's inverse transpose, column-major
constexpr uint32_t kCenter = 21;     // 3 floats: the sampled ball's centre, build space
constexpr uint32_t kRadius = 24;     // float
constexpr uint32_t kCount = 25;      // grid: cells a side; shells: shells
constexpr uint32_t kSpacing = 26;    // grid: the cell's side (float); shells: directions a shell (unsigned)
constexpr uint32_t kFirstLight = 27; // index of its first light in LpiFrameData::lights
constexpr uint32_t kLightCount = 28;
constexpr uint32_t kValues = 29;     // word where its values start in LpiFrameData::values
constexpr uint32_t kPoints = 30;     // sample points of one light sample's block
constexpr uint32_t kScales = 31;     // index of its first light sample's scale in LpiFrameData::scales
constexpr uint32_t kRadii = 32;      // shells: word of its radii (floats) in LpiFrameData::shells
constexpr uint32_t kTriangles = 33;  // shells: word of its triangles, 12 words each: 3 corners (9 floats), 3 point indices
constexpr uint32_t kTexels = 34;     // shells: word of its lookup texels, 2 words each (first, rest), 6 n^2 + 1 of them
constexpr uint32_t kCandidates = 35; // shells: word of its candidate triangles
constexpr uint32_t kTableSize = 36;  // shells: texels a cube-face side, n
constexpr uint32_t kLongestEdge = 37;// shells: the longest edge normal's length (float)
constexpr uint32_t kWords = 40;
}  // namespace lpi_record

// Floats of one light's record in LpiFrameData::lights: irradiance rgb, the number of reads, then three
// reads of kReadFloats: light sample, weight, rotated (0 or 1), rotation (9, column-major).
namespace lpi_light {
constexpr uint32_t kReadFloats = 12;
constexpr uint32_t kFirstRead = 4;
constexpr uint32_t kFloats = 40;
}  // namespace lpi_light

struct LpiFrameData {
  uint32_t width = 0, height = 0;
  uint32_t storage = 0;    // 0 grid, 1 shells
  uint32_t channels = 3;   // 3 (orientation paper) or 9 (vector)
  uint32_t precision = 0;  // 0 float32, 1 float16, 2 uint8, 3 signed uint8 (-127 .. 127)
  uint32_t outside = 0;    // 0 clamp, 1 fade, 2 zero
  std::vector<float> receiver_positions;  // 4 per pixel: x, y, z, 1 for a receiver (0: masked)
  std::vector<float> receiver_normals;    // 4 per pixel: x, y, z, 0
  std::vector<uint32_t> objects;          // lpi_record::kWords per specular object
  std::vector<float> lights;              // lpi_light::kFloats per light and object
  std::vector<uint32_t> values;           // every object's StoredValues bytes, each padded to whole words
  std::vector<float> scales;              // every object's per-light-sample uint8 steps (1 otherwise)
  std::vector<uint32_t> shells;           // shells: every object's radii and geodesic lookup tables

  uint32_t pixel_count() const { return width * height; }
  uint32_t object_count() const { return static_cast<uint32_t>(objects.size() / lpi_record::kWords); }
  bool is_receiver(uint32_t pixel) const { return receiver_positions[4ull * pixel + 3] != 0.0f; }
};

// The folder holds frame.txt (the scalars, one `name value` a line, written last: its presence marks a
// complete frame) and one .bin file per array: float32, or for objects, values and shells 32-bit words
// (unsigned or a float's bits) as above. Throws std::runtime_error naming the file on any defect.
// method.txt is the caller's (write_dump_method).
void write_lpi_frame_data(const LpiFrameData& frame, const std::string& folder);
LpiFrameData read_lpi_frame_data(const std::string& folder);

}  // namespace causticbench
