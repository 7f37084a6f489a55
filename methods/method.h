// The one interface every caustics method implements. A method turns a scene into caustic irradiance
// E_c (W/m^2, RGB) at the G-buffer points, in three timed phases:
//   prepare(scene, build knobs)  everything that depends only on the static scene and the build knobs;
//   update(frame)                what depends on this frame's lights and object poses;
//   render(gbuffer, render knobs) the per-pixel work.
// See docs/adding-a-method.md.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/gbuffer.h"
#include "core/image.h"
#include "core/scene.h"
#include "core/tracer.h"
#include "methods/param_dict.h"

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

struct MethodInfo {
  std::string name;
  std::string paper;
  std::string summary;
  std::vector<ParamSpec> params;
  Capabilities capabilities;
  // Whether `causticbench render --dump-frame` can write this method's frame for causticbench-gpubench.
  bool frame_dump = false;
};

using Counters = std::vector<std::pair<std::string, double>>;

// One posed frame: the scene at this frame index and a ray tracer over it.
struct FrameContext {
  const SceneFrame& frame;
  const Tracer& tracer;
};

class CausticMethod {
 public:
  virtual ~CausticMethod() = default;
  virtual const MethodInfo& info() const = 0;
  // Throws InputError when the scene cannot be represented at all (before any work starts).
  virtual void check_scene(const Scene& scene) const {}
  virtual void prepare(const Scene& scene, const ParamSet& build) = 0;
  virtual void update(const FrameContext& frame) = 0;
  virtual Image render(const GBuffer& gbuffer, const ParamSet& render) = 0;
  // Bytes of the data the method keeps between frames.
  virtual size_t memory_bytes() const = 0;
  virtual Counters counters() const = 0;
  // Method-specific facts for the run record (e.g. the reference's noise floor).
  virtual nlohmann::json record() const { return nlohmann::json::object(); }
  // Writes the last rendered frame's GPU inputs and this backend's output into `folder` (methods whose
  // MethodInfo::frame_dump is set).
  virtual void dump_frame(const GBuffer& gbuffer, const ParamSet& render, const Image& output,
                          const std::string& folder) const {}
};

}  // namespace causticbench
