#include "methods/lpi/vulkan_lpi.h"

#include <algorithm>

namespace causticbench {

namespace {

const uint32_t kLpiSpirv[] =
#include "lpi.spv.inc"
    ;

struct Parameters {
  uint32_t pixel_count, object_count, storage, channels, precision, outside;
};

// Replaces `buffer` with one of the values' size unless it is already that large, then uploads. A
// buffer is never empty (Vulkan has no empty buffers): an empty array leaves one unread word.
template <class T>
void put(gpu::Context& context, std::unique_ptr<gpu::Buffer>& buffer, const std::vector<T>& values) {
  const size_t bytes = values.size() * sizeof(T);
  if (!buffer || buffer->size() < std::max(bytes, sizeof(uint32_t))) {
    buffer = std::make_unique<gpu::Buffer>(context, std::max(bytes, sizeof(uint32_t)));
  }
  if (bytes > 0) buffer->upload(values.data(), bytes);
}

}  // namespace

VulkanLpi::VulkanLpi(gpu::Context& context)
    : context_(context),
      pipeline_(std::make_unique<gpu::ComputePipeline>(context, kLpiSpirv, sizeof(kLpiSpirv), 8, sizeof(Parameters))) {}

VulkanLpi::~VulkanLpi() = default;

void VulkanLpi::upload_volumes(const LpiFrameData& frame) {
  put(context_, values_, frame.values);
  put(context_, scales_, frame.scales);
  put(context_, shells_, frame.shells);
}

void VulkanLpi::upload_frame(const LpiFrameData& frame) {
  put(context_, objects_, frame.objects);
  put(context_, lights_, frame.lights);
}

std::vector<float> VulkanLpi::render(const LpiFrameData& frame, double& gpu_ms) {
  if (!values_ || !objects_) throw gpu::VulkanError("VulkanLpi: upload the volumes and the frame before rendering");
  put(context_, receiver_positions_, frame.receiver_positions);
  put(context_, receiver_normals_, frame.receiver_normals);
  const size_t output_bytes = static_cast<size_t>(frame.pixel_count()) * 4 * sizeof(float);
  if (!output_ || output_->size() < std::max(output_bytes, sizeof(float))) {
    output_ = std::make_unique<gpu::Buffer>(context_, std::max(output_bytes, sizeof(float)));
  }
  const Parameters parameters{frame.pixel_count(), frame.object_count(), frame.storage,
                              frame.channels,      frame.precision,      frame.outside};
  const uint32_t groups = (frame.pixel_count() + 63) / 64;
  gpu_ms = pipeline_->dispatch({receiver_positions_.get(), receiver_normals_.get(), objects_.get(), lights_.get(),
                                values_.get(), scales_.get(), shells_.get(), output_.get()},
                               &parameters, groups);
  std::vector<float> result(static_cast<size_t>(frame.pixel_count()) * 4);
  if (output_bytes > 0) output_->download(result.data(), output_bytes);
  return result;
}

}  // namespace causticbench
