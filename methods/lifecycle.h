// The one driver of a method's life: check, prepare (or load the build from the cache), then play
// the frame sequence as an animation, update() and render() per frame. `causticbench render`, the
// experiment runner (its reference included) and the tests all go through it, so a phase is timed
// the same way everywhere.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/gbuffer.h"
#include "core/tracer.h"
#include "methods/build_store.h"
#include "methods/method.h"

namespace causticbench {

// A frame posed once: the scene at one frame index, a tracer over it and its G-buffer. Methods take
// it by const reference, so the reference and every run of a variant share it.
struct PosedFrame {
  int index = 0;
  SceneFrame frame;
  Tracer tracer;
  GBuffer gbuffer;  // through the pixel centres: its receiver mask is every metric's
  PosedFrame(const Scene& scene, int index);
  FrameContext context() const { return FrameContext{frame, tracer}; }
  // Visits, in order, the `samples` G-buffers through the centres of an s x s grid of sub-pixels (s^2 =
  // samples): what a method renders under the harness's pixel_samples. They are made on first use and
  // kept for the next pass while all frames' kept sub-pixel G-buffers fit in kSubpixelCacheBytes;
  // beyond that each is made, visited and freed, so that 4096^2 x 256 samples holds one at a time.
  void for_each_subpixel_gbuffer(int samples, const std::function<void(const GBuffer&)>& visit) const;
  ~PosedFrame();
  PosedFrame(const PosedFrame&) = delete;
  PosedFrame& operator=(const PosedFrame&) = delete;

 private:
  mutable std::mutex subpixel_mutex_;
  mutable std::map<int, std::vector<GBuffer>> subpixel_;
  mutable double subpixel_bytes_ = 0.0;  // what subpixel_ holds, counted in the process-wide budget
};

// What the kept sub-pixel G-buffers of every posed frame of the process may hold together.
constexpr double kSubpixelCacheBytes = 256.0 * 1024 * 1024;
// What rendering under pixel_samples adds to a frame's memory at most (the estimate's pixel_samples term):
// the kept sub-pixel G-buffers, up to kSubpixelCacheBytes, one more made on the way, and the mean's sums.
double pixel_samples_bytes(int width, int height, int samples, size_t frames);

// Whether `samples` is a valid pixel_samples value: a square from 1 to 256.
bool valid_pixel_samples(int64_t samples);

// The scene's rest pose (frame 0) with a tracer over it, and the frames to be rendered: what
// prepare() gets.
struct RestPose {
  SceneFrame frame;
  Tracer tracer;
  std::vector<int> frames;
  RestPose(const Scene& scene, std::vector<int> frames);
  PrepareContext context() const { return PrepareContext{*frame.scene, frame, tracer, frames}; }
};

// The context prepare() gets for rendering `frames` of `scene`: frame 0's posed frame when the caller
// has one (its tracer serves; no second Embree scene is built), otherwise a RestPose kept in `rest`.
// `frames` must outlive the context.
PrepareContext prepare_context(const Scene& scene, const std::vector<int>& frames, const PosedFrame* frame_zero,
                               std::unique_ptr<RestPose>& rest);

// How a build came to be.
struct PrepareOutcome {
  std::string source = "computed";  // computed, loaded (from the build cache), or recomputed (the stored one was unreadable)
  std::string build_key;            // empty when the method's build is not cacheable here
  double prepare_seconds = 0.0;     // the time prepare() took; for a loaded build, as stored when it was computed
  double load_seconds = 0.0;        // reading a cached build (loaded builds)
  double save_seconds = 0.0;        // writing it to the cache (computed, cacheable builds)
  std::string warning;              // why a stored build was recomputed
};

// check_scene(), then prepare(): when `builds` is given (store/build_cache.h keeps them in
// results/builds) and the method has the BuildCache facet with build_dependencies() for this scene and
// these knobs, its build is loaded from there if stored, and computed and stored otherwise.
PrepareOutcome prepare_method(CausticMethod& method, const PrepareContext& context, const ParamSet& build,
                              BuildStore* builds = nullptr);

// Timing protocol: `warm_up` plays the whole sequence once untimed; then `repetitions` timed passes
// each play it frame after frame, as an animation would (so a new light direction every frame costs
// what it costs, and only a static frame sequence finds per-frame caches warm).
struct TimingProtocol {
  bool warm_up = true;
  int repetitions = 1;
  // The harness's anti-aliasing (docs/metrics.md, "pixel_samples"): with N > 1, render() runs once per
  // stratified sub-pixel G-buffer (PosedFrame::for_each_subpixel_gbuffer), each image is cleared outside its own
  // receivers and the N are averaged per pixel; the render time is the sum of the N.
  int pixel_samples = 1;
};

// Per frame of the sequence, the timings of every timed pass.
struct FrameTimings {
  int frame = 0;
  std::vector<double> update_ms;
  std::vector<double> render_ms;
  std::vector<double> gpu_render_ms;  // GPU backends: kernel time from timestamp queries
};

// One render knob set's output over the sequence.
struct SequenceOutput {
  std::vector<Image> images;          // per frame, from the last pass, zero outside the receivers
  std::vector<FrameTimings> timings;  // per frame
  // The method's memory, counters and record right after this knob set's last render: runs that share
  // an instance (differing only in render knobs) each get their own, not the last set's.
  size_t memory_bytes = 0;
  Counters counters;
  nlohmann::json method_record = nlohmann::json::object();
  // Per frame, what the configuration loses (CausticMethod::lost_flux, measured untimed after the last
  // pass's render).
  std::vector<std::optional<LostFlux>> lost_flux;
};

// Plays `frames` on a prepared method with one set of frame knobs. For each frame, update() runs
// once and render() once per render knob set: runs that differ only in render knobs share update()
// (its times are theirs alike). Returns one output per render knob set, in order.
std::vector<SequenceOutput> play_sequence(CausticMethod& method, const std::vector<const PosedFrame*>& frames,
                                          const ParamSet& frame_knobs, const std::vector<ParamSet>& render_sets,
                                          const TimingProtocol& protocol);

// The three phase subsets of a method's resolved knobs.
struct PhaseKnobs {
  ParamSet build, frame, render;
};
PhaseKnobs split_phases(const ParamSet& all, const std::vector<ParamSpec>& specs);

}  // namespace causticbench
