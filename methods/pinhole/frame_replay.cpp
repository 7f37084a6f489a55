#include "methods/pinhole/frame_replay.h"

#include <sstream>

#include "gpu/cube_filter_check.h"
#include "methods/pinhole/frame_data.h"
#include "methods/pinhole/vulkan_pinhole.h"

namespace causticbench {

namespace {

class PinholeReplay : public FrameReplay {
 public:
  PinholeReplay(gpu::Context& context, const std::string& folder)
      : frame_(read_frame_data(folder)),
        // Whether this device's filtered lookups mean what textureGrad says (gpu/cube_filter_check.h):
        // run for both modes whatever the frame's filtering, since it is a fact of the device that a GPU
        // machine's timings should carry.
        isotropic_(gpu::check_cube_filtering(context, false)),
        anisotropic_(gpu::check_cube_filtering(context, true)),
        pinhole_(context) {
    pinhole_.upload_frame(frame_);
  }

  std::vector<float> render(double& kernel_ms) override { return pinhole_.render(frame_, kernel_ms); }

  std::string facts_json() const override {
    auto boolean = [](bool value) { return value ? "true" : "false"; };
    std::ostringstream facts;
    facts << "\"filtering\": " << frame_.filtering << ",\n\"samples\": " << frame_.sample_count()
          << ",\n\"isotropic_filtering_honours_gradients\": " << boolean(isotropic_.honours_gradients)
          << ",\n\"anisotropic_filtering_honours_gradients\": " << boolean(anisotropic_.honours_gradients)
          << ",\n\"sampler_check\": " << json_quoted(isotropic_.summary() + "; " + anisotropic_.summary());
    return facts.str();
  }

 private:
  PinholeFrameData frame_;
  gpu::CubeFilterCheck isotropic_, anisotropic_;
  VulkanPinhole pinhole_;
};

FrameDumpInfo read_pinhole_info(const std::string& folder) {
  const PinholeFrameData frame = read_frame_data(folder);
  // The shader evaluates every sample at every receiver (masked pixels return at once).
  return receiver_dump_info(frame.width, frame.height, frame.receiver_positions, frame.sample_count());
}

std::unique_ptr<FrameReplay> replay_pinhole(gpu::Context& context, const std::string& folder) {
  return std::make_unique<PinholeReplay>(context, folder);
}

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
  format.read_info = &read_pinhole_info;
  format.replay = &replay_pinhole;
  return format;
}

}  // namespace causticbench
