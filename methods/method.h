// The one interface every caustics method implements. A method turns a scene into caustic irradiance
// E_c (W/m^2, RGB) at the G-buffer points, in three timed phases:
//   prepare(context, build knobs)  everything that depends only on the static scene and the build knobs
//                                  (precomputations over light directions); may be cached on disk;
//   update(frame, frame knobs)     what depends on this frame's lights and object poses;
//   render(gbuffer, render knobs)  the per-pixel work.
// methods/lifecycle.h drives the phases for `render`, the experiment runner and the tests alike.
// See docs/adding-a-method.md and docs/design.md.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/gbuffer.h"
#include "core/image.h"
#include "core/scene.h"
#include "core/tracer.h"
#include "methods/param_dict.h"
#include "metrics/quantities.h"

namespace causticbench {

// What a method can model (Liu et al. 2008, Table 1, is this matrix). A method may be run on a scene
// it does not model (its error is what the suite measures) but check_scene() rejects scenes it cannot
// represent at all.
struct Capabilities {
  bool reflection = false;
  bool refraction = false;
  bool multiple_bounces = false;
  bool directional_light = false;
  bool point_light = false;
  bool environment_light = false;
  bool moving_light = false;
  bool moving_objects = false;
  bool occlusion = false;
  bool non_lambertian_receivers = false;
  // Per capability name, how the method treats it when the answer needs qualifying.
  std::vector<std::pair<std::string, std::string>> notes;

  // (name, value) in a fixed order, for tables.
  std::vector<std::pair<std::string, bool>> entries() const;
};

// A rule between knobs that no single knob's range can state (lpi's sh_order against light_subdivision),
// declared with the knobs and checked before any work starts (broken_knob_rule), both knobs named.
struct KnobRule {
  std::vector<std::string> knobs;
  // "" when the knobs agree, otherwise what is wrong and how to fix it; called only when every knob of
  // `knobs` applies (is in the resolved set).
  std::function<std::string(const ParamSet&)> problem;
};

struct MethodInfo {
  std::string name;
  std::string paper;
  std::string summary;
  std::vector<ParamSpec> params;
  Capabilities capabilities;
  // Knobs ("name=value") that make a run cheap enough for the conformance tests on tiny scenes
  // (tests/test_conformance.cpp): few photons, few samples.
  std::vector<std::string> quick_knobs;
  // The method's own memory per frame pixel beyond what every frame holds, for the estimate checked
  // before any work starts (methods/memory_estimate.h): measured, not derived.
  double working_bytes_per_pixel = 0.0;
  // Every counter counters() reports, with its unit and definition (metrics/quantities.h,
  // counter_quantity): they join the quantity registry, so that claims, tables and plots can use them.
  // The conformance tests check that a method reports exactly what it declares.
  std::vector<QuantityInfo> counters;
  std::vector<KnobRule> knob_rules;
  // The knob that buys accuracy with time (photons, samples, passes), or "" where the accuracy is set by
  // a precomputation's resolution instead: the report draws the error of the runs that sweep it against
  // their time to a first frame, joined by the reference's own convergence (docs/reports.md, "Error
  // against time").
  std::string budget_knob;
  // True for a method whose work is a user's program (external): what it models and costs is the
  // program's, so the suites run over the whole registry (conformance, the capability matrix), which have
  // no program to give it, leave it out (native_method_names()); methods/external/tests cover it.
  bool runs_a_program = false;
};

// The first of `info`'s knob rules that `params` (resolved) break, with its problem; nothing when none.
struct BrokenKnobRule {
  const KnobRule* rule = nullptr;
  std::string problem;
  // "knobs 'a' and 'b' of lpi: <problem>"
  std::string describe(const std::string& method) const;
};
std::optional<BrokenKnobRule> broken_knob_rule(const MethodInfo& info, const ParamSet& params);

using Counters = std::vector<std::pair<std::string, double>>;

// A part of a method's peak memory that grows with its knobs (CausticMethod::knob_memory), for the
// check before any work starts (methods/memory_estimate.h): an upper bound, in bytes, on what it adds
// to the peak resident size, the knobs it grows with, and how it was counted. Each method's terms are
// checked against measured peaks by tests/test_memory_cost.cpp.
struct MemoryTerm {
  std::vector<std::string> knobs;  // the knobs to lower to shrink it ("grid_resolution", "light_subdivision")
  double bytes = 0.0;
  std::string formula;  // "64^3 cells x 3 channels x (4 x 1 light sample + 44) bytes"
};

// What a method's configuration cannot represent of one frame's caustic (docs/metrics.md, "Lost flux"):
// the fraction of the frame's caustic flux it leaves out, what that flux is, and the knob that would
// recover it. Runs that lose more than kLostFluxWarning are warned about by `run` and `render` and
// marked in the report, so that a bad score is explained where it is read.
struct LostFlux {
  double fraction = 0.0;  // in [0, 1]
  std::string what;       // "caustic flux whose first receiver hit lies outside the sampled ball"
  std::string knob;       // the knob that would recover it ("volume_radius")
  std::string advice;     // how ("set volume_radius: auto, or at least 4.2")
  // Of `fraction`, the light the configuration moves rather than drops (csl's spot lights carry it, but
  // their point focus sends it elsewhere): it may still land in view, so the light account takes it as
  // possibly delivered (experiments/light_account.h). 0 for the light a method drops.
  double moved = 0.0;
};
inline constexpr double kLostFluxWarning = 0.05;
// "loses 12.3 % of the caustic flux (<what>); <advice>" for warnings and reports.
std::string describe_lost_flux(const LostFlux& lost);
// {"fraction", "what", "knob", "advice"} and "moved" where it is not 0: how `render` and the run record write it.
nlohmann::json lost_flux_json(const LostFlux& lost);

// What prepare() works from: the scene, its rest pose (frame 0) with a ray tracer over it (to trace
// photons or rays for any light direction, with CausticPhotonTracer's explicit lights), and the frame
// indices that will be rendered, so that a method can precompute only what those frames need (a light
// whose direction does not change gets one light sample, not 162).
struct PrepareContext {
  const Scene& scene;
  const SceneFrame& rest;
  const Tracer& tracer;
  const std::vector<int>& frames;
};

// One posed frame: the scene at this frame index and a ray tracer over it.
struct FrameContext {
  const SceneFrame& frame;
  const Tracer& tracer;
};

// A facet: a build worth keeping between processes (methods/build_store.h; the lifecycle driver stores it
// through store/build_cache.h). A method whose prepare() does costly work returns what that work depends
// on: the specular objects' geometry and materials, the light directions, the build knobs; never the
// camera, the receivers or the variant. Its hash with the method's name is the build's key.
class BuildCache {
 public:
  virtual ~BuildCache() = default;
  // std::nullopt: nothing worth storing for this scene and these knobs.
  virtual std::optional<nlohmann::json> build_dependencies(const PrepareContext& context, const ParamSet& build) const = 0;
  // Writes the prepared build into an empty `folder`; load_build() reads it back in place of prepare()
  // and leaves the method exactly as prepare() would have (renders bit-identically). Throws
  // std::runtime_error on a defect (the cache then recomputes).
  virtual void save_build(const std::string& folder) const = 0;
  virtual void load_build(const PrepareContext& context, const ParamSet& build, const std::string& folder) = 0;
};

// A facet: a GPU backend. Having it is what makes a method's frame dumpable for causticbench-gpubench
// (`render --dump-frame`); its replay is registered by the method folder's CMakeLists.txt
// (causticbench_add_gpu_backend, docs/gpu.md).
class GpuBackend {
 public:
  virtual ~GpuBackend() = default;
  // The kernel time of the last render() from timestamp queries, in milliseconds; none when that render
  // ran on the CPU.
  virtual std::optional<double> gpu_render_milliseconds() const = 0;
  // Throws InputError when dump_frame could not write a frame with these knobs (all phases), so that
  // `--dump-frame` is refused before any work starts.
  virtual void check_frame_dump(const ParamSet& knobs) const {}
  // Writes the last rendered frame's GPU inputs and this backend's output into `folder`.
  virtual void dump_frame(const GBuffer& gbuffer, const ParamSet& render, const Image& output,
                          const std::string& folder) const = 0;
};

// For check_scene: throws InputError "<scene>: <needs>, and the scene has none" when the scene has no
// specular object, for a method that has nothing to work from without one (`needs` says what it does
// with them, "lpi precomputes the caustics of specular objects").
void require_specular_object(const Scene& scene, const std::string& needs);

class CausticMethod {
 public:
  virtual ~CausticMethod() = default;
  virtual const MethodInfo& info() const = 0;
  // Throws InputError when the scene cannot be represented at all (before any work starts).
  virtual void check_scene(const Scene& scene) const {}
  virtual void prepare(const PrepareContext& context, const ParamSet& build) = 0;
  // Called at the start of every pass over a run's frames (each timed repetition, and the warm-up): a
  // method that carries state from frame to frame (rt_photons' adaptive emission map and history buffer)
  // resets it here, so that every pass measures the same work. The default: nothing carried.
  virtual void begin_sequence() {}
  // Called for every frame before render(), with the frame knobs of the run; the same prepared
  // instance may see different frame knobs from one call to the next.
  virtual void update(const FrameContext& frame, const ParamSet& frame_knobs) = 0;
  // The same updated instance may be asked to render with different render knobs.
  virtual Image render(const GBuffer& gbuffer, const ParamSet& render) = 0;
  // Bytes of the data the method keeps between frames.
  virtual size_t memory_bytes() const = 0;
  virtual Counters counters() const = 0;
  // What this method's knobs (every phase, resolved) will cost in memory on this scene, beyond the
  // frame's pixels (MethodInfo::working_bytes_per_pixel): upper bounds on the peak, each naming its
  // knobs. Called before any work starts, so it must be cheap: count, do not allocate. Empty (the
  // default): nothing a knob can make large.
  virtual std::vector<MemoryTerm> knob_memory(const PrepareContext& context, const ParamSet& knobs) const { return {}; }
  // Method-specific facts for the run record (e.g. the reference's estimated error). Called after
  // lost_flux() for the same render knobs, so it may report what that measured.
  virtual nlohmann::json record() const { return nlohmann::json::object(); }
  // What this configuration cannot represent of the frame's caustic (LostFlux); `gbuffer` is the one just
  // rendered. Called by the lifecycle driver once per frame, after the last pass's render with these
  // render knobs and outside the timed work, so that measuring it (probe photons, counts) costs the
  // method's timings nothing. std::nullopt: nothing to report (the reference).
  virtual std::optional<LostFlux> lost_flux(const FrameContext& frame, const GBuffer& gbuffer, const ParamSet& render) {
    return std::nullopt;
  }

  // Optional facets (nullptr: the method has none). A method that has one derives from it too and returns
  // `this`; the lifecycle driver, the runner and `render` ask for the facet rather than for optional
  // virtuals of every method.
  virtual BuildCache* build_cache() { return nullptr; }
  virtual GpuBackend* gpu() { return nullptr; }
};


}  // namespace causticbench
