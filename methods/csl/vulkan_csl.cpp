#include "methods/csl/vulkan_csl.h"

#include <string>

namespace causticbench {

namespace {

const uint32_t kCslSpirv[] =
#include "csl.spv.inc"
    ;

struct Parameters {
  uint32_t pixel_count, object_count, intensity_correction, on_axis;
};

// Replaces `buffer` with one of the values' size unless it is already that large, then uploads.
template <class T>
void put(gpu::Context& context, std::unique_ptr<gpu::Buffer>& buffer, const std::vector<T>& values) {
  const size_t bytes = values.size() * sizeof(T);
  if (!buffer || buffer->size() < bytes) buffer = std::make_unique<gpu::Buffer>(context, bytes);
  buffer->upload(values.data(), bytes);
}

}  // namespace

VulkanCsl::VulkanCsl(gpu::Context& context)
    : context_(context),
      pipeline_(std::make_unique<gpu::ComputePipeline>(context, kCslSpirv, sizeof(kCslSpirv), 11, sizeof(Parameters))) {}

VulkanCsl::~VulkanCsl() = default;

void VulkanCsl::upload_images(const CslFrameData& frame) {
  put(context_, images_, frame.images);
  put(context_, image_scalars_, frame.image_scalars);
  put(context_, texels_, frame.texels);
  put(context_, radial_, frame.radial);
}

void VulkanCsl::upload_lights(const CslFrameData& frame) {
  put(context_, lights_, frame.lights);
  put(context_, light_images_, frame.light_images);
  uploaded_lights_ = frame.light_count();
}

std::vector<float> VulkanCsl::render(const CslFrameData& frame, double& gpu_ms) {
  if (!images_ || !lights_) throw gpu::VulkanError("VulkanCsl: upload the images and the spot lights before rendering");
  // The shader trusts the indices: an object's spot lights must be among the uploaded ones.
  for (uint32_t object = 0; object < frame.object_count(); ++object) {
    if (static_cast<uint64_t>(frame.object_lights[2 * object]) + frame.object_lights[2 * object + 1] > uploaded_lights_) {
      throw gpu::VulkanError("VulkanCsl: object " + std::to_string(object) + " names spot lights that were not uploaded");
    }
  }
  put(context_, receiver_positions_, frame.receiver_positions);
  put(context_, receiver_normals_, frame.receiver_normals);
  put(context_, objects_, frame.objects);
  put(context_, object_lights_, frame.object_lights);
  const size_t output_bytes = static_cast<size_t>(frame.pixel_count()) * 4 * sizeof(float);
  if (!output_ || output_->size() < output_bytes) output_ = std::make_unique<gpu::Buffer>(context_, output_bytes);
  const Parameters parameters{frame.pixel_count(), frame.object_count(), frame.intensity_correction, frame.on_axis};
  const uint32_t groups = (frame.pixel_count() + 63) / 64;
  gpu_ms = pipeline_->dispatch({receiver_positions_.get(), receiver_normals_.get(), objects_.get(), object_lights_.get(),
                                lights_.get(), light_images_.get(), images_.get(), image_scalars_.get(), texels_.get(),
                                radial_.get(), output_.get()},
                               &parameters, groups);
  std::vector<float> result(static_cast<size_t>(frame.pixel_count()) * 4);
  output_->download(result.data(), output_bytes);
  return result;
}

}  // namespace causticbench
