#include "methods/caustic_mapping/vulkan_caustic_mapping.h"

#include <algorithm>
#include <limits>
#include <string>

namespace causticbench {

namespace {

const uint32_t kLightViewVertexSpirv[] =
#include "caustic_mapping_light_view_vertex.spv.inc"
    ;
const uint32_t kLightViewFragmentSpirv[] =
#include "caustic_mapping_light_view_fragment.spv.inc"
    ;
const uint32_t kLeaveSpirv[] =
#include "caustic_mapping_leave.spv.inc"
    ;
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

struct LightViewParameters {
  uint32_t view, mode, object;
};
struct LeaveParameters {
  uint32_t pass, resolution, first_photon, object, refraction;
};
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
  reserve(context, buffer, std::max<size_t>(values.size() * sizeof(T), 16));
  buffer->upload(values.data(), values.size() * sizeof(T));
}

uint32_t groups(uint32_t count) { return (count + 63) / 64; }

// A light view's pipeline: two RGBA32F targets, the nearest surface kept; `clear` fills both first (its w
// marks a texel nothing covered: +infinity depth for the receiver map, object -1 for the photon buffer's
// front, 0 for its back).
std::unique_ptr<gpu::RasterPipeline> light_view_pipeline(gpu::Context& context, float clear) {
  gpu::RasterOptions options;
  options.colour_targets = 2;
  options.additive = false;
  options.clear[3] = clear;
  return std::make_unique<gpu::RasterPipeline>(context, options, kLightViewVertexSpirv, sizeof(kLightViewVertexSpirv),
                                               kLightViewFragmentSpirv, sizeof(kLightViewFragmentSpirv), 3,
                                               sizeof(LightViewParameters));
}

}  // namespace

VulkanCausticMapping::VulkanCausticMapping(gpu::Context& context)
    : context_(context),
      leave_(std::make_unique<gpu::ComputePipeline>(context, kLeaveSpirv, sizeof(kLeaveSpirv), 6, sizeof(LeaveParameters))),
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
                                                    gpu::Primitive::triangles)),
      receiver_view_(light_view_pipeline(context, std::numeric_limits<float>::infinity())),
      front_view_(light_view_pipeline(context, -1.0f)),
      back_view_(light_view_pipeline(context, 0.0f)) {}

VulkanCausticMapping::~VulkanCausticMapping() = default;

gpu::RasterTarget& VulkanCausticMapping::target(uint32_t size, bool density) {
  auto& targets = density ? density_targets_ : caustic_targets_;
  std::unique_ptr<gpu::RasterTarget>& target = targets[size];
  if (!target)
    target = std::make_unique<gpu::RasterTarget>(context_, size, size,
                                                 density ? VK_FORMAT_R32_SFLOAT : VK_FORMAT_R32G32B32A32_SFLOAT);
  return *target;
}

VulkanCausticMapping::ViewTargets& VulkanCausticMapping::view_targets(uint32_t size) {
  ViewTargets& targets = view_targets_[size];
  if (!targets.first) {
    targets.first = std::make_unique<gpu::RasterTarget>(context_, size, size, VK_FORMAT_R32G32B32A32_SFLOAT);
    targets.second = std::make_unique<gpu::RasterTarget>(context_, size, size, VK_FORMAT_R32G32B32A32_SFLOAT);
    targets.depth = std::make_unique<gpu::RasterTarget>(context_, size, size, VK_FORMAT_D32_SFLOAT);
  }
  return targets;
}

double VulkanCausticMapping::light_view(gpu::RasterPipeline& pipeline, uint32_t size, uint32_t view, uint32_t mode,
                                        uint32_t object, uint32_t vertices, gpu::Buffer& into, size_t first) {
  ViewTargets& targets = view_targets(size);
  const LightViewParameters parameters{view, mode, object};
  const size_t vec4 = 4 * sizeof(float), texels = static_cast<size_t>(size) * size;
  return pipeline.draw({targets.first.get(), targets.second.get()}, targets.depth.get(),
                       {vertices_.get(), objects_.get(), views_.get()}, &parameters, 0, vertices, 1,
                       {{&into, first * vec4}, {&into, (first + texels) * vec4}});
}

double VulkanCausticMapping::splat(const CausticMappingFrameData& frame, Readback* readback) {
  check_frame_data(frame, "VulkanCausticMapping");
  using F = CausticMappingFrameData;
  put(context_, vertices_, frame.vertices);
  put(context_, objects_, frame.objects);
  put(context_, views_, frame.views);
  put(context_, strengths_, frame.strengths);
  put(context_, measures_, frame.measures);
  put(context_, photon_measures_, frame.photon_measures);
  const size_t vec4 = 4 * sizeof(float), slots = frame.photon_count();
  receiver_bytes_ = 2 * static_cast<size_t>(frame.texel_count()) * vec4;
  reserve(context_, receivers_, std::max<size_t>(receiver_bytes_, 16));
  reserve(context_, photon_buffer_, std::max<size_t>(4 * slots * vec4, 16));
  reserve(context_, photon_data_, std::max<size_t>(4 * slots * vec4, 16));
  reserve(context_, landings_, std::max<size_t>(slots * vec4, 16));
  reserve(context_, arriving_, std::max<size_t>(slots * vec4, 16));
  reserve(context_, splat_data_, std::max<size_t>(slots * vec4, 16));
  reserve(context_, caustic_, std::max<size_t>(static_cast<size_t>(frame.texel_count()) * vec4, 16));
  const uint32_t vertices = frame.vertex_count();
  double milliseconds = 0.0;
  for (uint32_t pass = 0; pass < frame.pass_count(); ++pass) {
    const uint32_t* words = &frame.passes[F::kPassWords * pass];
    const uint32_t n = words[0], first_texel = words[1], first_photon = words[2], p = words[3], object = words[4];
    const uint32_t count = p * p;
    // The photon buffer: the nearest surface of every object, then (glass that may take two interfaces)
    // the object's back faces.
    milliseconds += light_view(*front_view_, p, 2 * pass + 1, 1, object, vertices, *photon_buffer_, 4 * size_t(first_photon));
    const bool glass = frame.objects[F::kObjectFloats * object] == 2.0f;
    if (glass && frame.refraction != 2)
      milliseconds += light_view(*back_view_, p, 2 * pass + 1, 2, object, vertices, *photon_buffer_,
                                 4 * size_t(first_photon) + 2 * size_t(count));
    const LeaveParameters leave{pass, p, first_photon, object, frame.refraction};
    milliseconds += leave_->dispatch({views_.get(), objects_.get(), photon_buffer_.get(), photon_measures_.get(),
                                      strengths_.get(), photon_data_.get()},
                                     &leave, groups(count));
    // The receiver map: the surfaces that receive caustics, but the object's own.
    milliseconds += light_view(*receiver_view_, n, 2 * pass, 0, object, vertices, *receivers_, 2 * size_t(first_texel));
    const PhotonParameters stage{pass, n, first_texel, first_photon, count, frame.search_iterations, frame.plane_hit};
    milliseconds += photons_->dispatch({views_.get(), receivers_.get(), photon_data_.get(), landings_.get(), arriving_.get()},
                                       &stage, groups(count));
    if (frame.splat == 2) {
      const uint32_t cells = (n + 3) / 4;
      reserve(context_, counts_, static_cast<size_t>(cells) * cells * sizeof(float));
      const DensityParameters density{first_photon, cells};
      milliseconds += density_->draw(target(cells, true), {landings_.get()}, &density, count, 1, *counts_, 0);
    }
    if (!counts_) reserve(context_, counts_, 16);  // the weights read no counts but bind a buffer
    const WeightParameters weights{first_photon, count, n, frame.splat, frame.splat_radius, frame.splat_photons,
                                   frame.max_splat_radius};
    milliseconds += weights_->dispatch({landings_.get(), counts_.get(), splat_data_.get()}, &weights, groups(count));
    const SplatParameters splat{first_photon, n};
    // The caustic map, cleared, splatted and copied to its place among the passes' maps.
    milliseconds += splats_->draw(target(n, false), {landings_.get(), arriving_.get(), splat_data_.get()}, &splat, 6, count,
                                  *caustic_, static_cast<size_t>(first_texel) * vec4);
  }
  splatted_passes_ = frame.pass_count();
  if (readback) {
    readback->photons.assign(slots * 16, 0.0f);
    readback->landings.assign(slots * 4, 0.0f);
    readback->arriving.assign(slots * 4, 0.0f);
    if (slots > 0) {
      photon_data_->download(readback->photons.data(), slots * 4 * vec4);
      landings_->download(readback->landings.data(), slots * vec4);
      arriving_->download(readback->arriving.data(), slots * vec4);
    }
  }
  return milliseconds;
}

std::vector<float> VulkanCausticMapping::receiver_maps() const {
  std::vector<float> maps(receiver_bytes_ / sizeof(float));
  if (!maps.empty()) receivers_->download(maps.data(), receiver_bytes_);
  return maps;
}

std::vector<float> VulkanCausticMapping::look_up(const CausticMappingFrameData& frame, double& gpu_ms) {
  if (splatted_passes_ != frame.pass_count())
    throw gpu::VulkanError("VulkanCausticMapping: splat the frame's passes before looking them up");
  put(context_, positions_, frame.receiver_positions);
  put(context_, normals_, frame.receiver_normals);
  const size_t output_bytes = static_cast<size_t>(frame.pixel_count()) * 4 * sizeof(float);
  reserve(context_, output_, output_bytes);
  reserve(context_, caustic_, 16);
  reserve(context_, receivers_, 16);
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
