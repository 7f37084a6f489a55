// caustic_mapping's Vulkan backend: a raster pipeline, as the method is one. Per pass, the photon stage
// (shaders/photons.comp: the image-space receiver search of every photon leaving the object), for
// variable splats the coarse density buffer (points drawn with additive blending), the splats' radii and
// weight sums (shaders/weights.comp), then the splats drawn as instanced quads with additive blending
// into the pass's caustic map (shaders/splat.vert, splat.frag); last the lookup over the camera's
// receivers (shaders/lookup.comp). What comes before the photon stage (the light views, receiver map
// and photon buffer) is the CPU's light-view passes (light_pass.cpp). Depends only on gpu/ and the
// standard library.
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
  // Uploads the passes of `frame` (views, receiver maps, measures, photons), runs the photon stage and
  // the splats of every pass, and keeps the caustic maps on the device. With `landings`, reads back per
  // photon (x, y in caustic-map texels, Landing, receiver-map reads) and the arriving flux (rgb, 0), 4
  // floats each. Returns the kernels' time in milliseconds (timestamp queries).
  double splat(const CausticMappingFrameData& frame, std::vector<float>* landings = nullptr,
               std::vector<float>* arriving = nullptr);
  // The lookup of the splatted passes at the receivers of `frame`: RGBA irradiance per pixel.
  std::vector<float> look_up(const CausticMappingFrameData& frame, double& gpu_ms);
  // Both: the frame a replay times.
  std::vector<float> render(const CausticMappingFrameData& frame, double& gpu_ms);

 private:
  gpu::RasterTarget& target(uint32_t size, bool density);

  gpu::Context& context_;
  std::unique_ptr<gpu::ComputePipeline> photons_, weights_, lookup_;
  std::unique_ptr<gpu::RasterPipeline> density_, splats_;
  std::map<uint32_t, std::unique_ptr<gpu::RasterTarget>> caustic_targets_, density_targets_;
  std::unique_ptr<gpu::Buffer> views_, receivers_, measures_, photon_data_, landings_, arriving_, splat_data_;
  std::unique_ptr<gpu::Buffer> counts_, caustic_, positions_, normals_, output_;
  uint32_t splatted_passes_ = 0;
};

}  // namespace causticbench
