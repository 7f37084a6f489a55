#include "gpu/vulkan_context.h"

#include "gpu/pipeline_parts.h"

#include <algorithm>
#include <cstring>

namespace causticbench::gpu {

void check(VkResult result, const char* what) {
  if (result != VK_SUCCESS) throw VulkanError(std::string("Vulkan: ") + what + " failed with VkResult " + std::to_string(result));
}

Context::Context() {
  VkApplicationInfo application{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  application.pApplicationName = "causticbench";
  application.apiVersion = VK_API_VERSION_1_1;
  VkInstanceCreateInfo instance_info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  instance_info.pApplicationInfo = &application;
  check(vkCreateInstance(&instance_info, nullptr, &instance_), "vkCreateInstance (is a Vulkan driver installed?)");
  uint32_t count = 0;
  vkEnumeratePhysicalDevices(instance_, &count, nullptr);
  if (count == 0) throw VulkanError("Vulkan: no physical device (install mesa-vulkan-drivers for lavapipe)");
  std::vector<VkPhysicalDevice> devices(count);
  vkEnumeratePhysicalDevices(instance_, &count, devices.data());
  // A real GPU before a CPU implementation.
  const VkPhysicalDeviceType preference[] = {VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU, VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU,
                                             VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU, VK_PHYSICAL_DEVICE_TYPE_CPU,
                                             VK_PHYSICAL_DEVICE_TYPE_OTHER};
  VkPhysicalDeviceProperties properties{};
  for (VkPhysicalDeviceType wanted : preference) {
    for (VkPhysicalDevice candidate : devices) {
      vkGetPhysicalDeviceProperties(candidate, &properties);
      if (properties.deviceType == wanted && physical_ == VK_NULL_HANDLE) physical_ = candidate;
    }
    if (physical_ != VK_NULL_HANDLE) break;
  }
  vkGetPhysicalDeviceProperties(physical_, &properties);
  device_name_ = properties.deviceName;
  cpu_device_ = properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
  timestamp_period_ = properties.limits.timestampPeriod;
  vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);

  uint32_t family_count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physical_, &family_count, nullptr);
  std::vector<VkQueueFamilyProperties> families(family_count);
  vkGetPhysicalDeviceQueueFamilyProperties(physical_, &family_count, families.data());
  // A queue that computes and rasterises (the raster pipelines of gpu/raster.h), else one that computes.
  uint32_t family = UINT32_MAX;
  const VkQueueFlags both = VK_QUEUE_COMPUTE_BIT | VK_QUEUE_GRAPHICS_BIT;
  for (uint32_t i = 0; i < family_count; ++i) {
    if ((families[i].queueFlags & both) == both && family == UINT32_MAX) family = i;
  }
  for (uint32_t i = 0; i < family_count; ++i) {
    if ((families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) && family == UINT32_MAX) family = i;
  }
  if (family == UINT32_MAX) throw VulkanError("Vulkan: the device has no compute queue");
  graphics_ = (families[family].queueFlags & VK_QUEUE_GRAPHICS_BIT) != 0;
  timestamps_ = families[family].timestampValidBits > 0 && properties.limits.timestampComputeAndGraphics;
  float priority = 1.0f;
  VkDeviceQueueCreateInfo queue_info{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queue_info.queueFamilyIndex = family;
  queue_info.queueCount = 1;
  queue_info.pQueuePriorities = &priority;
  VkPhysicalDeviceFeatures supported{}, enabled{};
  vkGetPhysicalDeviceFeatures(physical_, &supported);
  if (supported.samplerAnisotropy) {
    enabled.samplerAnisotropy = VK_TRUE;
    max_anisotropy_ = properties.limits.maxSamplerAnisotropy;
  }
  VkDeviceCreateInfo device_info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  device_info.queueCreateInfoCount = 1;
  device_info.pQueueCreateInfos = &queue_info;
  device_info.pEnabledFeatures = &enabled;
  check(vkCreateDevice(physical_, &device_info, nullptr, &device_), "vkCreateDevice");
  vkGetDeviceQueue(device_, family, 0, &queue_);
  VkCommandPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pool_info.queueFamilyIndex = family;
  pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  check(vkCreateCommandPool(device_, &pool_info, nullptr, &command_pool_), "vkCreateCommandPool");
}

Context::~Context() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    vkDestroyCommandPool(device_, command_pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
}

uint32_t Context::memory_type(uint32_t type_bits, VkMemoryPropertyFlags flags) const {
  for (uint32_t i = 0; i < memory_.memoryTypeCount; ++i) {
    if ((type_bits & (1u << i)) && (memory_.memoryTypes[i].propertyFlags & flags) == flags) return i;
  }
  throw VulkanError("Vulkan: no memory type with the required properties");
}

VkCommandBuffer Context::begin_commands() {
  VkCommandBufferAllocateInfo allocate{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  allocate.commandPool = command_pool_;
  allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  allocate.commandBufferCount = 1;
  VkCommandBuffer commands;
  check(vkAllocateCommandBuffers(device_, &allocate, &commands), "vkAllocateCommandBuffers");
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(commands, &begin), "vkBeginCommandBuffer");
  return commands;
}

void Context::end_and_wait(VkCommandBuffer commands) {
  check(vkEndCommandBuffer(commands), "vkEndCommandBuffer");
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &commands;
  check(vkQueueSubmit(queue_, 1, &submit, VK_NULL_HANDLE), "vkQueueSubmit");
  check(vkQueueWaitIdle(queue_), "vkQueueWaitIdle");
  vkFreeCommandBuffers(device_, command_pool_, 1, &commands);
}

namespace {

struct Allocation {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
};

Allocation allocate(Context& context, size_t bytes, VkBufferUsageFlags usage, VkMemoryPropertyFlags flags) {
  Allocation allocation;
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = bytes;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  check(vkCreateBuffer(context.device(), &info, nullptr, &allocation.buffer), "vkCreateBuffer");
  VkMemoryRequirements requirements;
  vkGetBufferMemoryRequirements(context.device(), allocation.buffer, &requirements);
  VkMemoryAllocateInfo memory_info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  memory_info.allocationSize = requirements.size;
  memory_info.memoryTypeIndex = context.memory_type(requirements.memoryTypeBits, flags);
  check(vkAllocateMemory(context.device(), &memory_info, nullptr, &allocation.memory), "vkAllocateMemory");
  check(vkBindBufferMemory(context.device(), allocation.buffer, allocation.memory, 0), "vkBindBufferMemory");
  return allocation;
}

void release(Context& context, Allocation& allocation) {
  vkDestroyBuffer(context.device(), allocation.buffer, nullptr);
  vkFreeMemory(context.device(), allocation.memory, nullptr);
}

// A host-visible staging buffer for one transfer.
struct Staging {
  Context& context;
  Allocation allocation;
  void* mapped = nullptr;
  Staging(Context& c, size_t bytes) : context(c) {
    allocation = allocate(context, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                          VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    check(vkMapMemory(context.device(), allocation.memory, 0, bytes, 0, &mapped), "vkMapMemory");
  }
  ~Staging() {
    vkUnmapMemory(context.device(), allocation.memory);
    release(context, allocation);
  }
};

}  // namespace

Buffer::Buffer(Context& context, size_t bytes) : context_(context), bytes_(std::max<size_t>(bytes, 16)) {
  Allocation allocation = allocate(context, bytes_,
                                   VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                       VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                   VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  buffer_ = allocation.buffer;
  memory_ = allocation.memory;
}

Buffer::~Buffer() {
  vkDestroyBuffer(context_.device(), buffer_, nullptr);
  vkFreeMemory(context_.device(), memory_, nullptr);
}

void Buffer::upload(const void* data, size_t bytes) {
  if (bytes > bytes_) throw VulkanError("Vulkan: upload larger than the buffer");
  if (bytes == 0) return;
  Staging staging(context_, bytes);
  std::memcpy(staging.mapped, data, bytes);
  context_.submit([&](VkCommandBuffer commands) {
    VkBufferCopy region{0, 0, bytes};
    vkCmdCopyBuffer(commands, staging.allocation.buffer, buffer_, 1, &region);
  });
}

void Buffer::download(void* data, size_t bytes) const {
  if (bytes > bytes_) throw VulkanError("Vulkan: download larger than the buffer");
  Staging staging(context_, bytes);
  context_.submit([&](VkCommandBuffer commands) {
    VkBufferCopy region{0, 0, bytes};
    vkCmdCopyBuffer(commands, buffer_, staging.allocation.buffer, 1, &region);
  });
  std::memcpy(data, staging.mapped, bytes);
}

CubeTexture::CubeTexture(Context& context, int size, const std::vector<std::vector<float>>& levels, bool anisotropic)
    : context_(context) {
  VkDevice device = context.device();
  const VkFormat format = VK_FORMAT_R32G32B32A32_SFLOAT;
  VkFormatProperties format_properties;
  vkGetPhysicalDeviceFormatProperties(context.physical_device(), format, &format_properties);
  if (!(format_properties.optimalTilingFeatures & VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT)) {
    throw VulkanError("Vulkan: the device cannot filter RGBA32F images linearly");
  }
  uint32_t level_count = static_cast<uint32_t>(levels.size());
  VkImageCreateInfo image_info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  image_info.flags = VK_IMAGE_CREATE_CUBE_COMPATIBLE_BIT;
  image_info.imageType = VK_IMAGE_TYPE_2D;
  image_info.format = format;
  image_info.extent = {static_cast<uint32_t>(size), static_cast<uint32_t>(size), 1};
  image_info.mipLevels = level_count;
  image_info.arrayLayers = 6;
  image_info.samples = VK_SAMPLE_COUNT_1_BIT;
  image_info.tiling = VK_IMAGE_TILING_OPTIMAL;
  image_info.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  image_info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  check(vkCreateImage(device, &image_info, nullptr, &image_), "vkCreateImage");
  memory_ = bind_device_memory(context, image_);

  // All levels through one staging buffer, one copy region per level (6 layers each).
  size_t total = 0;
  for (const auto& level : levels) total += level.size() * sizeof(float);
  Staging staging(context, total);
  std::vector<VkBufferImageCopy> regions;
  size_t offset = 0;
  for (uint32_t level = 0; level < level_count; ++level) {
    std::memcpy(static_cast<char*>(staging.mapped) + offset, levels[level].data(), levels[level].size() * sizeof(float));
    uint32_t extent = std::max(1u, static_cast<uint32_t>(size) >> level);
    VkBufferImageCopy region{};
    region.bufferOffset = offset;
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, level, 0, 6};
    region.imageExtent = {extent, extent, 1};
    regions.push_back(region);
    offset += levels[level].size() * sizeof(float);
  }
  context.submit([&](VkCommandBuffer commands) {
    VkImageMemoryBarrier barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    barrier.srcQueueFamilyIndex = barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.image = image_;
    barrier.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, level_count, 0, 6};
    barrier.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    barrier.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    barrier.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0,
                         nullptr, 1, &barrier);
    vkCmdCopyBufferToImage(commands, staging.allocation.buffer, image_, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                           static_cast<uint32_t>(regions.size()), regions.data());
    barrier.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    barrier.newLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
    vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 0, nullptr, 0,
                         nullptr, 1, &barrier);
  });
  VkImageViewCreateInfo view_info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  view_info.image = image_;
  view_info.viewType = VK_IMAGE_VIEW_TYPE_CUBE;
  view_info.format = format;
  view_info.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, level_count, 0, 6};
  check(vkCreateImageView(device, &view_info, nullptr, &view_), "vkCreateImageView");
  VkSamplerCreateInfo sampler_info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  sampler_info.magFilter = sampler_info.minFilter = VK_FILTER_LINEAR;
  sampler_info.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
  sampler_info.addressModeU = sampler_info.addressModeV = sampler_info.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  sampler_info.maxLod = static_cast<float>(level_count);
  if (anisotropic && context.max_anisotropy() > 1.0f) {
    sampler_info.anisotropyEnable = VK_TRUE;
    sampler_info.maxAnisotropy = std::min(16.0f, context.max_anisotropy());
  }
  check(vkCreateSampler(device, &sampler_info, nullptr, &sampler_), "vkCreateSampler");
}

CubeTexture::~CubeTexture() {
  VkDevice device = context_.device();
  vkDestroySampler(device, sampler_, nullptr);
  vkDestroyImageView(device, view_, nullptr);
  vkDestroyImage(device, image_, nullptr);
  vkFreeMemory(device, memory_, nullptr);
}

ComputePipeline::ComputePipeline(Context& context, const uint32_t* spirv, size_t spirv_bytes, uint32_t buffer_count,
                                 uint32_t push_constant_bytes, uint32_t image_count)
    : context_(context), buffer_count_(buffer_count), push_constant_bytes_(push_constant_bytes), image_count_(image_count) {
  VkDevice device = context.device();
  pipeline_layout(device, buffer_count, image_count, VK_SHADER_STAGE_COMPUTE_BIT, push_constant_bytes, set_layout_, layout_);
  VkShaderModule module = shader_module(device, spirv, spirv_bytes);
  VkComputePipelineCreateInfo pipeline_info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  pipeline_info.stage = VkPipelineShaderStageCreateInfo{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  pipeline_info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  pipeline_info.stage.module = module;
  pipeline_info.stage.pName = "main";
  pipeline_info.layout = layout_;
  VkResult result = vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &pipeline_info, nullptr, &pipeline_);
  vkDestroyShaderModule(device, module, nullptr);
  check(result, "vkCreateComputePipelines");
  pool_ = descriptor_pool(device, buffer_count, image_count);
  timestamps_ = std::make_unique<TimestampPair>(context);
}

ComputePipeline::~ComputePipeline() {
  VkDevice device = context_.device();
  timestamps_.reset();
  vkDestroyDescriptorPool(device, pool_, nullptr);
  vkDestroyPipeline(device, pipeline_, nullptr);
  vkDestroyPipelineLayout(device, layout_, nullptr);
  vkDestroyDescriptorSetLayout(device, set_layout_, nullptr);
}

double ComputePipeline::dispatch(const std::vector<const Buffer*>& buffers, const void* push_constants, uint32_t groups_x,
                                 const std::vector<const CubeTexture*>& images) {
  if (buffers.size() != buffer_count_ || images.size() != image_count_) {
    throw VulkanError("Vulkan: wrong number of buffers or images for the pipeline");
  }
  VkDevice device = context_.device();
  VkDescriptorSet set = storage_set(device, pool_, set_layout_, buffers, images);
  context_.submit([&](VkCommandBuffer commands) {
    timestamps_->begin(commands);
    // What an earlier submission wrote (a copy, another kernel, a raster pass) is what this one reads.
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
    vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &barrier,
                         0, nullptr, 0, nullptr);
    vkCmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
    vkCmdBindDescriptorSets(commands, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &set, 0, nullptr);
    if (push_constant_bytes_) {
      vkCmdPushConstants(commands, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, push_constant_bytes_, push_constants);
    }
    vkCmdDispatch(commands, groups_x, 1, 1);
    timestamps_->end(commands);
  });
  const double milliseconds = timestamps_->milliseconds();
  vkFreeDescriptorSets(device, pool_, 1, &set);
  return milliseconds;
}

}  // namespace causticbench::gpu
