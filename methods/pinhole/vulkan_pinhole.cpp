#include "methods/pinhole/vulkan_pinhole.h"

namespace causticbench {

namespace {

const uint32_t kPinholeSpirv[] =
#include "pinhole.spv.inc"
    ;
const uint32_t kPinholeFilteredSpirv[] =
#include "pinhole_filtered.spv.inc"
    ;
const uint32_t kPinholeOwnFilterSpirv[] =
#include "pinhole_own_filter.spv.inc"
    ;

struct Parameters {
  uint32_t pixel_count, sample_count;
  int32_t resolution;
  float epsilon, area;
  uint32_t attenuation, fresnel, refraction;
  float footprint_radius;
  uint32_t filtering;
};

// The mip pyramid of a cube map (RGB per texel in, RGBA out): each level averages 2 x 2 texels of the
// one above within its face.
std::vector<std::vector<float>> cube_pyramid(const std::vector<float>& rgb, int size) {
  std::vector<std::vector<float>> levels;
  std::vector<float> level(6ull * size * size * 4);
  for (size_t texel = 0; texel < 6ull * size * size; ++texel) {
    for (int c = 0; c < 3; ++c) level[4 * texel + c] = rgb[3 * texel + c];
  }
  levels.push_back(level);
  for (int extent = size / 2; extent >= 1; extent /= 2) {
    const std::vector<float>& above = levels.back();
    int above_extent = extent * 2;
    std::vector<float> next(6ull * extent * extent * 4, 0.0f);
    for (int face = 0; face < 6; ++face) {
      for (int y = 0; y < extent; ++y) {
        for (int x = 0; x < extent; ++x) {
          for (int c = 0; c < 4; ++c) {
            float sum = 0.0f;
            for (int dy = 0; dy < 2; ++dy) {
              for (int dx = 0; dx < 2; ++dx) {
                sum += above[((static_cast<size_t>(face) * above_extent + 2 * y + dy) * above_extent + 2 * x + dx) * 4 + c];
              }
            }
            next[((static_cast<size_t>(face) * extent + y) * extent + x) * 4 + c] = 0.25f * sum;
          }
        }
      }
    }
    levels.push_back(std::move(next));
  }
  return levels;
}

// Replaces `buffer` with one of `bytes` unless it is already that large, then uploads.
void put(gpu::Context& context, std::unique_ptr<gpu::Buffer>& buffer, const std::vector<float>& values) {
  size_t bytes = values.size() * sizeof(float);
  if (!buffer || buffer->size() < bytes) buffer = std::make_unique<gpu::Buffer>(context, bytes);
  buffer->upload(values.data(), bytes);
}

}  // namespace

VulkanPinhole::VulkanPinhole(gpu::Context& context)
    : context_(context),
      pipeline_(std::make_unique<gpu::ComputePipeline>(context, kPinholeSpirv, sizeof(kPinholeSpirv), 7, sizeof(Parameters))),
      filtered_pipeline_(std::make_unique<gpu::ComputePipeline>(context, kPinholeFilteredSpirv, sizeof(kPinholeFilteredSpirv), 8,
                                                                sizeof(Parameters), 1)),
      own_filter_pipeline_(std::make_unique<gpu::ComputePipeline>(context, kPinholeOwnFilterSpirv, sizeof(kPinholeOwnFilterSpirv),
                                                                  9, sizeof(Parameters))) {}

VulkanPinhole::~VulkanPinhole() = default;

void VulkanPinhole::upload_samples(const PinholeFrameData& frame) {
  put(context_, sample_positions_, frame.sample_positions);
  put(context_, sample_normals_, frame.sample_normals);
  put(context_, materials_, frame.materials);
  if (frame.filtering != 0) put(context_, differentials_, frame.differentials);
}

void VulkanPinhole::upload_light_map(const PinholeFrameData& frame) {
  put(context_, cube_map_, frame.cube_map);
  if (frame.filtering != 0 && frame.own_filter) {
    put(context_, filter_levels_, frame.filter_levels);
  } else if (frame.filtering != 0) {
    texture_ = std::make_unique<gpu::CubeTexture>(context_, frame.resolution, cube_pyramid(frame.cube_map, frame.resolution),
                                                  frame.filtering == 2);
  }
}

std::vector<float> VulkanPinhole::render(const PinholeFrameData& frame, double& gpu_ms) {
  put(context_, receiver_positions_, frame.receiver_positions);
  put(context_, receiver_normals_, frame.receiver_normals);
  size_t output_bytes = static_cast<size_t>(frame.pixel_count()) * 4 * sizeof(float);
  if (!output_ || output_->size() < output_bytes) output_ = std::make_unique<gpu::Buffer>(context_, output_bytes);
  Parameters parameters{frame.pixel_count(), frame.sample_count(), frame.resolution, frame.epsilon, frame.area,
                        frame.attenuation, frame.fresnel, frame.refraction, frame.footprint_radius, frame.filtering};
  uint32_t groups = (frame.pixel_count() + 63) / 64;
  std::vector<const gpu::Buffer*> buffers = {receiver_positions_.get(), receiver_normals_.get(), sample_positions_.get(),
                                             sample_normals_.get(), materials_.get(), cube_map_.get(), output_.get()};
  if (frame.filtering != 0 && frame.own_filter) {
    if (!filter_levels_) throw gpu::VulkanError("VulkanPinhole: upload a filtered frame before rendering it");
    buffers.push_back(differentials_.get());
    buffers.push_back(filter_levels_.get());
    gpu_ms = own_filter_pipeline_->dispatch(buffers, &parameters, groups);
  } else if (frame.filtering != 0) {
    if (!texture_) throw gpu::VulkanError("VulkanPinhole: upload a filtered frame before rendering it");
    buffers.push_back(differentials_.get());
    gpu_ms = filtered_pipeline_->dispatch(buffers, &parameters, groups, {texture_.get()});
  } else {
    gpu_ms = pipeline_->dispatch(buffers, &parameters, groups);
  }
  std::vector<float> result(static_cast<size_t>(frame.pixel_count()) * 4);
  output_->download(result.data(), output_bytes);
  return result;
}

}  // namespace causticbench
