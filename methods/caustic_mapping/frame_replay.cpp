// caustic_mapping's frame dump format: a `--dump-frame` folder that CausticMappingMethod::dump_frame wrote
// (methods/caustic_mapping/frame_data.h), replayed with VulkanCausticMapping by the generic replay
// (methods/frame_replay.h): the light views, the leave and photon stages, the splats and the lookup,
// every repetition. Depends only
// on gpu/ and the standard library, like the rest of causticbench-gpubench.
#include <sstream>

#include "methods/caustic_mapping/frame_data.h"
#include "methods/caustic_mapping/vulkan_caustic_mapping.h"
#include "methods/frame_replay.h"

namespace causticbench {

namespace {

struct CausticMappingReplayTraits {
  using Frame = CausticMappingFrameData;
  using Backend = VulkanCausticMapping;
  static Frame read(const std::string& folder) { return read_caustic_mapping_frame_data(folder); }
  static void upload(Backend&, const Frame&) {}  // render() uploads the scene and renders every pass every time
  // The work per frame is photons and receivers; per receiver: the photons of the frame (searched and
  // splatted) over the receivers, plus one lookup per pass.
  static double evaluations_per_receiver(const Frame& frame) { return frame.pass_count(); }
  static std::string facts_json(const Frame& frame, gpu::Context&) {
    std::ostringstream facts;
    const char* splats[] = {"point", "gaussian", "variable"};
    facts << "\"passes\": " << frame.pass_count() << ",\n\"photon_buffer_texels\": " << frame.photon_count()
          << ",\n\"triangles\": " << frame.vertex_count() / 3
          << ",\n\"map_texels\": " << frame.texel_count() << ",\n\"search_iterations\": " << frame.search_iterations
          << ",\n\"hit_position\": " << json_quoted(frame.plane_hit ? "plane" : "texel")
          << ",\n\"splat\": " << json_quoted(splats[frame.splat]);
    return facts.str();
  }
};

}  // namespace

FrameDumpFormat caustic_mapping_frame_dump_format() {
  FrameDumpFormat format;
  format.method = "caustic_mapping";
  format.evaluation_unit = "receiver-pass lookups (the frame's photons, searched and splatted, are in the facts)";
  format.relmse_tolerance = 5e-3;
  format.flux_tolerance = 2e-3;
  format.tolerance_reason =
      "the device rasterises the light views from the scene's triangles, the analytic shapes tessellated at twice "
      "the photon buffer's resolution around (at most 512), where the CPU traces the exact surfaces: chords inside "
      "a sphere and interpolated normals move photons (measured: relMSE 3e-5 to 2.5e-3 and flux within 8e-4 on the "
      "test scenes' spheres at 128^2 photons, 1.5e-4 and 2.3e-4 on glass_sphere.yaml at 512^2); on surfaces that "
      "are triangles to both (a quad mirror) the device repeats the CPU's every step and agrees to 2e-11, which the "
      "tests hold it to; a wrong step or a lost normalisation of a percent is far above these bounds";
  return frame_dump_format_of<CausticMappingReplayTraits>(format);
}

}  // namespace causticbench
