#include "methods/pinhole/vulkan_pinhole.h"

namespace causticbench {

namespace {

const uint32_t kPinholeSpirv[] =
#include "pinhole.spv.inc"
    ;

struct Parameters {
  uint32_t pixel_count, sample_count;
  int32_t resolution;
  float epsilon, area;
  uint32_t attenuation, fresnel, refraction;
};

// Replaces `buffer` with one of `bytes` unless it is already that large, then uploads.
void put(gpu::Context& context, std::unique_ptr<gpu::Buffer>& buffer, const std::vector<float>& values) {
  size_t bytes = values.size() * sizeof(float);
  if (!buffer || buffer->size() < bytes) buffer = std::make_unique<gpu::Buffer>(context, bytes);
  buffer->upload(values.data(), bytes);
}

}  // namespace

VulkanPinhole::VulkanPinhole(gpu::Context& context)
    : context_(context),
      pipeline_(std::make_unique<gpu::ComputePipeline>(context, kPinholeSpirv, sizeof(kPinholeSpirv), 7, sizeof(Parameters))) {}

VulkanPinhole::~VulkanPinhole() = default;

void VulkanPinhole::upload_frame(const PinholeFrameData& frame) {
  put(context_, sample_positions_, frame.sample_positions);
  put(context_, sample_normals_, frame.sample_normals);
  put(context_, materials_, frame.materials);
  put(context_, cube_map_, frame.cube_map);
}

std::vector<float> VulkanPinhole::render(const PinholeFrameData& frame, double& gpu_ms) {
  put(context_, receiver_positions_, frame.receiver_positions);
  put(context_, receiver_normals_, frame.receiver_normals);
  size_t output_bytes = static_cast<size_t>(frame.pixel_count()) * 4 * sizeof(float);
  if (!output_ || output_->size() < output_bytes) output_ = std::make_unique<gpu::Buffer>(context_, output_bytes);
  Parameters parameters{frame.pixel_count(), frame.sample_count(), frame.resolution, frame.epsilon, frame.area,
                        frame.attenuation, frame.fresnel, frame.refraction};
  uint32_t groups = (frame.pixel_count() + 63) / 64;
  gpu_ms = pipeline_->dispatch({receiver_positions_.get(), receiver_normals_.get(), sample_positions_.get(),
                                sample_normals_.get(), materials_.get(), cube_map_.get(), output_.get()},
                               &parameters, groups);
  std::vector<float> result(static_cast<size_t>(frame.pixel_count()) * 4);
  output_->download(result.data(), output_bytes);
  return result;
}

}  // namespace causticbench
