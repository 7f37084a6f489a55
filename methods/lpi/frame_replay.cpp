// lpi's frame dump format: a `--dump-frame` folder that LpiMethod::dump_frame wrote
// (methods/lpi/frame_data.h), replayed with VulkanLpi by the generic replay (methods/frame_replay.h).
// Depends only on gpu/ and the standard library, like the rest of causticbench-gpubench.
#include <sstream>

#include "methods/frame_replay.h"
#include "methods/lpi/frame_data.h"
#include "methods/lpi/vulkan_lpi.h"

namespace causticbench {

namespace {

struct LpiReplayTraits {
  using Frame = LpiFrameData;
  using Backend = VulkanLpi;
  static Frame read(const std::string& folder) { return read_lpi_frame_data(folder); }
  static void upload(Backend& backend, const Frame& frame) {
    backend.upload_volumes(frame);
    backend.upload_frame(frame);
  }
  // Each receiver looks up every object's caustic (masked pixels return at once): the rate the issue's
  // target counts (receiver points per second), whatever the blend and storage.
  static double evaluations_per_receiver(const Frame&) { return 1.0; }
  static std::string facts_json(const Frame& frame, gpu::Context&) {
    static const char* const precisions[] = {"float32", "float16", "uint8", "uint8 signed"};
    static const char* const outside[] = {"clamp", "fade", "zero"};
    // Reads of light samples per receiver and object, over all lights: 1 (nearest) to 3 (barycentric).
    size_t light_reads = 0;
    for (size_t light = 0; light < frame.lights.size() / lpi_light::kFloats; ++light)
      light_reads += static_cast<size_t>(frame.lights[light * lpi_light::kFloats + 3]);
    std::ostringstream facts;
    facts << "\"storage\": " << json_quoted(frame.storage == 0 ? "grid" : "shells")
          << ",\n\"orientation\": " << json_quoted(frame.channels == 3 ? "paper" : "vector")
          << ",\n\"precision\": " << json_quoted(precisions[frame.precision])
          << ",\n\"outside\": " << json_quoted(outside[frame.outside]) << ",\n\"objects\": " << frame.object_count()
          << ",\n\"light_reads\": " << light_reads << ",\n\"values_bytes\": " << frame.values.size() * 4;
    return facts.str();
  }
};

}  // namespace

FrameDumpFormat lpi_frame_dump_format() {
  FrameDumpFormat format;
  format.method = "lpi";
  format.evaluation_unit = "receiver points";
  format.relmse_tolerance = 1e-6;
  format.flux_tolerance = 1e-4;
  format.tolerance_reason =
      "the kernel repeats the CPU lookup (the same stencils, the same decoding of the stored values, the same "
      "blend weights, computed once on the CPU) in float, with the geodesic cell's side tests in float where the "
      "CPU uses double, so the backends differ by rounding only; a wrong cell, weight or light sample is orders of "
      "magnitude larger";
  return frame_dump_format_of<LpiReplayTraits>(format);
}

}  // namespace causticbench
