// One prt frame as the Vulkan backend consumes it (shaders/product.comp, shaders/lookup.comp): the
// receivers, per specular object its record (build-space map, grid, where its matrices, lighting and
// incident field start), the frame's lighting per object, the stored matrices themselves, raw, in the
// build's precision, and the spherical-harmonic tables the CPU evaluates with (so that both evaluate the
// same floats). Free of the project's other dependencies so that causticbench-gpubench (which links only
// the Vulkan loader) can read it from a `--dump-frame` folder. Filled by methods/prt/prt_gpu.cpp.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "methods/frame_dump.h"  // method.txt and the float32 arrays of every dump folder

namespace causticbench {

// Words of one object's record in PrtFrameData::objects (32-bit: floats as their bits, or unsigned).
namespace prt_record {
constexpr uint32_t kLinear = 0;       // 9 floats: build-space map, column-major (point = linear p + offset)
constexpr uint32_t kOffset = 9;       // 3 floats
constexpr uint32_t kNormals = 12;     // 9 floats: the map's inverse transpose, column-major
constexpr uint32_t kCenter = 21;      // 3 floats: the grid's centre, build space
constexpr uint32_t kHalf = 24;        // float: half the cube's side (the ball's radius)
constexpr uint32_t kResolution = 25;  // cells a side
constexpr uint32_t kCell = 26;        // float: a cell's side
constexpr uint32_t kMatrices = 27;    // the element (float32 or float16) where its matrices start in `matrices`
constexpr uint32_t kLighting = 28;    // the float where its lighting (3 x bands^2) starts in `lighting`
constexpr uint32_t kIncident = 29;    // the float where its incident field (cells x 3 x bands^2) starts on the device
constexpr uint32_t kWords = 32;
}  // namespace prt_record

struct PrtFrameData {
  uint32_t width = 0, height = 0;
  uint32_t bands = 0;      // sh_order
  uint32_t precision = 0;  // 0 float32, 1 float16 (two a word, the lower half first)
  std::vector<float> receiver_positions;  // 4 per pixel: x, y, z, 1 for a receiver (0: masked)
  std::vector<float> receiver_normals;    // 4 per pixel: x, y, z, 0
  std::vector<uint32_t> objects;          // prt_record::kWords per specular object
  std::vector<float> lighting;            // per object, per colour, bands^2 coefficients (build space)
  std::vector<uint32_t> matrices;         // every object's cells x 3 x bands^2 x bands^2 entries, objects in order
  // Per coefficient k < bands^2: the basis recurrence's factors as spherical_harmonics.cpp evaluates them in
  // float (scale, along, back: 3 bands^2 floats, scale first), then per band the clamped cosine's Â_l.
  std::vector<float> basis_factors;
  std::vector<float> clamped_cosines;

  uint32_t pixel_count() const { return width * height; }
  uint32_t object_count() const { return static_cast<uint32_t>(objects.size() / prt_record::kWords); }
  uint32_t coefficients() const { return bands * bands; }
  uint32_t cells(uint32_t object) const;
  // Floats of every object's incident field together (the device's scratch between the two kernels).
  uint64_t incident_floats() const;
};

// The folder holds prt_frame.txt (the scalars, one `name value` a line, written last: its presence marks a
// complete frame) and one .bin file per array: float32, or for objects and matrices 32-bit words. Throws
// std::runtime_error naming the file on any defect (array sizes that do not match the records).
// method.txt is the caller's (write_dump_method).
void write_prt_frame_data(const PrtFrameData& frame, const std::string& folder);
PrtFrameData read_prt_frame_data(const std::string& folder);
void check_prt_frame_data(const PrtFrameData& frame, const std::string& where);

}  // namespace causticbench
