#include "methods/lifecycle.h"

#include <atomic>
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

// What every render() must return: an RGB image of the G-buffer's size. Anything else would be read or
// written past its end (by the clearing below, the metrics, the store), so the run fails here, naming both.
void check_rendered_image(const Image& image, const GBuffer& gbuffer, const CausticMethod& method) {
  if (image.width() == gbuffer.width && image.height() == gbuffer.height && image.channels() == 3 &&
      image.values().size() == gbuffer.pixel_count() * 3)
    return;
  throw MethodError(fmt::format("{}'s render() returned a {}x{} image with {} channel{}; expected {}x{} with 3 (RGB), the "
                                "G-buffer's size",
                                method.info().name, image.width(), image.height(), image.channels(),
                                image.channels() == 1 ? "" : "s", gbuffer.width, gbuffer.height));
}

// Runs `call`, which calls into a method's code (a plugin's, perhaps): whatever it throws that is not a
// std::exception becomes a MethodError naming the method and the phase, so that the run fails alone
// instead of the process ending in std::terminate.
template <typename Call>
decltype(auto) guarded(const CausticMethod& method, const char* phase, Call&& call) {
  try {
    return call();
  } catch (const std::exception&) {
    throw;
  } catch (...) {
    throw MethodError(fmt::format("{} of method {}: {}", phase, method.info().name, current_exception_text()));
  }
}

// One render per sub-pixel G-buffer, each zero where its own point sees no receiver, averaged; the
// times (and GPU times, where every sample has one) summed.
Image render_subpixels(CausticMethod& method, const PosedFrame& posed, const ParamSet& render_knobs, int samples,
                       double& render_ms, std::optional<double>& gpu_ms) {
  // Summed in double: N finite values near FLT_MAX overflow a float sum, though their mean is finite.
  std::vector<double> sum(posed.gbuffer.pixel_count() * 3, 0.0);
  double gpu_sum = 0.0;
  bool every_gpu = true;
  int count = 0;
  posed.for_each_subpixel_gbuffer(samples, [&](const GBuffer& buffer) {
    auto start = Clock::now();
    Image image = method.render(buffer, render_knobs);
    render_ms += seconds_since(start) * 1e3;
    check_rendered_image(image, buffer, method);
    std::optional<double> gpu = gpu_milliseconds(method);
    every_gpu = every_gpu && gpu.has_value();
    if (gpu) gpu_sum += *gpu;
    buffer.clear_outside_receivers(image);
    const std::vector<float>& values = image.values();
    for (size_t i = 0; i < sum.size(); ++i) sum[i] += values[i];
    ++count;
  });
  Image mean(posed.gbuffer.width, posed.gbuffer.height, 3);
  for (size_t i = 0; i < sum.size(); ++i) mean.values()[i] = static_cast<float>(sum[i] / count);
  if (every_gpu) gpu_ms = gpu_sum;
  return mean;
}

}  // namespace

PosedFrame::PosedFrame(const Scene& scene, int index_in)
    : index(index_in), frame(scene, index_in), tracer(frame), gbuffer(render_gbuffer(tracer)) {}

bool valid_pixel_samples(int64_t samples) {
  if (samples < 1 || samples > 256) return false;
  int64_t side = static_cast<int64_t>(std::lround(std::sqrt(static_cast<double>(samples))));
  return side * side == samples;
}

namespace {

// The bytes every posed frame's kept sub-pixel G-buffers hold together (PosedFrame::subpixel_).
std::atomic<double> subpixel_cache_bytes{0.0};

double gbuffer_bytes(const GBuffer& gbuffer) { return static_cast<double>(gbuffer.pixel_count()) * kGBufferBytesPerPixel; }

}  // namespace

double pixel_samples_bytes(int width, int height, int samples, size_t frames) {
  if (samples <= 1) return 0.0;
  const double one = static_cast<double>(width) * height * kGBufferBytesPerPixel;
  const double kept = std::min(kSubpixelCacheBytes, one * samples * static_cast<double>(std::max<size_t>(frames, 1)));
  return kept + one + static_cast<double>(width) * height * 3.0 * sizeof(double);
}

PosedFrame::~PosedFrame() { subpixel_cache_bytes -= subpixel_bytes_; }

void PosedFrame::for_each_subpixel_gbuffer(int samples, const std::function<void(const GBuffer&)>& visit) const {
  if (!valid_pixel_samples(samples)) throw std::logic_error(fmt::format("pixel_samples {} is not a square in [1, 256]", samples));
  const int side = static_cast<int>(std::lround(std::sqrt(static_cast<double>(samples))));
  auto make = [&](int index) {
    const int i = index % side, j = index / side;
    return render_gbuffer(tracer, (i + 0.5f) / static_cast<float>(side), (j + 0.5f) / static_cast<float>(side));
  };
  const std::vector<GBuffer>* kept = nullptr;
  {
    std::lock_guard<std::mutex> lock(subpixel_mutex_);
    auto found = subpixel_.find(samples);
    if (found != subpixel_.end()) {
      kept = &found->second;
    } else {
      const double bytes = gbuffer_bytes(gbuffer) * samples;
      double held = subpixel_cache_bytes.load();
      // Claimed from the budget before they are made, so that two frames cannot both take its last part.
      while (held + bytes <= kSubpixelCacheBytes && !subpixel_cache_bytes.compare_exchange_weak(held, held + bytes)) {
      }
      if (held + bytes <= kSubpixelCacheBytes) {
        // Made aside and kept only when all are made: a failure (bad_alloc) keeps no partial set and
        // gives its part of the budget back.
        std::vector<GBuffer> buffers;
        try {
          for (int index = 0; index < samples; ++index) buffers.push_back(make(index));
        } catch (...) {
          subpixel_cache_bytes -= bytes;
          throw;
        }
        subpixel_bytes_ += bytes;
        kept = &(subpixel_[samples] = std::move(buffers));
      }
    }
  }
  if (kept) {
    for (const GBuffer& buffer : *kept) visit(buffer);
    return;
  }
  for (int index = 0; index < samples; ++index) visit(make(index));
}

RestPose::RestPose(const Scene& scene, std::vector<int> frames_in) : frame(scene, 0), tracer(frame), frames(std::move(frames_in)) {}

PrepareContext prepare_context(const Scene& scene, const std::vector<int>& frames, const PosedFrame* frame_zero,
                               std::unique_ptr<RestPose>& rest) {
  if (frame_zero && frame_zero->index == 0) return PrepareContext{scene, frame_zero->frame, frame_zero->tracer, frames};
  if (!rest) rest = std::make_unique<RestPose>(scene, frames);
  return PrepareContext{scene, rest->frame, rest->tracer, frames};
}

namespace {

PrepareOutcome prepare_unguarded(CausticMethod& method, const PrepareContext& context, const ParamSet& build,
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

std::vector<SequenceOutput> play_unguarded(CausticMethod& method, const std::vector<const PosedFrame*>& frames,
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
          check_rendered_image(image, posed.gbuffer, method);
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

}  // namespace

PrepareOutcome prepare_method(CausticMethod& method, const PrepareContext& context, const ParamSet& build,
                              BuildStore* builds) {
  return guarded(method, "check_scene() or prepare()", [&] { return prepare_unguarded(method, context, build, builds); });
}

std::vector<SequenceOutput> play_sequence(CausticMethod& method, const std::vector<const PosedFrame*>& frames,
                                          const ParamSet& frame_knobs, const std::vector<ParamSet>& render_sets,
                                          const TimingProtocol& protocol) {
  return guarded(method, "update() or render()",
                 [&] { return play_unguarded(method, frames, frame_knobs, render_sets, protocol); });
}

PhaseKnobs split_phases(const ParamSet& all, const std::vector<ParamSpec>& specs) {
  return PhaseKnobs{select_phase(all, specs, ParamPhase::build), select_phase(all, specs, ParamPhase::frame),
                    select_phase(all, specs, ParamPhase::render)};
}

}  // namespace causticbench
