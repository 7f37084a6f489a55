// One method on one frame of a scene, through the lifecycle driver (methods/lifecycle.h):
// `causticbench render` and the tests.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "methods/lifecycle.h"
#include "methods/registry.h"

namespace causticbench {

struct PhaseTimings {
  double prepare_seconds = 0.0;
  double update_milliseconds = 0.0;
  double render_milliseconds = 0.0;
  std::optional<double> gpu_render_milliseconds;
};

// Everything a render needs, checked before any work starts (InputError on any defect).
struct RenderRequest {
  const Scene* scene = nullptr;
  std::string method;
  ParamDict params;
  int frame = 0;
  std::string dump_folder;  // --dump-frame: the method writes its GPU inputs and output here
  BuildStore* builds = nullptr;  // the build cache (store/build_cache.h on results/builds), or none
  int pixel_samples = 1;    // TimingProtocol::pixel_samples
};

struct CheckedRequest {
  const MethodEntry* method = nullptr;
  ParamSet params;  // all knobs, resolved with defaults
};

CheckedRequest check_request(const RenderRequest& request);

struct FrameResult {
  GBuffer gbuffer;
  Image caustic;
  PhaseTimings timings;
  PrepareOutcome prepare;
  size_t memory_bytes = 0;
  Counters counters;
  nlohmann::json method_record;
  std::optional<LostFlux> lost_flux;  // what the configuration loses of this frame (CausticMethod::lost_flux)
};

// Poses the frame, builds the tracer and the G-buffer, then check/prepare/update/render, each phase
// once and timed. If `direct` is not null it also receives the direct irradiance (for the composite)
// computed with `direct_samples`.
FrameResult run_frame(const RenderRequest& request, const CheckedRequest& checked, Image* direct = nullptr,
                      int direct_samples = 16);

nlohmann::json environment_json(int threads);

}  // namespace causticbench
