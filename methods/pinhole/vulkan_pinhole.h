// The pinhole method's Vulkan backend: uploads the reflector samples, materials and light cube map
// once per frame and evaluates every receiver pixel in a compute shader (pinhole.comp). Depends only
// on gpu/ and the standard library.
#pragma once

#include <memory>
#include <vector>

#include "gpu/vulkan_context.h"
#include "methods/pinhole/frame_data.h"

namespace causticbench {

class VulkanPinhole {
 public:
  explicit VulkanPinhole(gpu::Context& context);
  ~VulkanPinhole();
  // Uploads the reflector samples, their materials and, when filtering, their differentials.
  void upload_samples(const PinholeFrameData& frame);
  // Uploads the light cube map and, when filtering, the own filter's levels (frame.own_filter) or a
  // mip-mapped cube texture for textureGrad whose levels are 2 x 2 box averages. Needed only when the
  // map changes.
  void upload_light_map(const PinholeFrameData& frame);
  // Both.
  void upload_frame(const PinholeFrameData& frame) {
    upload_samples(frame);
    upload_light_map(frame);
  }
  // Uploads the receivers of `frame`, dispatches, and returns RGBA irradiance per pixel; gpu_ms gets the
  // kernel's duration from timestamp queries.
  std::vector<float> render(const PinholeFrameData& frame, double& gpu_ms);

 private:
  gpu::Context& context_;
  std::unique_ptr<gpu::ComputePipeline> pipeline_, filtered_pipeline_, own_filter_pipeline_;
  std::unique_ptr<gpu::Buffer> sample_positions_, sample_normals_, materials_, cube_map_, differentials_, filter_levels_;
  std::unique_ptr<gpu::CubeTexture> texture_;
  std::unique_ptr<gpu::Buffer> receiver_positions_, receiver_normals_, output_;
};

}  // namespace causticbench
