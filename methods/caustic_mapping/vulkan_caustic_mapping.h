// caustic_mapping's Vulkan backend: a raster pipeline, as the method is one. Per pass: the light-view
// passes (shaders/light_view.vert, light_view.frag), which rasterise the scene's triangles into the
// photon buffer (the nearest surface, and the object's back faces) and the receiver map (the surfaces that
// receive caustics) with a depth test; the leave stage (shaders/leave.comp: each texel's photon out of the
// object); the photon stage (shaders/photons.comp: the image-space receiver search); for variable splats
// the coarse density buffer (points drawn with additive blending); the splats' radii and weight sums
// (shaders/weights.comp); the splats drawn as instanced quads with additive blending into the pass's
// caustic map (shaders/splat.vert, splat.frag). Last, the lookup over the camera's receivers
// (shaders/lookup.comp). The CPU plans the light views (light_pass.h's PassPlan). Depends only on gpu/
// and the standard library.
#pragma once

#include <map>
#include <memory>
#include <vector>

#include "gpu/raster.h"
#include "gpu/vulkan_context.h"
#include "methods/caustic_mapping/frame_data.h"

namespace causticbench {

class VulkanCausticMapping {
 public:
  explicit VulkanCausticMapping(gpu::Context& context);
  ~VulkanCausticMapping();
  // Uploads `frame` (scene, views, measures), renders every pass's light views, photons, searches and
  // splats, and keeps the caustic maps on the device. Read back on request, per photon-buffer texel: the
  // leave stage's photon record (16 floats, shaders/leave.comp), the landing (x, y in caustic-map texels,
  // Landing, receiver-map reads) and the arriving flux (rgb, 0). Returns the kernels' time in
  // milliseconds (timestamp queries).
  struct Readback {
    std::vector<float> photons, landings, arriving;
  };
  double splat(const CausticMappingFrameData& frame, Readback* readback = nullptr);
  // The receiver maps the last splat() rendered: per pass, n^2 (position, depth) then n^2 (normal, 0).
  std::vector<float> receiver_maps() const;
  // The lookup of the splatted passes at the receivers of `frame`: RGBA irradiance per pixel.
  std::vector<float> look_up(const CausticMappingFrameData& frame, double& gpu_ms);
  // Both: the frame a replay times.
  std::vector<float> render(const CausticMappingFrameData& frame, double& gpu_ms);

 private:
  gpu::RasterTarget& target(uint32_t size, bool density);
  // The two colour targets and the depth target of a size x size light view.
  struct ViewTargets {
    std::unique_ptr<gpu::RasterTarget> first, second, depth;
  };
  ViewTargets& view_targets(uint32_t size);
  // Rasterises the pass's light view `view` (mode: 0 receivers, 1 every object, 2 the object's back faces)
  // into `into` from vec4 `first` on: size^2 of the first target, then size^2 of the second.
  double light_view(gpu::RasterPipeline& pipeline, uint32_t size, uint32_t view, uint32_t mode, uint32_t object,
                    uint32_t vertices, gpu::Buffer& into, size_t first);

  gpu::Context& context_;
  std::unique_ptr<gpu::ComputePipeline> leave_, photons_, weights_, lookup_;
  std::unique_ptr<gpu::RasterPipeline> receiver_view_, front_view_, back_view_, density_, splats_;
  std::map<uint32_t, std::unique_ptr<gpu::RasterTarget>> caustic_targets_, density_targets_;
  std::map<uint32_t, ViewTargets> view_targets_;
  std::unique_ptr<gpu::Buffer> vertices_, objects_, views_, strengths_, measures_, photon_measures_;
  std::unique_ptr<gpu::Buffer> receivers_, photon_buffer_, photon_data_, landings_, arriving_, splat_data_;
  std::unique_ptr<gpu::Buffer> counts_, caustic_, positions_, normals_, output_;
  size_t receiver_bytes_ = 0;
  uint32_t splatted_passes_ = 0;
};

}  // namespace causticbench
