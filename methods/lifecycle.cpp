#include "methods/lifecycle.h"

#include <chrono>
#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "methods/plugins.h"
#include "methods/registry.h"

namespace causticbench {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The last render's kernel time, for a method with a GPU backend whose last render ran there.
std::optional<double> gpu_milliseconds(CausticMethod& method) {
  GpuBackend* gpu = method.gpu();
  return gpu ? gpu->gpu_render_milliseconds() : std::nullopt;
}

// One render per sub-pixel G-buffer, each zero where its own point sees no receiver, averaged; the
// times (and GPU times, where every sample has one) summed.
Image render_subpixels(CausticMethod& method, const PosedFrame& posed, const ParamSet& render_knobs, int samples,
                       double& render_ms, std::optional<double>& gpu_ms) {
  const std::vector<GBuffer>& buffers = posed.subpixel_gbuffers(samples);
  Image sum(posed.gbuffer.width, posed.gbuffer.height, 3);
  double gpu_sum = 0.0;
  bool every_gpu = true;
  for (const GBuffer& buffer : buffers) {
    auto start = Clock::now();
    Image image = method.render(buffer, render_knobs);
    render_ms += seconds_since(start) * 1e3;
    std::optional<double> gpu = gpu_milliseconds(method);
    every_gpu = every_gpu && gpu.has_value();
    if (gpu) gpu_sum += *gpu;
    buffer.clear_outside_receivers(image);
    for (size_t pixel = 0; pixel < sum.pixel_count(); ++pixel)
      for (int c = 0; c < 3; ++c) sum.at(pixel, c) += image.at(pixel, c);
  }
  for (float& value : sum.values()) value /= static_cast<float>(buffers.size());
  if (every_gpu) gpu_ms = gpu_sum;
  return sum;
}

}  // namespace

PosedFrame::PosedFrame(const Scene& scene, int index_in)
    : index(index_in), frame(scene, index_in), tracer(frame), gbuffer(render_gbuffer(tracer)) {}

bool valid_pixel_samples(int64_t samples) {
  if (samples < 1 || samples > 256) return false;
  int64_t side = static_cast<int64_t>(std::lround(std::sqrt(static_cast<double>(samples))));
  return side * side == samples;
}

const std::vector<GBuffer>& PosedFrame::subpixel_gbuffers(int samples) const {
  if (!valid_pixel_samples(samples)) throw std::logic_error(fmt::format("pixel_samples {} is not a square in [1, 256]", samples));
  std::lock_guard<std::mutex> lock(subpixel_mutex_);
  std::vector<GBuffer>& buffers = subpixel_[samples];
  if (buffers.empty()) {
    const int side = static_cast<int>(std::lround(std::sqrt(static_cast<double>(samples))));
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i)
        buffers.push_back(render_gbuffer(tracer, (i + 0.5f) / static_cast<float>(side), (j + 0.5f) / static_cast<float>(side)));
  }
  return buffers;
}

RestPose::RestPose(const Scene& scene, std::vector<int> frames_in) : frame(scene, 0), tracer(frame), frames(std::move(frames_in)) {}

PrepareContext prepare_context(const Scene& scene, const std::vector<int>& frames, const PosedFrame* frame_zero,
                               std::unique_ptr<RestPose>& rest) {
  if (frame_zero && frame_zero->index == 0) return PrepareContext{scene, frame_zero->frame, frame_zero->tracer, frames};
  if (!rest) rest = std::make_unique<RestPose>(scene, frames);
  return PrepareContext{scene, rest->frame, rest->tracer, frames};
}

PrepareOutcome prepare_method(CausticMethod& method, const PrepareContext& context, const ParamSet& build,
                              BuildStore* builds) {
  PrepareOutcome outcome;
  method.check_scene(context.scene);
  BuildCache* cache = builds ? method.build_cache() : nullptr;
  std::optional<nlohmann::json> dependencies;
  if (cache) dependencies = cache->build_dependencies(context, build);
  if (!dependencies) {
    auto start = Clock::now();
    method.prepare(context, build);
    outcome.prepare_seconds = seconds_since(start);
    return outcome;
  }
  const std::string& name = method.info().name;
  // A plugin's build depends on which build of the plugin computed it: a rebuilt plugin computes it again.
  if (const PluginIdentity* plugin = find_method(name).plugin) (*dependencies)["plugin"] = plugin->key_json();
  outcome.build_key = builds->key(name, *dependencies);
  if (std::optional<BuildStore::Found> stored = builds->find(name, outcome.build_key, *dependencies)) {
    std::string problem = stored->problem;
    if (problem.empty()) {
      try {
        auto start = Clock::now();
        cache->load_build(context, build, stored->folder);
        outcome.load_seconds = seconds_since(start);
        outcome.prepare_seconds = stored->prepare_seconds;
        outcome.source = "loaded";
        return outcome;
      } catch (const std::runtime_error& error) {
        problem = error.what();
      }
    }
    outcome.warning = fmt::format("build {} of {} in {} cannot be used ({}); recomputing it", outcome.build_key, name,
                                  stored->folder, problem);
    fmt::print(stderr, "warning: {}\n", outcome.warning);
    outcome.source = "recomputed";
  }
  auto start = Clock::now();
  method.prepare(context, build);
  outcome.prepare_seconds = seconds_since(start);
  start = Clock::now();
  builds->put(name, outcome.build_key, *dependencies, build, outcome.prepare_seconds, outcome.source == "recomputed",
              [&](const std::string& folder) { cache->save_build(folder); });
  outcome.save_seconds = seconds_since(start);
  return outcome;
}

std::vector<SequenceOutput> play_sequence(CausticMethod& method, const std::vector<const PosedFrame*>& frames,
                                          const ParamSet& frame_knobs, const std::vector<ParamSet>& render_sets,
                                          const TimingProtocol& protocol) {
  std::vector<SequenceOutput> outputs(render_sets.size());
  for (SequenceOutput& output : outputs) {
    output.images.resize(frames.size());
    output.lost_flux.resize(frames.size());
    for (size_t f = 0; f < frames.size(); ++f) output.timings.push_back(FrameTimings{frames[f]->index, {}, {}, {}});
  }
  const int passes = (protocol.warm_up ? 1 : 0) + std::max(1, protocol.repetitions);
  for (int pass = 0; pass < passes; ++pass) {
    const bool timed = !protocol.warm_up || pass > 0;
    method.begin_sequence();
    for (size_t f = 0; f < frames.size(); ++f) {
      const PosedFrame& posed = *frames[f];
      auto start = Clock::now();
      method.update(posed.context(), frame_knobs);
      double update_ms = seconds_since(start) * 1e3;
      for (size_t r = 0; r < render_sets.size(); ++r) {
        std::optional<double> gpu_ms;
        double render_ms = 0.0;
        Image image;
        if (protocol.pixel_samples <= 1) {
          start = Clock::now();
          image = method.render(posed.gbuffer, render_sets[r]);
          render_ms = seconds_since(start) * 1e3;
          gpu_ms = gpu_milliseconds(method);
        } else {
          image = render_subpixels(method, posed, render_sets[r], protocol.pixel_samples, render_ms, gpu_ms);
        }
        if (timed) {
          FrameTimings& timings = outputs[r].timings[f];
          timings.update_ms.push_back(update_ms);
          timings.render_ms.push_back(render_ms);
          if (gpu_ms) timings.gpu_render_ms.push_back(*gpu_ms);
        }
        if (pass == passes - 1) {
          posed.gbuffer.clear_outside_receivers(image);
          outputs[r].images[f] = std::move(image);
          outputs[r].memory_bytes = method.memory_bytes();
          outputs[r].counters = method.counters();
          outputs[r].lost_flux[f] = method.lost_flux(posed.context(), posed.gbuffer, render_sets[r]);
          outputs[r].method_record = method.record();
        }
      }
    }
  }
  return outputs;
}

PhaseKnobs split_phases(const ParamSet& all, const std::vector<ParamSpec>& specs) {
  return PhaseKnobs{select_phase(all, specs, ParamPhase::build), select_phase(all, specs, ParamPhase::frame),
                    select_phase(all, specs, ParamPhase::render)};
}

}  // namespace causticbench
