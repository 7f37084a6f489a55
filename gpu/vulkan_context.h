// A minimal Vulkan compute runtime shared by every GPU backend: device selection (a real GPU first,
// Mesa's lavapipe otherwise), device-local buffers with staging uploads and read-backs, compute
// pipelines from SPIR-V compiled by glslc at build time, and timestamp queries. Depends only on the
// Vulkan loader and the C++ standard library, so that causticbench-gpubench runs on GPU machines
// that have none of the project's other dependencies.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace causticbench::gpu {

class VulkanError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Context;
class TimestampPair;

// A storage buffer in device memory.
class Buffer {
 public:
  Buffer(Context& context, size_t bytes);
  ~Buffer();
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  void upload(const void* data, size_t bytes);
  void download(void* data, size_t bytes) const;
  VkBuffer handle() const { return buffer_; }
  size_t size() const { return bytes_; }

 private:
  Context& context_;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  size_t bytes_ = 0;
};

// A mip-mapped RGBA float cube map with a trilinear sampler, optionally anisotropic, for filtered
// lookups with explicit gradients (textureGrad). The mip levels are given, not generated, so that
// every device filters the same pyramid.
class CubeTexture {
 public:
  // levels[l] holds 6 faces of (size >> l)^2 RGBA texels, face-major (the faces of LightCubeMap).
  CubeTexture(Context& context, int size, const std::vector<std::vector<float>>& levels, bool anisotropic);
  ~CubeTexture();
  CubeTexture(const CubeTexture&) = delete;
  CubeTexture& operator=(const CubeTexture&) = delete;
  VkImageView view() const { return view_; }
  VkSampler sampler() const { return sampler_; }

 private:
  Context& context_;
  VkImage image_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
  VkSampler sampler_ = VK_NULL_HANDLE;
};

// A compute pipeline whose bindings 0 .. n-1 are storage buffers, followed by `image_count` combined
// image samplers, with push constants.
class ComputePipeline {
 public:
  ComputePipeline(Context& context, const uint32_t* spirv, size_t spirv_bytes, uint32_t buffer_count,
                  uint32_t push_constant_bytes, uint32_t image_count = 0);
  ~ComputePipeline();
  ComputePipeline(const ComputePipeline&) = delete;
  ComputePipeline& operator=(const ComputePipeline&) = delete;
  // Records, submits and waits for one dispatch; returns the GPU time in milliseconds measured with
  // timestamp queries (0 when the queue has no timestamps).
  double dispatch(const std::vector<const Buffer*>& buffers, const void* push_constants, uint32_t groups_x,
                  const std::vector<const CubeTexture*>& images = {});

 private:
  Context& context_;
  uint32_t buffer_count_, push_constant_bytes_, image_count_;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  std::unique_ptr<TimestampPair> timestamps_;
};

class Context {
 public:
  // Picks the first discrete GPU, then integrated, then virtual, then CPU (lavapipe) device.
  Context();
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  const std::string& device_name() const { return device_name_; }
  bool is_cpu_device() const { return cpu_device_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  VkCommandPool command_pool() const { return command_pool_; }
  float timestamp_period() const { return timestamp_period_; }
  VkPhysicalDevice physical_device() const { return physical_; }
  // samplerAnisotropy is enabled when the device has it; 1 otherwise.
  float max_anisotropy() const { return max_anisotropy_; }
  bool has_timestamps() const { return timestamps_; }
  // Whether the queue rasterises too (gpu/raster.h needs it).
  bool has_graphics() const { return graphics_; }
  uint32_t memory_type(uint32_t type_bits, VkMemoryPropertyFlags flags) const;
  // One-shot command buffer: record with `record`, submit, wait.
  template <typename Record>
  void submit(Record record) {
    VkCommandBuffer commands = begin_commands();
    record(commands);
    end_and_wait(commands);
  }
  VkCommandBuffer begin_commands();
  void end_and_wait(VkCommandBuffer commands);

 private:
  VkInstance instance_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  VkCommandPool command_pool_ = VK_NULL_HANDLE;
  VkPhysicalDeviceMemoryProperties memory_{};
  std::string device_name_;
  bool cpu_device_ = false;
  bool timestamps_ = false;
  bool graphics_ = false;
  float timestamp_period_ = 1.0f;
  float max_anisotropy_ = 1.0f;
};

void check(VkResult result, const char* what);

}  // namespace causticbench::gpu
