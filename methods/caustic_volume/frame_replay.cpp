// caustic_volume's frame dump format: a `--dump-frame` folder that CausticVolumeMethod::dump_frame wrote
// (methods/caustic_volume/frame_data.h), replayed with VulkanCausticVolume by the generic replay
// (methods/frame_replay.h): the footprints rasterised and every fragment's test, every repetition.
// Depends only on gpu/ and the standard library, like the rest of causticbench-gpubench.
#include <sstream>

#include "methods/caustic_volume/frame_data.h"
#include "methods/caustic_volume/vulkan_caustic_volume.h"
#include "methods/frame_replay.h"

namespace causticbench {

namespace {

struct CausticVolumeReplayTraits {
  using Frame = CausticVolumeFrameData;
  using Backend = VulkanCausticVolume;
  static Frame read(const std::string& folder) { return read_caustic_volume_frame_data(folder); }
  static void upload(Backend&, const Frame&) {}  // render() uploads the volumes and footprints every time
  // The fill cost is the footprints' fragments; per receiver, the volumes of the frame are an upper bound
  // of the tests, the facts give the footprints' triangles.
  static double evaluations_per_receiver(const Frame&) { return 1.0; }
  static std::string facts_json(const Frame& frame, gpu::Context&) {
    std::ostringstream facts;
    facts << "\"volumes\": " << frame.volume_count() << ",\n\"footprint_triangles\": " << frame.footprint_vertex_count() / 3
          << ",\n\"intensity\": " << json_quoted(frame.intensity ? "constant" : "interpolated");
    return facts.str();
  }
};

}  // namespace

FrameDumpFormat caustic_volume_frame_dump_format() {
  FrameDumpFormat format;
  format.method = "caustic_volume";
  format.evaluation_unit = "receiver pixels (every volume's light summed; the volumes are in the facts)";
  format.relmse_tolerance = 1e-6;
  format.flux_tolerance = 1e-3;
  format.tolerance_reason =
      "the device tests the same volumes at the same points as the CPU, in float where the CPU solves the cubic and "
      "the barycentric test in double; the intensity near a focus is a flux over a cross-section that tends to 0, "
      "which float loses digits of (measured on the test scenes: relMSE 0 to 2e-10, flux within 1.3e-4, all of the "
      "last from the ring's cusp, where two pixels of 214 W/m^2 read 1.2e-3 less; the points found lit equal); a "
      "wrong step or a lost factor is far above these bounds";
  return frame_dump_format_of<CausticVolumeReplayTraits>(format);
}

}  // namespace causticbench
