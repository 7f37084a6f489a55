#include "gpu/vulkan_context.h"

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
  uint32_t family = UINT32_MAX;
  for (uint32_t i = 0; i < family_count; ++i) {
    if ((families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) && family == UINT32_MAX) family = i;
  }
  if (family == UINT32_MAX) throw VulkanError("Vulkan: the device has no compute queue");
  timestamps_ = families[family].timestampValidBits > 0 && properties.limits.timestampComputeAndGraphics;
  float priority = 1.0f;
  VkDeviceQueueCreateInfo queue_info{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queue_info.queueFamilyIndex = family;
  queue_info.queueCount = 1;
  queue_info.pQueuePriorities = &priority;
  VkDeviceCreateInfo device_info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  device_info.queueCreateInfoCount = 1;
  device_info.pQueueCreateInfos = &queue_info;
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

ComputePipeline::ComputePipeline(Context& context, const uint32_t* spirv, size_t spirv_bytes, uint32_t buffer_count,
                                 uint32_t push_constant_bytes)
    : context_(context), buffer_count_(buffer_count), push_constant_bytes_(push_constant_bytes) {
  VkDevice device = context.device();
  std::vector<VkDescriptorSetLayoutBinding> bindings(buffer_count);
  for (uint32_t i = 0; i < buffer_count; ++i) {
    bindings[i] = VkDescriptorSetLayoutBinding{i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
  }
  VkDescriptorSetLayoutCreateInfo set_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  set_info.bindingCount = buffer_count;
  set_info.pBindings = bindings.data();
  check(vkCreateDescriptorSetLayout(device, &set_info, nullptr, &set_layout_), "vkCreateDescriptorSetLayout");
  VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_constant_bytes};
  VkPipelineLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layout_info.setLayoutCount = 1;
  layout_info.pSetLayouts = &set_layout_;
  layout_info.pushConstantRangeCount = push_constant_bytes ? 1 : 0;
  layout_info.pPushConstantRanges = &range;
  check(vkCreatePipelineLayout(device, &layout_info, nullptr, &layout_), "vkCreatePipelineLayout");
  VkShaderModuleCreateInfo module_info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  module_info.codeSize = spirv_bytes;
  module_info.pCode = spirv;
  VkShaderModule module;
  check(vkCreateShaderModule(device, &module_info, nullptr, &module), "vkCreateShaderModule");
  VkComputePipelineCreateInfo pipeline_info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  pipeline_info.stage = VkPipelineShaderStageCreateInfo{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  pipeline_info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  pipeline_info.stage.module = module;
  pipeline_info.stage.pName = "main";
  pipeline_info.layout = layout_;
  VkResult result = vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &pipeline_info, nullptr, &pipeline_);
  vkDestroyShaderModule(device, module, nullptr);
  check(result, "vkCreateComputePipelines");
  VkDescriptorPoolSize pool_size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, buffer_count};
  VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pool_info.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
  pool_info.maxSets = 1;
  pool_info.poolSizeCount = 1;
  pool_info.pPoolSizes = &pool_size;
  check(vkCreateDescriptorPool(device, &pool_info, nullptr, &pool_), "vkCreateDescriptorPool");
  if (context.has_timestamps()) {
    VkQueryPoolCreateInfo query_info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    query_info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    query_info.queryCount = 2;
    check(vkCreateQueryPool(device, &query_info, nullptr, &queries_), "vkCreateQueryPool");
  }
}

ComputePipeline::~ComputePipeline() {
  VkDevice device = context_.device();
  if (queries_) vkDestroyQueryPool(device, queries_, nullptr);
  vkDestroyDescriptorPool(device, pool_, nullptr);
  vkDestroyPipeline(device, pipeline_, nullptr);
  vkDestroyPipelineLayout(device, layout_, nullptr);
  vkDestroyDescriptorSetLayout(device, set_layout_, nullptr);
}

double ComputePipeline::dispatch(const std::vector<const Buffer*>& buffers, const void* push_constants, uint32_t groups_x) {
  if (buffers.size() != buffer_count_) throw VulkanError("Vulkan: wrong number of buffers for the pipeline");
  VkDevice device = context_.device();
  VkDescriptorSetAllocateInfo allocate{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  allocate.descriptorPool = pool_;
  allocate.descriptorSetCount = 1;
  allocate.pSetLayouts = &set_layout_;
  VkDescriptorSet set;
  check(vkAllocateDescriptorSets(device, &allocate, &set), "vkAllocateDescriptorSets");
  std::vector<VkDescriptorBufferInfo> infos(buffer_count_);
  std::vector<VkWriteDescriptorSet> writes(buffer_count_);
  for (uint32_t i = 0; i < buffer_count_; ++i) {
    infos[i] = VkDescriptorBufferInfo{buffers[i]->handle(), 0, VK_WHOLE_SIZE};
    writes[i] = VkWriteDescriptorSet{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    writes[i].dstSet = set;
    writes[i].dstBinding = i;
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[i].pBufferInfo = &infos[i];
  }
  vkUpdateDescriptorSets(device, buffer_count_, writes.data(), 0, nullptr);
  context_.submit([&](VkCommandBuffer commands) {
    if (queries_) {
      vkCmdResetQueryPool(commands, queries_, 0, 2);
      vkCmdWriteTimestamp(commands, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_, 0);
    }
    vkCmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
    vkCmdBindDescriptorSets(commands, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &set, 0, nullptr);
    if (push_constant_bytes_) {
      vkCmdPushConstants(commands, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, push_constant_bytes_, push_constants);
    }
    vkCmdDispatch(commands, groups_x, 1, 1);
    if (queries_) vkCmdWriteTimestamp(commands, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, 1);
  });
  double milliseconds = 0.0;
  if (queries_) {
    uint64_t stamps[2] = {0, 0};
    check(vkGetQueryPoolResults(device, queries_, 0, 2, sizeof(stamps), stamps, sizeof(uint64_t),
                                VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
          "vkGetQueryPoolResults");
    milliseconds = static_cast<double>(stamps[1] - stamps[0]) * context_.timestamp_period() * 1e-6;
  }
  vkFreeDescriptorSets(device, pool_, 1, &set);
  return milliseconds;
}

}  // namespace causticbench::gpu
