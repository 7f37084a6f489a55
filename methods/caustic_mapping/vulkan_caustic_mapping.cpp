#include "methods/caustic_mapping/vulkan_caustic_mapping.h"

#include <string>

namespace causticbench {

namespace {

const uint32_t kPhotonsSpirv[] =
#include "caustic_mapping_photons.spv.inc"
    ;
const uint32_t kDensityVertexSpirv[] =
#include "caustic_mapping_density_vertex.spv.inc"
    ;
const uint32_t kDensityFragmentSpirv[] =
#include "caustic_mapping_density_fragment.spv.inc"
    ;
const uint32_t kWeightsSpirv[] =
#include "caustic_mapping_weights.spv.inc"
    ;
const uint32_t kSplatVertexSpirv[] =
#include "caustic_mapping_splat_vertex.spv.inc"
    ;
const uint32_t kSplatFragmentSpirv[] =
#include "caustic_mapping_splat_fragment.spv.inc"
    ;
const uint32_t kLookupSpirv[] =
#include "caustic_mapping_lookup.spv.inc"
    ;

struct PhotonParameters {
  uint32_t pass, resolution, first_texel, first_photon, photon_count, iterations, plane_hit;
};
struct DensityParameters {
  uint32_t first_photon, cells;
};
struct WeightParameters {
  uint32_t first_photon, photon_count, resolution, splat;
  float splat_radius, splat_photons, max_splat_radius;
};
struct SplatParameters {
  uint32_t first_photon, resolution;
};
struct LookupParameters {
  uint32_t pass, resolution, first_texel, pixel_count, first_pass;
};

// Replaces `buffer` with one of `bytes` unless it is already that large.
void reserve(gpu::Context& context, std::unique_ptr<gpu::Buffer>& buffer, size_t bytes) {
  if (!buffer || buffer->size() < bytes) buffer = std::make_unique<gpu::Buffer>(context, bytes);
}

template <class T>
void put(gpu::Context& context, std::unique_ptr<gpu::Buffer>& buffer, const std::vector<T>& values) {
  reserve(context, buffer, values.size() * sizeof(T));
  buffer->upload(values.data(), values.size() * sizeof(T));
}

uint32_t groups(uint32_t count) { return (count + 63) / 64; }

}  // namespace

VulkanCausticMapping::VulkanCausticMapping(gpu::Context& context)
    : context_(context),
      photons_(std::make_unique<gpu::ComputePipeline>(context, kPhotonsSpirv, sizeof(kPhotonsSpirv), 5,
                                                      sizeof(PhotonParameters))),
      weights_(std::make_unique<gpu::ComputePipeline>(context, kWeightsSpirv, sizeof(kWeightsSpirv), 3,
                                                      sizeof(WeightParameters))),
      lookup_(std::make_unique<gpu::ComputePipeline>(context, kLookupSpirv, sizeof(kLookupSpirv), 7,
                                                     sizeof(LookupParameters))),
      density_(std::make_unique<gpu::RasterPipeline>(context, VK_FORMAT_R32_SFLOAT, kDensityVertexSpirv,
                                                     sizeof(kDensityVertexSpirv), kDensityFragmentSpirv,
                                                     sizeof(kDensityFragmentSpirv), 1, sizeof(DensityParameters),
                                                     gpu::Primitive::points)),
      splats_(std::make_unique<gpu::RasterPipeline>(context, VK_FORMAT_R32G32B32A32_SFLOAT, kSplatVertexSpirv,
                                                    sizeof(kSplatVertexSpirv), kSplatFragmentSpirv,
                                                    sizeof(kSplatFragmentSpirv), 3, sizeof(SplatParameters),
                                                    gpu::Primitive::triangles)) {}

VulkanCausticMapping::~VulkanCausticMapping() = default;

gpu::RasterTarget& VulkanCausticMapping::target(uint32_t size, bool density) {
  auto& targets = density ? density_targets_ : caustic_targets_;
  std::unique_ptr<gpu::RasterTarget>& target = targets[size];
  if (!target)
    target = std::make_unique<gpu::RasterTarget>(context_, size, size,
                                                 density ? VK_FORMAT_R32_SFLOAT : VK_FORMAT_R32G32B32A32_SFLOAT);
  return *target;
}

double VulkanCausticMapping::splat(const CausticMappingFrameData& frame, std::vector<float>* landings,
                                   std::vector<float>* arriving) {
  check_frame_data(frame, "VulkanCausticMapping");
  using F = CausticMappingFrameData;
  put(context_, views_, frame.views);
  put(context_, receivers_, frame.receivers);
  put(context_, measures_, frame.measures);
  put(context_, photon_data_, frame.photons);
  const size_t photon_bytes = static_cast<size_t>(frame.photon_count()) * 4 * sizeof(float);
  reserve(context_, landings_, photon_bytes);
  reserve(context_, arriving_, photon_bytes);
  reserve(context_, splat_data_, photon_bytes);
  reserve(context_, caustic_, static_cast<size_t>(frame.texel_count()) * 4 * sizeof(float));
  double milliseconds = 0.0;
  for (uint32_t pass = 0; pass < frame.pass_count(); ++pass) {
    const uint32_t* words = &frame.passes[F::kPassWords * pass];
    const uint32_t n = words[0], first_texel = words[1], first_photon = words[2], count = words[3];
    const PhotonParameters stage{pass, n, first_texel, first_photon, count, frame.search_iterations, frame.plane_hit};
    if (count > 0)
      milliseconds += photons_->dispatch({views_.get(), receivers_.get(), photon_data_.get(), landings_.get(), arriving_.get()},
                                         &stage, groups(count));
    if (frame.splat == 2 && count > 0) {
      const uint32_t cells = (n + 3) / 4;
      reserve(context_, counts_, static_cast<size_t>(cells) * cells * sizeof(float));
      const DensityParameters density{first_photon, cells};
      milliseconds += density_->draw(target(cells, true), {landings_.get()}, &density, count, 1, *counts_, 0);
    }
    if (!counts_) reserve(context_, counts_, 16);  // the weights read no counts but bind a buffer
    const WeightParameters weights{first_photon, count, n, frame.splat, frame.splat_radius, frame.splat_photons,
                                   frame.max_splat_radius};
    if (count > 0)
      milliseconds += weights_->dispatch({landings_.get(), counts_.get(), splat_data_.get()}, &weights, groups(count));
    const SplatParameters splat{first_photon, n};
    // The caustic map, cleared, splatted and copied to its place among the passes' maps.
    milliseconds += splats_->draw(target(n, false), {landings_.get(), arriving_.get(), splat_data_.get()}, &splat, 6, count,
                                  *caustic_, static_cast<size_t>(first_texel) * 4 * sizeof(float));
  }
  splatted_passes_ = frame.pass_count();
  if (landings) {
    landings->resize(static_cast<size_t>(frame.photon_count()) * 4);
    if (!landings->empty()) landings_->download(landings->data(), photon_bytes);
  }
  if (arriving) {
    arriving->resize(static_cast<size_t>(frame.photon_count()) * 4);
    if (!arriving->empty()) arriving_->download(arriving->data(), photon_bytes);
  }
  return milliseconds;
}

std::vector<float> VulkanCausticMapping::look_up(const CausticMappingFrameData& frame, double& gpu_ms) {
  if (splatted_passes_ != frame.pass_count())
    throw gpu::VulkanError("VulkanCausticMapping: splat the frame's passes before looking them up");
  put(context_, positions_, frame.receiver_positions);
  put(context_, normals_, frame.receiver_normals);
  const size_t output_bytes = static_cast<size_t>(frame.pixel_count()) * 4 * sizeof(float);
  reserve(context_, output_, output_bytes);
  reserve(context_, caustic_, 16);
  gpu_ms = 0.0;
  std::vector<float> result(static_cast<size_t>(frame.pixel_count()) * 4, 0.0f);
  if (frame.pass_count() == 0) return result;
  for (uint32_t pass = 0; pass < frame.pass_count(); ++pass) {
    const uint32_t* words = &frame.passes[CausticMappingFrameData::kPassWords * pass];
    const LookupParameters lookup{pass, words[0], words[1], frame.pixel_count(), pass == 0 ? 1u : 0u};
    gpu_ms += lookup_->dispatch({views_.get(), receivers_.get(), measures_.get(), caustic_.get(), positions_.get(),
                                 normals_.get(), output_.get()},
                                &lookup, groups(frame.pixel_count()));
  }
  output_->download(result.data(), output_bytes);
  return result;
}

std::vector<float> VulkanCausticMapping::render(const CausticMappingFrameData& frame, double& gpu_ms) {
  const double splat_ms = splat(frame);
  std::vector<float> result = look_up(frame, gpu_ms);
  gpu_ms += splat_ms;
  return result;
}

}  // namespace causticbench
