// external: any renderer, run as a program once per frame. Each frame's scene is written for it
// (core/scene_export.h: scene.json, a causticbench scene; world.json, the frame in world space; meshes
// and environment maps as files) with the G-buffer (gbuffer.exr); the command line of the `command` knob
// runs with those paths filled in, and the E_c image it writes is checked (size, finite, sign) and
// measured like any method's output. A program that fails (a non-zero exit, a missing or malformed image
// or statistics file, a run past `timeout_seconds`) fails its run, with the program's stderr tail, and
// the sweep goes on. Knobs under `program.` are passed through to the command. README.md says it all.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>

#include "core/scene_export.h"
#include "methods/method.h"

namespace causticbench {

class ExternalMethod : public CausticMethod {
 public:
  ExternalMethod();
  ~ExternalMethod() override;
  static const MethodInfo& static_info();
  const MethodInfo& info() const override { return static_info(); }
  void prepare(const PrepareContext& context, const ParamSet& build) override;
  void begin_sequence() override;
  void update(const FrameContext& frame, const ParamSet& frame_knobs) override;
  Image render(const GBuffer& gbuffer, const ParamSet& render) override;
  size_t memory_bytes() const override;
  Counters counters() const override;
  nlohmann::json record() const override;

 private:
  ParamSet build_;
  std::string folder_;   // the frame files, a fresh temporary folder per prepared instance
  bool keep_folder_ = false;  // a failed frame's files stay for the user to rerun its command
  std::unique_ptr<SceneExporter> exporter_;
  int frame_ = 0;
  // Per frame index of the current pass, what the program took and reported (record()).
  std::map<int, nlohmann::json> reports_;
  double peak_bytes_ = 0.0;

  std::string fail(const std::string& reason, const std::string& stderr_path) ;
};

}  // namespace causticbench
