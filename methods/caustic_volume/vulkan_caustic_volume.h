// caustic_volume's Vulkan backend: the volumes' footprints rasterised over the camera's image like shadow
// volumes (shaders/footprint.vert), each fragment's receiver point tested against its volume exactly
// (shaders/containment.frag), the light added with blending one + one into an RGBA32F image. The CPU
// builds the volumes (methods/caustic_volume/beams.cpp) and their footprints. Depends only on gpu/ and
// the standard library.
#pragma once

#include <memory>
#include <vector>

#include "gpu/raster.h"
#include "gpu/vulkan_context.h"
#include "methods/caustic_volume/frame_data.h"

namespace causticbench {

class VulkanCausticVolume {
 public:
  explicit VulkanCausticVolume(gpu::Context& context);
  ~VulkanCausticVolume();
  // The frame's caustic irradiance, RGBA per pixel; with `counts`, per pixel the volumes tested and those
  // that lit it (2 floats a pixel). gpu_ms: the draw's time (timestamp queries).
  std::vector<float> render(const CausticVolumeFrameData& frame, double& gpu_ms, std::vector<float>* counts = nullptr);

 private:
  gpu::Context& context_;
  std::unique_ptr<gpu::RasterPipeline> pipeline_;
  std::unique_ptr<gpu::RasterTarget> light_, tests_;
  std::unique_ptr<gpu::Buffer> footprints_, volumes_, positions_, normals_, objects_, output_, tested_;
};

}  // namespace causticbench
