// csl's frame dump format: a `--dump-frame` folder that CslMethod::dump_frame wrote
// (methods/csl/frame_data.h), replayed with VulkanCsl by the generic replay (methods/frame_replay.h).
// Depends only on gpu/ and the standard library, like the rest of causticbench-gpubench.
#include <sstream>

#include "methods/csl/frame_data.h"
#include "methods/csl/vulkan_csl.h"
#include "methods/frame_replay.h"

namespace causticbench {

namespace {

struct CslReplayTraits {
  using Frame = CslFrameData;
  using Backend = VulkanCsl;
  static Frame read(const std::string& folder) { return read_csl_frame_data(folder); }
  static void upload(Backend& backend, const Frame& frame) {
    backend.upload_images(frame);
    backend.upload_lights(frame);
  }
  // The shader evaluates every spot light of the frame at every receiver (csl_evaluations' unit).
  static double evaluations_per_receiver(const Frame& frame) { return frame.light_count(); }
  static std::string facts_json(const Frame& frame, gpu::Context&) {
    size_t sources = 0;
    for (uint32_t light = 0; light < frame.light_count(); ++light) sources += frame.light_images[CslFrameData::kLightWords * light];
    std::ostringstream facts;
    const double per_light = frame.light_count() ? static_cast<double>(sources) / frame.light_count() : 0.0;
    facts << "\"objects\": " << frame.object_count() << ",\n\"spot_lights\": " << frame.light_count()
          << ",\n\"source_images_per_spot_light\": " << per_light
          << ",\n\"images\": " << frame.image_count() << ",\n\"image_bytes\": " << 4 * frame.texels.size()
          << ",\n\"intensity_correction\": " << frame.intensity_correction << ",\n\"on_axis\": "
          << json_quoted(frame.on_axis == 1 ? "epsilon" : "integrate");
    return facts.str();
  }
};

}  // namespace

FrameDumpFormat csl_frame_dump_format() {
  FrameDumpFormat format;
  format.method = "csl";
  format.evaluation_unit = "receiver-spot light pairs";
  format.relmse_tolerance = 1e-5;
  format.flux_tolerance = 1e-4;
  format.tolerance_reason =
      "the kernel repeats the CPU evaluation step by step but in float where the CPU solves in double; on the "
      "caustic's fold, where two radii merge and Eq. 4's area ratio vanishes, 1 / sigma amplifies that rounding "
      "(measured at 800x600 on the glass sphere: relMSE 1.4e-11, flux 7.6e-6, all of it from fold pixels of "
      "values near 2000 off by up to 1e-3), and a double root found by one backend may be missed by the other; "
      "a real disagreement (a dropped correction, a wrong texel, a missed radius elsewhere) is far larger";
  return frame_dump_format_of<CslReplayTraits>(format);
}

}  // namespace causticbench
