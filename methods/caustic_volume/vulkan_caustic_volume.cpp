#include "methods/caustic_volume/vulkan_caustic_volume.h"

#include <algorithm>

namespace causticbench {

namespace {

const uint32_t kFootprintSpirv[] =
#include "caustic_volume_footprint.spv.inc"
    ;
const uint32_t kContainmentSpirv[] =
#include "caustic_volume_containment.spv.inc"
    ;

struct Parameters {
  uint32_t width, height, intensity;
};

template <class T>
void put(gpu::Context& context, std::unique_ptr<gpu::Buffer>& buffer, const std::vector<T>& values) {
  const size_t bytes = std::max<size_t>(values.size() * sizeof(T), 16);
  if (!buffer || buffer->size() < bytes) buffer = std::make_unique<gpu::Buffer>(context, bytes);
  if (!values.empty()) buffer->upload(values.data(), values.size() * sizeof(T));
}

gpu::RasterOptions options() {
  gpu::RasterOptions options;
  options.colour_targets = 2;  // the light, and the counts
  return options;
}

}  // namespace

VulkanCausticVolume::VulkanCausticVolume(gpu::Context& context)
    : context_(context),
      pipeline_(std::make_unique<gpu::RasterPipeline>(context, options(), kFootprintSpirv, sizeof(kFootprintSpirv),
                                                      kContainmentSpirv, sizeof(kContainmentSpirv), 5,
                                                      sizeof(Parameters))) {}

VulkanCausticVolume::~VulkanCausticVolume() = default;

std::vector<float> VulkanCausticVolume::render(const CausticVolumeFrameData& frame, double& gpu_ms,
                                               std::vector<float>* counts) {
  check_frame_data(frame, "VulkanCausticVolume");
  std::vector<float> result(static_cast<size_t>(frame.pixel_count()) * 4, 0.0f);
  gpu_ms = 0.0;
  if (frame.pixel_count() == 0) return result;
  if (!light_ || light_->width() != frame.width || light_->height() != frame.height) {
    light_ = std::make_unique<gpu::RasterTarget>(context_, frame.width, frame.height, VK_FORMAT_R32G32B32A32_SFLOAT);
    tests_ = std::make_unique<gpu::RasterTarget>(context_, frame.width, frame.height, VK_FORMAT_R32G32B32A32_SFLOAT);
  }
  put(context_, footprints_, frame.footprints);
  put(context_, volumes_, frame.volumes);
  put(context_, positions_, frame.receiver_positions);
  put(context_, normals_, frame.receiver_normals);
  put(context_, objects_, frame.receiver_objects);
  const size_t bytes = light_->bytes();
  if (!output_ || output_->size() < bytes) output_ = std::make_unique<gpu::Buffer>(context_, bytes);
  if (!tested_ || tested_->size() < bytes) tested_ = std::make_unique<gpu::Buffer>(context_, bytes);
  const Parameters parameters{frame.width, frame.height, frame.intensity};
  gpu_ms = pipeline_->draw({light_.get(), tests_.get()}, nullptr,
                           {footprints_.get(), volumes_.get(), positions_.get(), normals_.get(), objects_.get()},
                           &parameters, 0, frame.footprint_vertex_count(), 1, {{output_.get(), 0}, {tested_.get(), 0}});
  output_->download(result.data(), bytes);
  if (counts) {
    std::vector<float> rgba(result.size());
    tested_->download(rgba.data(), bytes);
    counts->resize(static_cast<size_t>(frame.pixel_count()) * 2);
    for (size_t pixel = 0; pixel < frame.pixel_count(); ++pixel) {
      (*counts)[2 * pixel] = rgba[4 * pixel];
      (*counts)[2 * pixel + 1] = rgba[4 * pixel + 1];
    }
  }
  return result;
}

}  // namespace causticbench
