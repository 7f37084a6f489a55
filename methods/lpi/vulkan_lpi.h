// lpi's Vulkan backend: uploads the stored values and the shells' lookup tables once per build, the
// objects' records and the lights' reads once per frame, and evaluates every receiver pixel in a
// compute shader (lpi.comp). Depends only on gpu/ and the standard library.
#pragma once

#include <memory>
#include <vector>

#include "gpu/vulkan_context.h"
#include "methods/lpi/frame_data.h"

namespace causticbench {

class VulkanLpi {
 public:
  explicit VulkanLpi(gpu::Context& context);
  ~VulkanLpi();
  // The build: values, scales and shell tables (needed again only after a new build).
  void upload_volumes(const LpiFrameData& frame);
  // The frame: object records and light reads.
  void upload_frame(const LpiFrameData& frame);
  // Uploads the receivers of `frame`, dispatches, and returns RGBA irradiance per pixel; gpu_ms gets the
  // kernel's duration from timestamp queries.
  std::vector<float> render(const LpiFrameData& frame, double& gpu_ms);

 private:
  gpu::Context& context_;
  std::unique_ptr<gpu::ComputePipeline> pipeline_;
  std::unique_ptr<gpu::Buffer> values_, scales_, shells_, objects_, lights_;
  std::unique_ptr<gpu::Buffer> receiver_positions_, receiver_normals_, output_;
};

}  // namespace causticbench
