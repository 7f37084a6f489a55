// prt's Vulkan backend: uploads the matrices and the basis tables once per build, the objects' records
// and the lighting once per frame; per frame l = M L for every row of every object (shaders/product.comp,
// the incident field kept on the device) and per pixel the lookup (shaders/lookup.comp). Depends only on
// gpu/ and the standard library.
#pragma once

#include <memory>
#include <vector>

#include "gpu/vulkan_context.h"
#include "methods/prt/frame_data.h"

namespace causticbench {

class VulkanPrt {
 public:
  explicit VulkanPrt(gpu::Context& context);
  ~VulkanPrt();
  // The build: matrices and basis tables (needed again only after a new build).
  void upload_build(const PrtFrameData& frame);
  // The frame: records and lighting, then l = M L per row; returns the kernels' time in milliseconds.
  double update(const PrtFrameData& frame);
  // The receivers of `frame` looked up in the incident field of the last update(); RGBA per pixel.
  std::vector<float> lookup(const PrtFrameData& frame, double& gpu_ms);
  // A whole frame (what gpubench times): update() then lookup(), gpu_ms the sum of their kernels.
  std::vector<float> render(const PrtFrameData& frame, double& gpu_ms);

 private:
  gpu::Context& context_;
  std::unique_ptr<gpu::ComputePipeline> product_, lookup_;
  std::unique_ptr<gpu::Buffer> matrices_, factors_, cosines_, objects_, lighting_, incident_;
  std::unique_ptr<gpu::Buffer> receiver_positions_, receiver_normals_, output_;
};

}  // namespace causticbench
