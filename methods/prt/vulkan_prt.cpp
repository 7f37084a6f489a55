#include "methods/prt/vulkan_prt.h"

#include <algorithm>

namespace causticbench {

namespace {

const uint32_t kProductSpirv[] =
#include "prt_product.spv.inc"
    ;
const uint32_t kLookupSpirv[] =
#include "prt_lookup.spv.inc"
    ;

struct ProductParameters {
  uint32_t object, rows, coefficients, precision, stride;
};
struct LookupParameters {
  uint32_t pixel_count, object_count, bands;
};

constexpr uint32_t kGroupSize = 64;
// At most this many groups a dispatch (the least maxComputeWorkGroupCount[0] Vulkan guarantees); the
// product's invocations then take further rows in turn.
constexpr uint32_t kMaxGroups = 65535;

// Replaces `buffer` with one of `bytes` unless it is already that large (never empty: Vulkan has no
// empty buffers).
void reserve(gpu::Context& context, std::unique_ptr<gpu::Buffer>& buffer, size_t bytes) {
  bytes = std::max(bytes, sizeof(uint32_t));
  if (!buffer || buffer->size() < bytes) buffer = std::make_unique<gpu::Buffer>(context, bytes);
}

template <class T>
void put(gpu::Context& context, std::unique_ptr<gpu::Buffer>& buffer, const std::vector<T>& values) {
  reserve(context, buffer, values.size() * sizeof(T));
  if (!values.empty()) buffer->upload(values.data(), values.size() * sizeof(T));
}

}  // namespace

VulkanPrt::VulkanPrt(gpu::Context& context)
    : context_(context),
      product_(std::make_unique<gpu::ComputePipeline>(context, kProductSpirv, sizeof(kProductSpirv), 4,
                                                       sizeof(ProductParameters))),
      lookup_(std::make_unique<gpu::ComputePipeline>(context, kLookupSpirv, sizeof(kLookupSpirv), 7,
                                                      sizeof(LookupParameters))) {}

VulkanPrt::~VulkanPrt() = default;

void VulkanPrt::upload_build(const PrtFrameData& frame) {
  put(context_, matrices_, frame.matrices);
  put(context_, factors_, frame.basis_factors);
  put(context_, cosines_, frame.clamped_cosines);
}

double VulkanPrt::update(const PrtFrameData& frame) {
  if (!matrices_) throw gpu::VulkanError("VulkanPrt: upload the build before a frame");
  put(context_, objects_, frame.objects);
  put(context_, lighting_, frame.lighting);
  reserve(context_, incident_, frame.incident_floats() * sizeof(float));
  double milliseconds = 0.0;
  for (uint32_t object = 0; object < frame.object_count(); ++object) {
    const uint32_t rows = frame.cells(object) * 3 * frame.coefficients();
    const uint32_t groups = std::min((rows + kGroupSize - 1) / kGroupSize, kMaxGroups);
    const ProductParameters parameters{object, rows, frame.coefficients(), frame.precision, groups * kGroupSize};
    milliseconds += product_->dispatch({objects_.get(), lighting_.get(), matrices_.get(), incident_.get()}, &parameters,
                                       groups);
  }
  return milliseconds;
}

std::vector<float> VulkanPrt::lookup(const PrtFrameData& frame, double& gpu_ms) {
  if (!incident_) throw gpu::VulkanError("VulkanPrt: update before looking up");
  put(context_, receiver_positions_, frame.receiver_positions);
  put(context_, receiver_normals_, frame.receiver_normals);
  const size_t output_bytes = static_cast<size_t>(frame.pixel_count()) * 4 * sizeof(float);
  reserve(context_, output_, output_bytes);
  const LookupParameters parameters{frame.pixel_count(), frame.object_count(), frame.bands};
  gpu_ms = lookup_->dispatch({receiver_positions_.get(), receiver_normals_.get(), objects_.get(), incident_.get(),
                              factors_.get(), cosines_.get(), output_.get()},
                             &parameters, (frame.pixel_count() + kGroupSize - 1) / kGroupSize);
  std::vector<float> result(static_cast<size_t>(frame.pixel_count()) * 4);
  if (output_bytes > 0) output_->download(result.data(), output_bytes);
  return result;
}

std::vector<float> VulkanPrt::render(const PrtFrameData& frame, double& gpu_ms) {
  const double product_ms = update(frame);
  std::vector<float> result = lookup(frame, gpu_ms);
  gpu_ms += product_ms;
  return result;
}

}  // namespace causticbench
