// What the compute and the raster pipelines (gpu/vulkan_context.h, gpu/raster.h) build alike: shader
// modules, a descriptor pool and set of storage buffers (and combined image samplers), and the pair of
// timestamp queries around a submission.
#pragma once

#include <cstdint>
#include <vector>

#include "gpu/vulkan_context.h"

namespace causticbench::gpu {

VkShaderModule shader_module(VkDevice device, const uint32_t* spirv, size_t bytes);

// Device-local memory for `image`, bound to it (free it with vkFreeMemory after destroying the image).
VkDeviceMemory bind_device_memory(Context& context, VkImage image);

// The set layout (bindings 0 .. buffer_count - 1 storage buffers, then `image_count` combined image
// samplers, all seen by `stages`) and the pipeline layout over it with `push_constant_bytes` of push
// constants.
void pipeline_layout(VkDevice device, uint32_t buffer_count, uint32_t image_count, VkShaderStageFlags stages,
                     uint32_t push_constant_bytes, VkDescriptorSetLayout& set_layout, VkPipelineLayout& layout);

// A pool for one descriptor set of `buffer_count` storage buffers and `image_count` image samplers.
VkDescriptorPool descriptor_pool(VkDevice device, uint32_t buffer_count, uint32_t image_count);

// One set of `layout` from `pool`: bindings 0 .. buffers - 1 the buffers, then the cube maps. Free it with
// vkFreeDescriptorSets.
VkDescriptorSet storage_set(VkDevice device, VkDescriptorPool pool, VkDescriptorSetLayout layout,
                            const std::vector<const Buffer*>& buffers, const std::vector<const CubeTexture*>& images = {});

// Two timestamps around the commands of one submission (none where the queue has no timestamps).
class TimestampPair {
 public:
  explicit TimestampPair(Context& context);
  ~TimestampPair();
  TimestampPair(const TimestampPair&) = delete;
  TimestampPair& operator=(const TimestampPair&) = delete;
  void begin(VkCommandBuffer commands);  // resets the pair and writes the first
  void end(VkCommandBuffer commands);
  // After the submission completed: milliseconds between the two, 0 without timestamps.
  double milliseconds() const;

 private:
  Context& context_;
  VkQueryPool queries_ = VK_NULL_HANDLE;
};

}  // namespace causticbench::gpu
