// One caustic_mapping frame as the Vulkan backend consumes it: the scene's triangles and materials as
// the light views rasterise them, what the CPU planned per pass (its two light views, the texel
// measures, the light's strength), the knobs of every stage, and the camera's receivers, as flat arrays.
// The device renders the rest (photon buffers, receiver maps, photons, caustic maps). Free of the
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
  static constexpr size_t kViewFloats = 20, kPassWords = 8, kVertexFloats = 8, kObjectFloats = 20;

  uint32_t width = 0, height = 0;
  std::vector<float> receiver_positions;  // 4 per pixel: x, y, z (world), 1 for a receiver (0: masked)
  std::vector<float> receiver_normals;    // 4 per pixel: x, y, z (world, unit), 0

  uint32_t search_iterations = 5;
  uint32_t plane_hit = 1;   // hit_position: 1 plane, 0 texel
  uint32_t splat = 2;       // 0 point, 1 gaussian, 2 variable
  uint32_t refraction = 0;  // 0 auto, 1 two_interface, 2 one_interface
  float splat_radius = 1.5f, splat_photons = 16.0f, max_splat_radius = 16.0f;

  // The scene, three vertices a triangle (no index buffer), 2 x 4 floats a vertex: position (world),
  // object index; normal (unit, the shading normal), d_N (glass that may take two interfaces: the
  // distance through the object along the inward normal, Wyman's per-vertex precomputation; else 0).
  std::vector<float> vertices;
  // Per object, 5 x 4 floats: material kind (0 diffuse or glossy, 1 mirror, 2 glass, 3 diffuse mirror),
  // 1 if it receives caustics, ior, 1 for conductor Fresnel; reflectance, 0; eta, 0; k, 0; absorption, 0.
  std::vector<float> objects;
  // Per pass, two light views (LightView) of 5 x 4 floats: the caustic map's, then the photon buffer's.
  // Each: eye (the window's centre when orthographic), 1 orthographic / 0 perspective; axis, half extent;
  // right, the window's offset along it; up, the offset along it; the depth range rasterised (near, far:
  // along the axis from the eye, negative allowed when orthographic), 0, 0.
  std::vector<float> views;
  // Per pass: the caustic map's resolution n, its first texel in `measures`, its first photon slot in
  // `photon_measures`, the photon buffer's resolution p (p^2 slots, one a texel), the object, 0, 0, 0.
  std::vector<uint32_t> passes;
  std::vector<float> strengths;        // per pass, 4: the light's irradiance (directional) or intensity (point), 0
  std::vector<float> measures;         // per caustic-map texel: LightView::texel_measure (m^2 or sr)
  std::vector<float> photon_measures;  // per photon-buffer texel: its measure, as the CPU computes it in double

  uint32_t pixel_count() const { return width * height; }
  uint32_t pass_count() const { return static_cast<uint32_t>(passes.size() / kPassWords); }
  uint32_t photon_count() const { return static_cast<uint32_t>(photon_measures.size()); }  // slots
  uint32_t texel_count() const { return static_cast<uint32_t>(measures.size()); }
  uint32_t vertex_count() const { return static_cast<uint32_t>(vertices.size() / kVertexFloats); }
  uint32_t object_count() const { return static_cast<uint32_t>(objects.size() / kObjectFloats); }
};

// The folder holds caustic_mapping_frame.txt (the scalars, one `name value` a line, written last: its
// presence marks a complete frame), one float32 .bin file per float array (write_floats) and
// passes.bin (little-endian uint32). Throws std::runtime_error naming the file on any defect, including
// passes that point outside their arrays and vertices naming no object. method.txt is the caller's (write_dump_method).
void write_caustic_mapping_frame_data(const CausticMappingFrameData& frame, const std::string& folder);
CausticMappingFrameData read_caustic_mapping_frame_data(const std::string& folder);
// The same checks on a frame in memory (what reading runs; also before an upload).
void check_frame_data(const CausticMappingFrameData& frame, const std::string& where);

}  // namespace causticbench
