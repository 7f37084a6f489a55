// The one replay of a dumped frame for every method's Vulkan backend (causticbench-gpubench, `causticbench
// gpu-compare`): a method names its frame type and its backend in a Traits struct and gets its
// FrameDumpFormat from frame_dump_format_of<Traits>(...). Depends only on methods/frame_dump.h and what
// the traits name (gpu/ and the standard library), like the rest of causticbench-gpubench.
//
//   struct Traits {
//     using Frame = ...;    // has width, height and receiver_positions (RGBA per pixel, w > 0 on receivers)
//     using Backend = ...;  // Backend(gpu::Context&); std::vector<float> render(const Frame&, double& kernel_ms)
//     static Frame read(const std::string& folder);           // throws std::runtime_error naming the file
//     static void upload(Backend& backend, const Frame& frame);
//     static double evaluations_per_receiver(const Frame& frame);  // in the format's evaluation_unit
//     static std::string facts_json(const Frame& frame, gpu::Context& context);  // FrameReplay::facts_json
//   };
//
// A method folder registers its format with causticbench_add_gpu_backend (cmake/methods.cmake), which
// lists it in the generated frame_dump_formats.cpp: nothing outside the folder names it.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "methods/frame_dump.h"

namespace causticbench {

template <class Traits>
class BackendReplay : public FrameReplay {
 public:
  BackendReplay(gpu::Context& context, const std::string& folder) : frame_(Traits::read(folder)), backend_(context) {
    Traits::upload(backend_, frame_);
    facts_ = Traits::facts_json(frame_, context);
  }
  std::vector<float> render(double& kernel_ms) override { return backend_.render(frame_, kernel_ms); }
  std::string facts_json() const override { return facts_; }

 private:
  typename Traits::Frame frame_;
  typename Traits::Backend backend_;
  std::string facts_;
};

// `format` with its method, unit and tolerances filled in; the reading and replaying come from Traits.
template <class Traits>
FrameDumpFormat frame_dump_format_of(FrameDumpFormat format) {
  format.read_info = [](const std::string& folder) {
    const typename Traits::Frame frame = Traits::read(folder);
    return receiver_dump_info(frame.width, frame.height, frame.receiver_positions, Traits::evaluations_per_receiver(frame));
  };
  format.replay = [](gpu::Context& context, const std::string& folder) -> std::unique_ptr<FrameReplay> {
    return std::make_unique<BackendReplay<Traits>>(context, folder);
  };
  return format;
}

}  // namespace causticbench
