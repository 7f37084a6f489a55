// prt's frame dump format: a `--dump-frame` folder that PrtMethod::dump_frame wrote (methods/prt/frame_data.h),
// replayed with VulkanPrt by the generic replay (methods/frame_replay.h): every repetition a whole frame,
// l = M L over every cell and the lookup at every receiver. Depends only on gpu/ and the standard library,
// like the rest of causticbench-gpubench.
#include <sstream>

#include "methods/frame_replay.h"
#include "methods/prt/frame_data.h"
#include "methods/prt/vulkan_prt.h"

namespace causticbench {

namespace {

struct PrtReplayTraits {
  using Frame = PrtFrameData;
  using Backend = VulkanPrt;
  static Frame read(const std::string& folder) { return read_prt_frame_data(folder); }
  static void upload(Backend& backend, const Frame& frame) { backend.upload_build(frame); }
  // Each receiver is looked up in every object's field (the rate the target counts); the cells the
  // product covers are in the facts.
  static double evaluations_per_receiver(const Frame& frame) { return frame.object_count(); }
  static std::string facts_json(const Frame& frame, gpu::Context&) {
    uint64_t cells = 0;
    for (uint32_t object = 0; object < frame.object_count(); ++object) cells += frame.cells(object);
    std::ostringstream facts;
    facts << "\"sh_order\": " << frame.bands << ",\n\"precision\": " << json_quoted(frame.precision ? "float16" : "float32")
          << ",\n\"objects\": " << frame.object_count() << ",\n\"cells\": " << cells
          << ",\n\"matrix_bytes\": " << frame.matrices.size() * 4;
    return facts.str();
  }
};

}  // namespace

FrameDumpFormat prt_frame_dump_format() {
  FrameDumpFormat format;
  format.method = "prt";
  format.evaluation_unit = "receiver points x objects (each a trilinear read of 3 sh_order^2 coefficients and the "
                           "clamped-cosine sum; the frame's l = M L over every cell included in the time)";
  format.relmse_tolerance = 1e-6;
  format.flux_tolerance = 1e-4;
  format.tolerance_reason =
      "the kernels repeat the CPU's product and lookup in the same order with the same float tables (the basis "
      "recurrence's factors, the clamped cosine), differing by rounding and fused multiply-adds only; a wrong cell, "
      "weight, coefficient or band is orders of magnitude larger";
  return frame_dump_format_of<PrtReplayTraits>(format);
}

}  // namespace causticbench
