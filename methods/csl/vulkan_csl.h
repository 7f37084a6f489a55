// csl's Vulkan backend: the frame's spot lights evaluated at every receiver pixel in a compute shader
// (csl.comp) that repeats the CPU evaluation (methods/csl/spot_light_evaluate.h) in float. The images
// are uploaded once per build, the spot lights once per frame, the receivers per render. Depends only
// on gpu/ and the standard library.
#pragma once

#include <memory>
#include <vector>

#include "gpu/vulkan_context.h"
#include "methods/csl/frame_data.h"

namespace causticbench {

class VulkanCsl {
 public:
  explicit VulkanCsl(gpu::Context& context);
  ~VulkanCsl();
  // The intensity images and their on-axis tables (images, image_scalars, texels, radial).
  void upload_images(const CslFrameData& frame);
  // The spot lights (lights, light_images), whose image indices refer to the uploaded images.
  void upload_lights(const CslFrameData& frame);
  // Uploads the receivers and the objects of `frame`, dispatches, and returns RGBA irradiance per
  // pixel; gpu_ms gets the kernel's duration from timestamp queries.
  std::vector<float> render(const CslFrameData& frame, double& gpu_ms);

 private:
  gpu::Context& context_;
  std::unique_ptr<gpu::ComputePipeline> pipeline_;
  std::unique_ptr<gpu::Buffer> images_, image_scalars_, texels_, radial_, lights_, light_images_;
  std::unique_ptr<gpu::Buffer> receiver_positions_, receiver_normals_, objects_, object_lights_, output_;
  uint32_t uploaded_lights_ = 0;
};

}  // namespace causticbench
