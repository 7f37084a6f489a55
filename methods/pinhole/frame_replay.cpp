// pinhole's frame dump format: a `--dump-frame` folder that PinholeMethod::dump_frame wrote
// (methods/pinhole/frame_data.h), replayed with VulkanPinhole by the generic replay (methods/frame_replay.h).
// Depends only on gpu/ and the standard library, like the rest of causticbench-gpubench.
#include <sstream>

#include "gpu/cube_filter_check.h"
#include "methods/frame_replay.h"
#include "methods/pinhole/frame_data.h"
#include "methods/pinhole/vulkan_pinhole.h"

namespace causticbench {

namespace {

struct PinholeReplayTraits {
  using Frame = PinholeFrameData;
  using Backend = VulkanPinhole;
  static Frame read(const std::string& folder) { return read_frame_data(folder); }
  static void upload(Backend& backend, const Frame& frame) { backend.upload_frame(frame); }
  // The shader evaluates every sample at every receiver (masked pixels return at once).
  static double evaluations_per_receiver(const Frame& frame) { return frame.sample_count(); }
  static std::string facts_json(const Frame& frame, gpu::Context& context) {
    // Whether this device's filtered lookups mean what textureGrad says (gpu/cube_filter_check.h): run for
    // both modes whatever the frame's filtering, since it is a fact of the device that a GPU machine's
    // timings should carry.
    const gpu::CubeFilterCheck isotropic = gpu::check_cube_filtering(context, false);
    const gpu::CubeFilterCheck anisotropic = gpu::check_cube_filtering(context, true);
    auto boolean = [](bool value) { return value ? "true" : "false"; };
    std::ostringstream facts;
    facts << "\"filtering\": " << frame.filtering << ",\n\"samples\": " << frame.sample_count()
          << ",\n\"isotropic_filtering_honours_gradients\": " << boolean(isotropic.honours_gradients)
          << ",\n\"anisotropic_filtering_honours_gradients\": " << boolean(anisotropic.honours_gradients)
          << ",\n\"sampler_check\": " << json_quoted(isotropic.summary() + "; " + anisotropic.summary());
    return facts.str();
  }
};

}  // namespace

FrameDumpFormat pinhole_frame_dump_format() {
  FrameDumpFormat format;
  format.method = "pinhole";
  format.evaluation_unit = "receiver-sample pairs";
  format.relmse_tolerance = 1e-6;
  format.flux_tolerance = 1e-4;
  format.tolerance_reason =
      "both backends do the same float arithmetic in a different order and with different square roots and "
      "divisions, so they differ by rounding only; a real disagreement (a wrong texel, a missed sample) is orders "
      "of magnitude larger";
  return frame_dump_format_of<PinholeReplayTraits>(format);
}

}  // namespace causticbench
