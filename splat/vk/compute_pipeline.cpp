#include "splat/vk/compute_pipeline.h"

#include <vector>

namespace uf::splat::vk {

Expected<std::unique_ptr<ComputePipeline>> ComputePipeline::Create(const Context& context,
                                                                   std::span<const std::uint32_t> spirv,
                                                                   std::uint32_t bindings,
                                                                   std::uint32_t push_bytes,
                                                                   const std::string& name) {
  std::unique_ptr<ComputePipeline> p(new ComputePipeline());
  p->device_ = context.device();
  p->bindings_ = bindings;
  p->push_bytes_ = push_bytes;
  p->name_ = name;
  auto fail = [&](VkResult result) {
    return Status::Error("Vulkan: cannot create the compute pipeline '" + name + "': " + ResultName(result));
  };

  std::vector<VkDescriptorSetLayoutBinding> layout_bindings(bindings);
  for (std::uint32_t i = 0; i < bindings; ++i)
    layout_bindings[i] = {i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
  VkDescriptorSetLayoutCreateInfo set_info{};
  set_info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
  set_info.bindingCount = bindings;
  set_info.pBindings = layout_bindings.data();
  if (VkResult r = vkCreateDescriptorSetLayout(p->device_, &set_info, nullptr, &p->set_layout_);
      r != VK_SUCCESS)
    return fail(r);

  const VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes};
  VkPipelineLayoutCreateInfo layout_info{};
  layout_info.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
  layout_info.setLayoutCount = 1;
  layout_info.pSetLayouts = &p->set_layout_;
  layout_info.pushConstantRangeCount = push_bytes ? 1 : 0;
  layout_info.pPushConstantRanges = &push;
  if (VkResult r = vkCreatePipelineLayout(p->device_, &layout_info, nullptr, &p->layout_); r != VK_SUCCESS)
    return fail(r);

  VkShaderModuleCreateInfo module_info{};

  module_info.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
  module_info.codeSize = spirv.size_bytes();
  module_info.pCode = spirv.data();
  VkShaderModule module = VK_NULL_HANDLE;
  if (VkResult r = vkCreateShaderModule(p->device_, &module_info, nullptr, &module); r != VK_SUCCESS)
    return fail(r);
  VkComputePipelineCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO;
  info.stage = {};
  info.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = module;
  info.stage.pName = "main";
  info.layout = p->layout_;
  const VkResult r = vkCreateComputePipelines(p->device_, VK_NULL_HANDLE, 1, &info, nullptr, &p->pipeline_);
  vkDestroyShaderModule(p->device_, module, nullptr);
  if (r != VK_SUCCESS) return fail(r);
  return p;
}

ComputePipeline::~ComputePipeline() {
  if (pipeline_) vkDestroyPipeline(device_, pipeline_, nullptr);
  if (layout_) vkDestroyPipelineLayout(device_, layout_, nullptr);
  if (set_layout_) vkDestroyDescriptorSetLayout(device_, set_layout_, nullptr);
}

}  // namespace uf::splat::vk
