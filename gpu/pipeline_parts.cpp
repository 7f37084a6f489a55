#include "gpu/pipeline_parts.h"

#include <algorithm>

namespace causticbench::gpu {

VkShaderModule shader_module(VkDevice device, const uint32_t* spirv, size_t bytes) {
  VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  info.codeSize = bytes;
  info.pCode = spirv;
  VkShaderModule module;
  check(vkCreateShaderModule(device, &info, nullptr, &module), "vkCreateShaderModule");
  return module;
}

VkDeviceMemory bind_device_memory(Context& context, VkImage image) {
  VkMemoryRequirements requirements;
  vkGetImageMemoryRequirements(context.device(), image, &requirements);
  VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  info.allocationSize = requirements.size;
  info.memoryTypeIndex = context.memory_type(requirements.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  VkDeviceMemory memory;
  check(vkAllocateMemory(context.device(), &info, nullptr, &memory), "vkAllocateMemory");
  check(vkBindImageMemory(context.device(), image, memory, 0), "vkBindImageMemory");
  return memory;
}

void pipeline_layout(VkDevice device, uint32_t buffer_count, uint32_t image_count, VkShaderStageFlags stages,
                     uint32_t push_constant_bytes, VkDescriptorSetLayout& set_layout, VkPipelineLayout& layout) {
  std::vector<VkDescriptorSetLayoutBinding> bindings(buffer_count + image_count);
  for (uint32_t i = 0; i < buffer_count + image_count; ++i) {
    const VkDescriptorType type = i < buffer_count ? VK_DESCRIPTOR_TYPE_STORAGE_BUFFER : VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    bindings[i] = VkDescriptorSetLayoutBinding{i, type, 1, stages, nullptr};
  }
  VkDescriptorSetLayoutCreateInfo set_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  set_info.bindingCount = buffer_count + image_count;
  set_info.pBindings = bindings.data();
  check(vkCreateDescriptorSetLayout(device, &set_info, nullptr, &set_layout), "vkCreateDescriptorSetLayout");
  VkPushConstantRange range{stages, 0, push_constant_bytes};
  VkPipelineLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layout_info.setLayoutCount = 1;
  layout_info.pSetLayouts = &set_layout;
  layout_info.pushConstantRangeCount = push_constant_bytes ? 1 : 0;
  layout_info.pPushConstantRanges = &range;
  check(vkCreatePipelineLayout(device, &layout_info, nullptr, &layout), "vkCreatePipelineLayout");
}

VkDescriptorPool descriptor_pool(VkDevice device, uint32_t buffer_count, uint32_t image_count) {
  VkDescriptorPoolSize sizes[2] = {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, std::max(1u, buffer_count)},
                                   {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, std::max(1u, image_count)}};
  VkDescriptorPoolCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  info.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
  info.maxSets = 1;
  info.poolSizeCount = 2;
  info.pPoolSizes = sizes;
  VkDescriptorPool pool;
  check(vkCreateDescriptorPool(device, &info, nullptr, &pool), "vkCreateDescriptorPool");
  return pool;
}

VkDescriptorSet storage_set(VkDevice device, VkDescriptorPool pool, VkDescriptorSetLayout layout,
                            const std::vector<const Buffer*>& buffers, const std::vector<const CubeTexture*>& images) {
  VkDescriptorSetAllocateInfo allocate{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  allocate.descriptorPool = pool;
  allocate.descriptorSetCount = 1;
  allocate.pSetLayouts = &layout;
  VkDescriptorSet set;
  check(vkAllocateDescriptorSets(device, &allocate, &set), "vkAllocateDescriptorSets");
  const uint32_t count = static_cast<uint32_t>(buffers.size() + images.size());
  std::vector<VkDescriptorBufferInfo> infos(buffers.size());
  std::vector<VkDescriptorImageInfo> image_infos(images.size());
  std::vector<VkWriteDescriptorSet> writes(count);
  for (uint32_t i = 0; i < count; ++i) {
    writes[i] = VkWriteDescriptorSet{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    writes[i].dstSet = set;
    writes[i].dstBinding = i;
    writes[i].descriptorCount = 1;
    if (i < buffers.size()) {
      infos[i] = VkDescriptorBufferInfo{buffers[i]->handle(), 0, VK_WHOLE_SIZE};
      writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      writes[i].pBufferInfo = &infos[i];
    } else {
      const CubeTexture* image = images[i - buffers.size()];
      image_infos[i - buffers.size()] =
          VkDescriptorImageInfo{image->sampler(), image->view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
      writes[i].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
      writes[i].pImageInfo = &image_infos[i - buffers.size()];
    }
  }
  vkUpdateDescriptorSets(device, count, writes.data(), 0, nullptr);
  return set;
}

TimestampPair::TimestampPair(Context& context) : context_(context) {
  if (!context.has_timestamps()) return;
  VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  info.queryCount = 2;
  check(vkCreateQueryPool(context.device(), &info, nullptr, &queries_), "vkCreateQueryPool");
}

TimestampPair::~TimestampPair() {
  if (queries_) vkDestroyQueryPool(context_.device(), queries_, nullptr);
}

void TimestampPair::begin(VkCommandBuffer commands) {
  if (!queries_) return;
  vkCmdResetQueryPool(commands, queries_, 0, 2);
  vkCmdWriteTimestamp(commands, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_, 0);
}

void TimestampPair::end(VkCommandBuffer commands) {
  if (queries_) vkCmdWriteTimestamp(commands, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, 1);
}

double TimestampPair::milliseconds() const {
  if (!queries_) return 0.0;
  uint64_t stamps[2] = {0, 0};
  check(vkGetQueryPoolResults(context_.device(), queries_, 0, 2, sizeof(stamps), stamps, sizeof(uint64_t),
                              VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
        "vkGetQueryPoolResults");
  return static_cast<double>(stamps[1] - stamps[0]) * context_.timestamp_period() * 1e-6;
}

}  // namespace causticbench::gpu
