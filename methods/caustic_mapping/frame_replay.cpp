// caustic_mapping's frame dump format: a `--dump-frame` folder that CausticMappingMethod::dump_frame wrote
// (methods/caustic_mapping/frame_data.h), replayed with VulkanCausticMapping by the generic replay
// (methods/frame_replay.h): the photon stage, the splats and the lookup, every repetition. Depends only
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
  static void upload(Backend&, const Frame&) {}  // render() uploads the passes and splats them every time
  // The work per frame is photons and receivers; per receiver: the photons of the frame (searched and
  // splatted) over the receivers, plus one lookup per pass.
  static double evaluations_per_receiver(const Frame& frame) { return frame.pass_count(); }
  static std::string facts_json(const Frame& frame, gpu::Context&) {
    std::ostringstream facts;
    const char* splats[] = {"point", "gaussian", "variable"};
    facts << "\"passes\": " << frame.pass_count() << ",\n\"photons\": " << frame.photon_count()
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
  format.relmse_tolerance = 1e-6;
  format.flux_tolerance = 1e-4;
  format.tolerance_reason =
      "the device repeats the CPU's search, landing, splat weights and lookup step by step, but projects in float "
      "where the CPU projects in double and adds splats in float in the rasteriser's order (measured on the test "
      "scenes: relMSE 1e-13 to 7e-11, flux within 7.4e-6); a photon whose search or landing lies within rounding "
      "of a texel's edge may still read or land in the neighbouring texel, which the bounds leave room for; a "
      "real disagreement (a wrong step, a lost normalisation, a texel off by one) is far above them";
  return frame_dump_format_of<CausticMappingReplayTraits>(format);
}

}  // namespace causticbench
