#include "methods/lpi/frame_replay.h"

#include <sstream>

#include "methods/lpi/frame_data.h"
#include "methods/lpi/vulkan_lpi.h"

namespace causticbench {

namespace {

class LpiReplay : public FrameReplay {
 public:
  LpiReplay(gpu::Context& context, const std::string& folder) : frame_(read_lpi_frame_data(folder)), lpi_(context) {
    lpi_.upload_volumes(frame_);
    lpi_.upload_frame(frame_);
  }

  std::vector<float> render(double& kernel_ms) override { return lpi_.render(frame_, kernel_ms); }

  std::string facts_json() const override {
    static const char* const precisions[] = {"float32", "float16", "uint8", "uint8 signed"};
    static const char* const outside[] = {"clamp", "fade", "zero"};
    std::ostringstream facts;
    facts << "\"storage\": " << json_quoted(frame_.storage == 0 ? "grid" : "shells")
          << ",\n\"orientation\": " << json_quoted(frame_.channels == 3 ? "paper" : "vector")
          << ",\n\"precision\": " << json_quoted(precisions[frame_.precision])
          << ",\n\"outside\": " << json_quoted(outside[frame_.outside]) << ",\n\"objects\": " << frame_.object_count()
          << ",\n\"light_reads\": " << light_reads() << ",\n\"values_bytes\": " << frame_.values.size() * 4;
    return facts.str();
  }

 private:
  // Reads of light samples per receiver and object, over all lights: 1 (nearest) to 3 (barycentric).
  size_t light_reads() const {
    size_t reads = 0;
    for (size_t light = 0; light < frame_.lights.size() / lpi_light::kFloats; ++light) {
      reads += static_cast<size_t>(frame_.lights[light * lpi_light::kFloats + 3]);
    }
    return reads;
  }

  LpiFrameData frame_;
  VulkanLpi lpi_;
};

FrameDumpInfo read_lpi_info(const std::string& folder) {
  const LpiFrameData frame = read_lpi_frame_data(folder);
  // Each receiver looks up every object's caustic (masked pixels return at once): the rate the issue's
  // target counts (receiver points per second), whatever the blend and storage.
  return receiver_dump_info(frame.width, frame.height, frame.receiver_positions, 1.0);
}

std::unique_ptr<FrameReplay> replay_lpi(gpu::Context& context, const std::string& folder) {
  return std::make_unique<LpiReplay>(context, folder);
}

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
  format.read_info = &read_lpi_info;
  format.replay = &replay_lpi;
  return format;
}

}  // namespace causticbench
