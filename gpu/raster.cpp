#include "gpu/raster.h"

#include <algorithm>
#include <string>

#include "gpu/pipeline_parts.h"

namespace causticbench::gpu {

namespace {

size_t texel_bytes(VkFormat format) { return format == VK_FORMAT_R32G32B32A32_SFLOAT ? 16 : 4; }

RasterOptions additive_options(VkFormat format, Primitive primitive) {
  RasterOptions options;
  options.format = format;
  options.primitive = primitive;
  return options;
}

}  // namespace

RasterTarget::RasterTarget(Context& context, uint32_t width, uint32_t height, VkFormat format)
    : context_(context), width_(width), height_(height), format_(format) {
  const bool depth = format == VK_FORMAT_D32_SFLOAT;
  if (format != VK_FORMAT_R32_SFLOAT && format != VK_FORMAT_R32G32B32A32_SFLOAT && !depth)
    throw VulkanError("Vulkan: a raster target is R32F, RGBA32F or D32F");
  if (!context.has_graphics()) throw VulkanError("Vulkan: the device's queue does not rasterise");
  VkFormatProperties properties;
  vkGetPhysicalDeviceFormatProperties(context.physical_device(), format, &properties);
  if (!depth && !(properties.optimalTilingFeatures & VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BLEND_BIT))
    throw VulkanError("Vulkan: the device cannot blend into float targets (needed to add photons' flux)");
  if (depth && !(properties.optimalTilingFeatures & VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT))
    throw VulkanError("Vulkan: the device has no 32-bit float depth targets");
  VkDevice device = context.device();
  VkImageCreateInfo image_info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  image_info.imageType = VK_IMAGE_TYPE_2D;
  image_info.format = format;
  image_info.extent = {width, height, 1};
  image_info.mipLevels = 1;
  image_info.arrayLayers = 1;
  image_info.samples = VK_SAMPLE_COUNT_1_BIT;
  image_info.tiling = VK_IMAGE_TILING_OPTIMAL;
  image_info.usage = depth ? VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT
                           : VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  image_info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  check(vkCreateImage(device, &image_info, nullptr, &image_), "vkCreateImage");
  memory_ = bind_device_memory(context, image_);
  VkImageViewCreateInfo view_info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  view_info.image = image_;
  view_info.viewType = VK_IMAGE_VIEW_TYPE_2D;
  view_info.format = format;
  view_info.subresourceRange = {depth ? VkImageAspectFlags(VK_IMAGE_ASPECT_DEPTH_BIT) : VkImageAspectFlags(VK_IMAGE_ASPECT_COLOR_BIT),
                                0, 1, 0, 1};
  check(vkCreateImageView(device, &view_info, nullptr, &view_), "vkCreateImageView");
}

RasterTarget::~RasterTarget() {
  VkDevice device = context_.device();
  vkDestroyImageView(device, view_, nullptr);
  vkDestroyImage(device, image_, nullptr);
  vkFreeMemory(device, memory_, nullptr);
}

size_t RasterTarget::bytes() const { return static_cast<size_t>(width_) * height_ * texel_bytes(format_); }

RasterPipeline::RasterPipeline(Context& context, VkFormat format, const uint32_t* vertex_spirv, size_t vertex_bytes,
                               const uint32_t* fragment_spirv, size_t fragment_bytes, uint32_t buffer_count,
                               uint32_t push_constant_bytes, Primitive primitive)
    : RasterPipeline(context, additive_options(format, primitive), vertex_spirv, vertex_bytes, fragment_spirv,
                     fragment_bytes, buffer_count, push_constant_bytes) {}

RasterPipeline::RasterPipeline(Context& context, const RasterOptions& options, const uint32_t* vertex_spirv,
                               size_t vertex_bytes, const uint32_t* fragment_spirv, size_t fragment_bytes,
                               uint32_t buffer_count, uint32_t push_constant_bytes)
    : context_(context), options_(options), buffer_count_(buffer_count), push_constant_bytes_(push_constant_bytes) {
  if (options.colour_targets < 1 || options.colour_targets > 4)
    throw VulkanError("Vulkan: a raster pipeline draws into 1 to 4 colour targets");
  VkDevice device = context.device();
  const uint32_t colours = options.colour_targets;
  const bool depth = !options.additive;
  // The targets are cleared, drawn, then copied out: their contents end in TRANSFER_SRC layout, and the
  // copy waits for the writes. The depth target is the draw's own (nothing reads it after).
  std::vector<VkAttachmentDescription> attachments(colours + (depth ? 1 : 0));
  std::vector<VkAttachmentReference> references(colours);
  for (uint32_t i = 0; i < attachments.size(); ++i) {
    VkAttachmentDescription& attachment = attachments[i];
    const bool is_depth = i == colours;
    attachment.format = is_depth ? VK_FORMAT_D32_SFLOAT : options.format;
    attachment.samples = VK_SAMPLE_COUNT_1_BIT;
    attachment.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    attachment.storeOp = is_depth ? VK_ATTACHMENT_STORE_OP_DONT_CARE : VK_ATTACHMENT_STORE_OP_STORE;
    attachment.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    attachment.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    attachment.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    attachment.finalLayout = is_depth ? VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL : VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    if (!is_depth) references[i] = {i, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  }
  const VkAttachmentReference depth_reference{colours, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
  VkSubpassDescription subpass{};
  subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  subpass.colorAttachmentCount = colours;
  subpass.pColorAttachments = references.data();
  if (depth) subpass.pDepthStencilAttachment = &depth_reference;
  VkSubpassDependency dependencies[2] = {};
  dependencies[0].srcSubpass = VK_SUBPASS_EXTERNAL;
  dependencies[0].dstSubpass = 0;
  dependencies[0].srcStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT |
                                 VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
  dependencies[0].dstStageMask = VK_PIPELINE_STAGE_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT |
                                 VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT;
  dependencies[0].srcAccessMask =
      VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
  dependencies[0].dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                                  VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
  dependencies[1].srcSubpass = 0;
  dependencies[1].dstSubpass = VK_SUBPASS_EXTERNAL;
  dependencies[1].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  dependencies[1].dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
  dependencies[1].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  dependencies[1].dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
  VkRenderPassCreateInfo pass_info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
  pass_info.attachmentCount = static_cast<uint32_t>(attachments.size());
  pass_info.pAttachments = attachments.data();
  pass_info.subpassCount = 1;
  pass_info.pSubpasses = &subpass;
  pass_info.dependencyCount = 2;
  pass_info.pDependencies = dependencies;
  check(vkCreateRenderPass(device, &pass_info, nullptr, &render_pass_), "vkCreateRenderPass");

  pipeline_layout(device, buffer_count, 0, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                  push_constant_bytes, set_layout_, layout_);

  VkShaderModule vertex = shader_module(device, vertex_spirv, vertex_bytes);
  VkShaderModule fragment = shader_module(device, fragment_spirv, fragment_bytes);
  VkPipelineShaderStageCreateInfo stage_infos[2] = {{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO},
                                                    {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO}};
  stage_infos[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
  stage_infos[0].module = vertex;
  stage_infos[0].pName = "main";
  stage_infos[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
  stage_infos[1].module = fragment;
  stage_infos[1].pName = "main";
  VkPipelineVertexInputStateCreateInfo vertex_input{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  assembly.topology = options.primitive == Primitive::points ? VK_PRIMITIVE_TOPOLOGY_POINT_LIST : VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  viewport.viewportCount = viewport.scissorCount = 1;  // dynamic: one pipeline for targets of any size
  VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  raster.polygonMode = VK_POLYGON_MODE_FILL;
  raster.cullMode = VK_CULL_MODE_NONE;
  raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  raster.lineWidth = 1.0f;
  VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  VkPipelineDepthStencilStateCreateInfo depth_state{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  depth_state.depthTestEnable = depth_state.depthWriteEnable = depth ? VK_TRUE : VK_FALSE;
  depth_state.depthCompareOp = VK_COMPARE_OP_GREATER;
  VkPipelineColorBlendAttachmentState blend{};
  blend.blendEnable = options.additive ? VK_TRUE : VK_FALSE;
  blend.srcColorBlendFactor = blend.dstColorBlendFactor = VK_BLEND_FACTOR_ONE;
  blend.colorBlendOp = VK_BLEND_OP_ADD;
  blend.srcAlphaBlendFactor = blend.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
  blend.alphaBlendOp = VK_BLEND_OP_ADD;
  blend.colorWriteMask = options.format == VK_FORMAT_R32_SFLOAT ? VK_COLOR_COMPONENT_R_BIT
                                                        : VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                                                              VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
  VkPipelineColorBlendStateCreateInfo blending{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  const std::vector<VkPipelineColorBlendAttachmentState> blends(colours, blend);
  blending.attachmentCount = colours;
  blending.pAttachments = blends.data();
  const VkDynamicState dynamic_states[2] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
  VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
  dynamic.dynamicStateCount = 2;
  dynamic.pDynamicStates = dynamic_states;
  VkGraphicsPipelineCreateInfo pipeline_info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  pipeline_info.stageCount = 2;
  pipeline_info.pStages = stage_infos;
  pipeline_info.pVertexInputState = &vertex_input;
  pipeline_info.pInputAssemblyState = &assembly;
  pipeline_info.pViewportState = &viewport;
  pipeline_info.pRasterizationState = &raster;
  pipeline_info.pMultisampleState = &multisample;
  pipeline_info.pColorBlendState = &blending;
  pipeline_info.pDepthStencilState = depth ? &depth_state : nullptr;
  pipeline_info.pDynamicState = &dynamic;
  pipeline_info.layout = layout_;
  pipeline_info.renderPass = render_pass_;
  const VkResult result = vkCreateGraphicsPipelines(device, VK_NULL_HANDLE, 1, &pipeline_info, nullptr, &pipeline_);
  vkDestroyShaderModule(device, vertex, nullptr);
  vkDestroyShaderModule(device, fragment, nullptr);
  check(result, "vkCreateGraphicsPipelines");

  pool_ = descriptor_pool(device, buffer_count, 0);
  timestamps_ = std::make_unique<TimestampPair>(context);
}

RasterPipeline::~RasterPipeline() {
  VkDevice device = context_.device();
  timestamps_.reset();
  vkDestroyDescriptorPool(device, pool_, nullptr);
  vkDestroyPipeline(device, pipeline_, nullptr);
  vkDestroyPipelineLayout(device, layout_, nullptr);
  vkDestroyDescriptorSetLayout(device, set_layout_, nullptr);
  vkDestroyRenderPass(device, render_pass_, nullptr);
}

double RasterPipeline::draw(RasterTarget& target, const std::vector<const Buffer*>& buffers, const void* push_constants,
                            uint32_t vertices, uint32_t instances, Buffer& into, size_t into_offset) {
  return draw({&target}, nullptr, buffers, push_constants, 0, vertices, instances, {Copy{&into, into_offset}});
}

double RasterPipeline::draw(const std::vector<RasterTarget*>& targets, RasterTarget* depth,
                            const std::vector<const Buffer*>& buffers, const void* push_constants, uint32_t first_vertex,
                            uint32_t vertices, uint32_t instances, const std::vector<Copy>& copies) {
  if (buffers.size() != buffer_count_) throw VulkanError("Vulkan: wrong number of buffers for the raster pipeline");
  if (targets.size() != options_.colour_targets || copies.size() != targets.size())
    throw VulkanError("Vulkan: the raster pipeline draws into " + std::to_string(options_.colour_targets) +
                      " targets, each copied out");
  const uint32_t width = targets[0]->width(), height = targets[0]->height();
  for (size_t i = 0; i < targets.size(); ++i) {
    if (targets[i]->format() != options_.format) throw VulkanError("Vulkan: the raster target's format is not the pipeline's");
    if (targets[i]->width() != width || targets[i]->height() != height)
      throw VulkanError("Vulkan: the raster targets differ in size");
    if (!copies[i].into || copies[i].into->size() < copies[i].offset + targets[i]->bytes())
      throw VulkanError("Vulkan: the buffer is smaller than the raster target");
  }
  const bool depth_test = !options_.additive;
  if (depth_test != (depth != nullptr) ||
      (depth && (depth->format() != VK_FORMAT_D32_SFLOAT || depth->width() != width || depth->height() != height)))
    throw VulkanError("Vulkan: a depth-tested draw takes a D32F depth target of its targets' size (an additive one none)");
  VkDevice device = context_.device();
  std::vector<VkImageView> views;
  for (RasterTarget* target : targets) views.push_back(target->view());
  if (depth) views.push_back(depth->view());
  VkFramebufferCreateInfo framebuffer_info{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
  framebuffer_info.renderPass = render_pass_;
  framebuffer_info.attachmentCount = static_cast<uint32_t>(views.size());
  framebuffer_info.pAttachments = views.data();
  framebuffer_info.width = width;
  framebuffer_info.height = height;
  framebuffer_info.layers = 1;
  VkFramebuffer framebuffer;
  check(vkCreateFramebuffer(device, &framebuffer_info, nullptr, &framebuffer), "vkCreateFramebuffer");
  VkDescriptorSet set = storage_set(device, pool_, set_layout_, buffers);
  context_.submit([&](VkCommandBuffer commands) {
    timestamps_->begin(commands);
    std::vector<VkClearValue> clears(views.size());
    for (size_t i = 0; i < targets.size(); ++i)
      for (int c = 0; c < 4; ++c) clears[i].color.float32[c] = options_.clear[c];
    if (depth) clears.back().depthStencil = {0.0f, 0};  // reversed depth: 0 is the farthest
    VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    begin.renderPass = render_pass_;
    begin.framebuffer = framebuffer;
    begin.renderArea = {{0, 0}, {width, height}};
    begin.clearValueCount = static_cast<uint32_t>(clears.size());
    begin.pClearValues = clears.data();
    vkCmdBeginRenderPass(commands, &begin, VK_SUBPASS_CONTENTS_INLINE);
    vkCmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_);
    vkCmdBindDescriptorSets(commands, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_, 0, 1, &set, 0, nullptr);
    if (push_constant_bytes_)
      vkCmdPushConstants(commands, layout_, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                         push_constant_bytes_, push_constants);
    const VkViewport viewport{0.0f, 0.0f, float(width), float(height), 0.0f, 1.0f};
    const VkRect2D scissor{{0, 0}, {width, height}};
    vkCmdSetViewport(commands, 0, 1, &viewport);
    vkCmdSetScissor(commands, 0, 1, &scissor);
    if (vertices > 0 && instances > 0) vkCmdDraw(commands, vertices, instances, first_vertex, 0);
    vkCmdEndRenderPass(commands);
    for (size_t i = 0; i < targets.size(); ++i) {
      VkBufferImageCopy region{};
      region.bufferOffset = copies[i].offset;
      region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
      region.imageExtent = {width, height, 1};
      vkCmdCopyImageToBuffer(commands, targets[i]->image(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, copies[i].into->handle(),
                             1, &region);
    }
    // What follows (a compute pass in its own submission) reads the copy.
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
    vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_VERTEX_SHADER_BIT |
                             VK_PIPELINE_STAGE_TRANSFER_BIT,
                         0, 1, &barrier, 0, nullptr, 0, nullptr);
    timestamps_->end(commands);
  });
  const double milliseconds = timestamps_->milliseconds();
  vkFreeDescriptorSets(device, pool_, 1, &set);
  vkDestroyFramebuffer(device, framebuffer, nullptr);
  return milliseconds;
}

}  // namespace causticbench::gpu
