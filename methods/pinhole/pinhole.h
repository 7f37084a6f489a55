// Wand & Strasser 2003, "Real-Time Caustics": every reflector sample is a pinhole camera that projects
// the light, held in an environment map, onto the receivers. Parameter table: methods/pinhole/README.md.
#pragma once

#include <memory>

#include "gpu/vulkan_context.h"
#include "methods/method.h"
#include "methods/pinhole/frame_data.h"
#include "methods/pinhole/light_map.h"
#include "methods/pinhole/packed_texels.h"
#include "methods/pinhole/reflector_sampling.h"

namespace causticbench {

class PinholeMethod : public CausticMethod, public GpuBackend {
 public:
  PinholeMethod();
  ~PinholeMethod() override;
  static const MethodInfo& static_info();
  const MethodInfo& info() const override { return static_info(); }
  void check_scene(const Scene& scene) const override;
  void prepare(const PrepareContext& context, const ParamSet& build) override;
  void update(const FrameContext& frame, const ParamSet& frame_knobs) override;
  Image render(const GBuffer& gbuffer, const ParamSet& render) override;
  size_t memory_bytes() const override;
  Counters counters() const override;
  nlohmann::json record() const override;
  std::vector<MemoryTerm> knob_memory(const PrepareContext& context, const ParamSet& knobs) const override;
  // The caustic flux of the specular objects whose material this run's interaction does not model.
  std::optional<LostFlux> lost_flux(const FrameContext& frame, const GBuffer& gbuffer, const ParamSet& render) override;
  // The Vulkan backend (backend: vulkan).
  GpuBackend* gpu() override { return this; }
  std::optional<double> gpu_render_milliseconds() const override {
    return vulkan_ ? std::optional<double>(gpu_render_ms_) : std::nullopt;
  }
  void dump_frame(const GBuffer& gbuffer, const ParamSet& render, const Image& output,
                  const std::string& folder) const override;

 private:
  ParamSet build_;
  const Scene* scene_ = nullptr;
  std::vector<int> reflectors_;  // the objects sampled, from prepare()
  std::string interaction_;      // the build knob: reflect, refract or auto (each object by its material)
  bool any_refracts_ = false;    // some sampled object refracts (the reflection-only fast paths do not apply)
  SampleSet samples_;
  std::vector<const Material*> sample_materials_;
  // The largest deviation of the last unfiltered render's throughput tables from the exact Fresnel
  // (ThroughputTable::max_error), for the run record.
  float table_error_ = 0.0f;
  LightCubeMap cube_map_;
  // The shared-exponent copy the unfiltered vector fetch reads when every block of the map is lit (an
  // environment map); empty under compact lights, whose few fetches read the float map exactly.
  PackedTexels packed_map_;
  std::unique_ptr<DistantLights> cube_map_lights_;  // the lights cube_map_ was built from
  std::string filter_implementation_;  // "" when not filtering
  std::unique_ptr<FilteredLightMap> filtered_map_;        // filter_implementation: oiio
  std::unique_ptr<class CubeFilter> cube_filter_;         // filter_implementation: own (CPU)
  double evaluations_ = 0.0;
  // The per-frame GPU inputs (samples, materials, cube map); receivers are added at render time.
  PinholeFrameData frame_data_;
  std::unique_ptr<gpu::Context> gpu_context_;
  std::string sampler_note_;  // set when the device's filtered lookups ignore the gradients
  std::unique_ptr<class VulkanPinhole> vulkan_;
  double gpu_render_ms_ = 0.0;

  void fill_receivers(const GBuffer& gbuffer, const ParamSet& render, PinholeFrameData& frame) const;
  nlohmann::json interaction_record() const;
  float epsilon_of(const ParamSet& render) const;
  // Half the sample spacing: where the differential point samples' footprint gradients are taken.
  float footprint_radius() const { return static_cast<float>(0.5 * samples_.spacing); }
};

// The specular objects the method samples for an interaction ("reflect" and "auto": mirrors,
// diffuse+mirror and glass; "refract": glass).
std::vector<int> pinhole_reflectors(const Scene& scene, const std::string& interaction);
// Whether a sample of this material refracts under the interaction: always under "refract", never under
// "reflect", and under "auto" when the material is glass (a mirror, or a diffuse+mirror surface's mirror
// part, reflects).
inline bool pinhole_refracts(const std::string& interaction, const Material& material) {
  return interaction == "refract" || (interaction == "auto" && material.kind == MaterialKind::glass);
}

}  // namespace causticbench
