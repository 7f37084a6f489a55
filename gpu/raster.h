// Rasterisation for the methods that are rasterisers (caustics mapping renders its light views and splats
// its photons as sprites): float colour targets and a graphics pipeline that draws into them, without
// vertex buffers (the vertex shader reads storage buffers by gl_VertexIndex and gl_InstanceIndex), then
// copies the targets into storage buffers for the compute passes that follow. Two ways to draw: additive
// blending (photons' flux adds up), or a depth test that keeps the nearest surface (a light view's
// G-buffer, as shadow mapping renders it). Depends only on the Vulkan loader and gpu/vulkan_context.h,
// like the rest of gpu/.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "gpu/vulkan_context.h"

namespace causticbench::gpu {

// A width x height image of `format`: a colour target (VK_FORMAT_R32_SFLOAT or VK_FORMAT_R32G32B32A32_SFLOAT)
// or a depth target (VK_FORMAT_D32_SFLOAT).
class RasterTarget {
 public:
  RasterTarget(Context& context, uint32_t width, uint32_t height, VkFormat format);
  ~RasterTarget();
  RasterTarget(const RasterTarget&) = delete;
  RasterTarget& operator=(const RasterTarget&) = delete;
  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  VkFormat format() const { return format_; }
  VkImage image() const { return image_; }
  VkImageView view() const { return view_; }
  // Bytes of the target's texels, tightly packed (what draw() copies out).
  size_t bytes() const;

 private:
  Context& context_;
  uint32_t width_, height_;
  VkFormat format_;
  VkImage image_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
};

enum class Primitive { points, triangles };

// How a pipeline draws.
struct RasterOptions {
  Primitive primitive = Primitive::triangles;
  VkFormat format = VK_FORMAT_R32G32B32A32_SFLOAT;  // every colour target's
  uint32_t colour_targets = 1;                     // fragment outputs at locations 0 .. colour_targets - 1
  // true: every output added to what the target holds (blend one + one). false: a D32F depth target,
  // cleared to 0, keeps the fragment of greatest depth (reversed depth: the vertex stage writes near / z
  // or an orthographic equivalent, 1 nearest), and its outputs replace the target's.
  bool additive = true;
  float clear[4] = {0.0f, 0.0f, 0.0f, 0.0f};  // every colour target's value before the draw
};

// A vertex and a fragment shader (SPIR-V) drawing `primitive`s into targets of `format`. Bindings
// 0 .. buffer_count - 1 are storage buffers both stages see; push constants likewise.
class RasterPipeline {
 public:
  RasterPipeline(Context& context, const RasterOptions& options, const uint32_t* vertex_spirv, size_t vertex_bytes,
                 const uint32_t* fragment_spirv, size_t fragment_bytes, uint32_t buffer_count,
                 uint32_t push_constant_bytes);
  // One additive target of `format`.
  RasterPipeline(Context& context, VkFormat format, const uint32_t* vertex_spirv, size_t vertex_bytes,
                 const uint32_t* fragment_spirv, size_t fragment_bytes, uint32_t buffer_count,
                 uint32_t push_constant_bytes, Primitive primitive);
  ~RasterPipeline();
  RasterPipeline(const RasterPipeline&) = delete;
  RasterPipeline& operator=(const RasterPipeline&) = delete;
  // Clears `target` to zero, draws `vertices` vertices `instances` times over the whole target (window
  // coordinates: texel (x, y) covers [x, x + 1) x [y, y + 1), row y at y), copies the target into
  // `into` from byte `into_offset` on (RasterTarget::bytes() of it), all in one submission; returns the
  // GPU time in milliseconds from timestamp queries (0 without them).
  double draw(RasterTarget& target, const std::vector<const Buffer*>& buffers, const void* push_constants,
              uint32_t vertices, uint32_t instances, Buffer& into, size_t into_offset = 0);
  // Where a colour target is copied after the draw.
  struct Copy {
    Buffer* into = nullptr;
    size_t offset = 0;
  };
  // The general draw: clears `targets` (options.clear) and `depth` (with a depth test: a D32F target of
  // the same size), draws vertices first_vertex .. first_vertex + vertices - 1, `instances` times, and
  // copies targets[i] into copies[i].
  double draw(const std::vector<RasterTarget*>& targets, RasterTarget* depth, const std::vector<const Buffer*>& buffers,
              const void* push_constants, uint32_t first_vertex, uint32_t vertices, uint32_t instances,
              const std::vector<Copy>& copies);

 private:
  Context& context_;
  RasterOptions options_;
  uint32_t buffer_count_, push_constant_bytes_;
  VkRenderPass render_pass_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  std::unique_ptr<TimestampPair> timestamps_;
};

}  // namespace causticbench::gpu
