// One caustic_mapping frame as the Vulkan backend consumes it: what the light-view passes produced on
// the CPU (each pass's light view, receiver map, texel measures and the photons leaving its object),
// the knobs of the photon stage and the splats, and the camera's receivers, as flat arrays. Free of the
// project's other dependencies so that causticbench-gpubench (which links only the Vulkan loader) can
// read it from a `--dump-frame` folder.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "methods/frame_dump.h"  // method.txt and the float32 arrays of every dump folder

namespace causticbench {

struct CausticMappingFrameData {
  // Strides of the records (see the members).
  static constexpr size_t kViewFloats = 16, kPassWords = 4, kReceiverFloats = 8, kPhotonFloats = 16;

  uint32_t width = 0, height = 0;
  std::vector<float> receiver_positions;  // 4 per pixel: x, y, z (world), 1 for a receiver (0: masked)
  std::vector<float> receiver_normals;    // 4 per pixel: x, y, z (world, unit), 0

  uint32_t search_iterations = 5;
  uint32_t plane_hit = 1;  // hit_position: 1 plane, 0 texel
  uint32_t splat = 2;      // 0 point, 1 gaussian, 2 variable
  float splat_radius = 1.5f, splat_photons = 16.0f, max_splat_radius = 16.0f;

  // Per pass, the caustic map's light view (LightView), 4 x 4 floats: eye (the window's centre when
  // orthographic), 1 orthographic / 0 perspective; axis, half extent; right, the window's offset along
  // it; up, the offset along it.
  std::vector<float> views;
  // Per pass: the maps' resolution n, its first texel in `receivers` and `measures`, its first photon in
  // `photons`, its photon count.
  std::vector<uint32_t> passes;
  // Per receiver-map texel, 2 x 4 floats: position, depth from the light (+infinity: no receiver);
  // normal, 0.
  std::vector<float> receivers;
  std::vector<float> measures;  // per caustic-map texel: LightView::texel_measure (m^2 or sr)
  // Per photon, 4 x 4 floats: origin, 0; direction (unit), 0; flux (W, rgb), 0; the medium's absorption
  // (per scene unit, rgb), 0.
  std::vector<float> photons;

  uint32_t pixel_count() const { return width * height; }
  uint32_t pass_count() const { return static_cast<uint32_t>(passes.size() / kPassWords); }
  uint32_t photon_count() const { return static_cast<uint32_t>(photons.size() / kPhotonFloats); }
  uint32_t texel_count() const { return static_cast<uint32_t>(measures.size()); }
};

// The folder holds caustic_mapping_frame.txt (the scalars, one `name value` a line, written last: its
// presence marks a complete frame), one float32 .bin file per float array (write_floats) and
// passes.bin (little-endian uint32). Throws std::runtime_error naming the file on any defect, including
// passes that point outside their arrays. method.txt is the caller's (write_dump_method).
void write_caustic_mapping_frame_data(const CausticMappingFrameData& frame, const std::string& folder);
CausticMappingFrameData read_caustic_mapping_frame_data(const std::string& folder);
// The same checks on a frame in memory (what reading runs; also before an upload).
void check_frame_data(const CausticMappingFrameData& frame, const std::string& where);

}  // namespace causticbench
