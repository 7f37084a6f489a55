#include "methods/method_runner.h"

#include <sys/utsname.h>

#include <fstream>
#include <thread>

#include <fmt/format.h>

#include "core/build_info.h"
#include "core/direct_lighting.h"
#include "core/parallel.h"
#include "methods/lifecycle.h"
#include "methods/memory_estimate.h"

namespace causticbench {

CheckedRequest check_request(const RenderRequest& request) {
  CheckedRequest checked;
  checked.method = &find_method(request.method);
  const MethodInfo& info = checked.method->info();
  checked.params = request.params.resolve(info.params, info.name);
  if (std::optional<BrokenKnobRule> broken = broken_knob_rule(info, checked.params)) {
    throw InputError(fmt::format("--set: expected knobs that agree with each other, found {}", broken->describe(info.name)));
  }
  if (request.frame < 0 || request.frame >= request.scene->frames) {
    throw InputError(fmt::format("frame {} is outside the scene's animation: expected 0 to {} ({} frames in {})",
                                 request.frame, request.scene->frames - 1, request.scene->frames,
                                 request.scene->source));
  }
  std::unique_ptr<CausticMethod> method = create_method(info.name);
  if (!request.dump_folder.empty() && !method->gpu()) {
    throw InputError(fmt::format("--dump-frame: expected a method that can dump its frame ({}), found '{}'",
                                 join(methods_with_gpu_backend(), ", "), info.name));
  }
  method->check_scene(*request.scene);
  if (!request.dump_folder.empty()) method->gpu()->check_frame_dump(checked.params);
  const Camera& camera = request.scene->camera;
  const RestPose rest(*request.scene, {request.frame});
  check_memory_fits(estimate_run_memory(camera.width, camera.height, *method, rest.context(), checked.params, request.pixel_samples),
                    fmt::format("{} with {} at {}x{}", request.scene->source, info.name, camera.width, camera.height));
  return checked;
}

FrameResult run_frame(const RenderRequest& request, const CheckedRequest& checked, Image* direct, int direct_samples) {
  FrameResult result;
  const MethodInfo& info = checked.method->info();
  std::unique_ptr<CausticMethod> method = create_method(info.name);
  const PhaseKnobs knobs = split_phases(checked.params, info.params);
  PosedFrame posed(*request.scene, request.frame);
  const std::vector<int> frames = {request.frame};
  std::unique_ptr<RestPose> rest;
  result.prepare =
      prepare_method(*method, prepare_context(*request.scene, frames, &posed, rest), knobs.build, request.builds);
  result.timings.prepare_seconds = result.prepare.prepare_seconds;
  std::vector<SequenceOutput> outputs =
      play_sequence(*method, {&posed}, knobs.frame, {knobs.render}, TimingProtocol{false, 1, request.pixel_samples});
  const FrameTimings& timings = outputs.front().timings.front();
  result.timings.update_milliseconds = timings.update_ms.front();
  result.timings.render_milliseconds = timings.render_ms.front();
  if (!timings.gpu_render_ms.empty()) result.timings.gpu_render_milliseconds = timings.gpu_render_ms.front();
  result.caustic = std::move(outputs.front().images.front());
  result.gbuffer = std::move(posed.gbuffer);
  result.memory_bytes = outputs.front().memory_bytes;
  result.counters = outputs.front().counters;
  result.method_record = outputs.front().method_record;
  result.lost_flux = outputs.front().lost_flux.front();
  if (!request.dump_folder.empty()) method->gpu()->dump_frame(result.gbuffer, knobs.render, result.caustic, request.dump_folder);
  if (direct) *direct = direct_irradiance(posed.tracer, result.gbuffer, direct_samples, 12345);
  return result;
}

nlohmann::json environment_json(int threads) {
  utsname name{};
  uname(&name);
  std::string cpu = "unknown";
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);) {
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  }
#ifdef NDEBUG
  const char* build_type = "Release";
#else
  const char* build_type = "Debug";
#endif
  return {{"machine", fmt::format("{} {} {}", name.sysname, name.release, name.machine)},
          {"cpu", cpu},
          {"hardware_threads", std::thread::hardware_concurrency()},
          {"threads", threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency())},
          {"compiler", fmt::format("{} {}", "g++", __VERSION__)},
          {"build_type", build_type},
          {"git_revision", git_revision()},
          {"compute_device", "cpu"}};
}

}  // namespace causticbench
