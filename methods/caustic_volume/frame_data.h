// One caustic_volume frame as the Vulkan backend consumes it: the volumes the CPU built (update()), their
// footprints in the image as triangle fans, the intensity knob, and the camera's receivers, as flat
// arrays. Free of the project's other dependencies so that causticbench-gpubench (which links only the
// Vulkan loader) can read it from a `--dump-frame` folder.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "methods/frame_dump.h"  // method.txt and the float32 arrays of every dump folder

namespace causticbench {

struct CausticVolumeFrameData {
  static constexpr size_t kVolumeFloats = 19 * 4;

  uint32_t width = 0, height = 0;
  std::vector<float> receiver_positions;  // 4 per pixel: x, y, z (world), 1 for a receiver (0: masked)
  std::vector<float> receiver_normals;    // 4 per pixel: x, y, z (world, unit), 0
  std::vector<float> receiver_objects;    // 1 per pixel: the object the pixel sees (a volume's own: its self gap)
  uint32_t intensity = 0;                 // 0 interpolated, 1 constant

  // Per volume (caustic_volume::Volume), 19 x 4 floats: P0, t_max; P1, area_in; P2, self_gap; D0, object;
  // D1, 0; D2, 0; arriving at each vertex (rgb) and its one-ring's area across the light (3 records);
  // each vertex's one-ring cross-section as a quadratic in t (1, t, t^2), 0 (3 records); the mean
  // direction, 0; the medium's absorption, 0; the bounds' lower and upper corners, 0 each; the cubic's
  // vector coefficients k_j with k_j . D0 (3 records).
  std::vector<float> volumes;
  // Three vertices a triangle, 4 floats a vertex: x, y in pixels (pixel (i, j) spans [i, i + 1) x
  // [j, j + 1), rows down), the volume, 0. Each volume's triangles cover its footprint once, in volume
  // order (the order the CPU adds their light).
  std::vector<float> footprints;

  uint32_t pixel_count() const { return width * height; }
  uint32_t volume_count() const { return static_cast<uint32_t>(volumes.size() / kVolumeFloats); }
  uint32_t footprint_vertex_count() const { return static_cast<uint32_t>(footprints.size() / 4); }
};

// The folder holds caustic_volume_frame.txt (width, height, intensity; written last: its presence marks
// a complete frame) and one float32 .bin file per array. Throws std::runtime_error naming the file on any
// defect, including footprints that name no volume.
void write_caustic_volume_frame_data(const CausticVolumeFrameData& frame, const std::string& folder);
CausticVolumeFrameData read_caustic_volume_frame_data(const std::string& folder);
void check_frame_data(const CausticVolumeFrameData& frame, const std::string& where);

}  // namespace causticbench
