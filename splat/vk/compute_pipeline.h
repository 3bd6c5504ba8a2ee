// A compute pipeline made from embedded SPIR-V: a descriptor-set layout of `bindings` storage buffers
// (bindings 0..n-1, set 0), a push-constant range, the pipeline layout and the pipeline.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "odometry/types/status.h"
#include "splat/vk/context.h"

namespace uf::splat::vk {

class ComputePipeline {
 public:
  static Expected<std::unique_ptr<ComputePipeline>> Create(const Context& context,
                                                           std::span<const std::uint32_t> spirv,
                                                           std::uint32_t bindings, std::uint32_t push_bytes,
                                                           const std::string& name);
  ~ComputePipeline();
  ComputePipeline(const ComputePipeline&) = delete;
  ComputePipeline& operator=(const ComputePipeline&) = delete;

  VkPipeline pipeline() const { return pipeline_; }
  VkPipelineLayout layout() const { return layout_; }
  VkDescriptorSetLayout set_layout() const { return set_layout_; }
  std::uint32_t bindings() const { return bindings_; }
  std::uint32_t push_bytes() const { return push_bytes_; }
  const std::string& name() const { return name_; }

 private:
  ComputePipeline() = default;
  VkDevice device_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  std::uint32_t bindings_ = 0, push_bytes_ = 0;
  std::string name_;
};

}  // namespace uf::splat::vk
