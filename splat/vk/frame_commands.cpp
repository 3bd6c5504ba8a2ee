#include "splat/vk/frame_commands.h"

#include <cassert>

namespace uf::splat::vk {

namespace {
constexpr std::uint32_t kMaxBindings = 12;
}

Expected<std::unique_ptr<FrameCommands>> FrameCommands::Create(const Context& context,
                                                               std::uint32_t max_dispatches,
                                                               std::uint32_t max_timestamps) {
  std::unique_ptr<FrameCommands> f(new FrameCommands(context));
  const VkDevice device = context.device();
  auto fail = [](const char* what, VkResult r) {
    return Status::Error(std::string("Vulkan: cannot create the ") + what + ": " + ResultName(r));
  };
  VkCommandPoolCreateInfo pool_info{};
  pool_info.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
  pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool_info.queueFamilyIndex = context.queue_family();
  if (VkResult r = vkCreateCommandPool(device, &pool_info, nullptr, &f->pool_); r != VK_SUCCESS)
    return fail("command pool", r);
  VkCommandBufferAllocateInfo allocate{};
  allocate.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
  allocate.commandPool = f->pool_;
  allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  allocate.commandBufferCount = 1;
  if (VkResult r = vkAllocateCommandBuffers(device, &allocate, &f->commands_); r != VK_SUCCESS)
    return fail("command buffer", r);

  const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, max_dispatches * kMaxBindings};
  VkDescriptorPoolCreateInfo descriptor_info{};
  descriptor_info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
  descriptor_info.maxSets = max_dispatches;
  descriptor_info.poolSizeCount = 1;
  descriptor_info.pPoolSizes = &size;
  if (VkResult r = vkCreateDescriptorPool(device, &descriptor_info, nullptr, &f->descriptor_pool_);
      r != VK_SUCCESS)
    return fail("descriptor pool", r);

  if (context.timestamps_supported() && max_timestamps > 0) {
    VkQueryPoolCreateInfo query_info{};
    query_info.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
    query_info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    query_info.queryCount = max_timestamps;
    if (VkResult r = vkCreateQueryPool(device, &query_info, nullptr, &f->queries_); r != VK_SUCCESS)
      return fail("timestamp query pool", r);
    f->max_timestamps_ = max_timestamps;
  }
  VkFenceCreateInfo fence_info{};
  fence_info.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
  if (VkResult r = vkCreateFence(device, &fence_info, nullptr, &f->fence_); r != VK_SUCCESS)
    return fail("fence", r);
  return f;
}

FrameCommands::~FrameCommands() {
  const VkDevice device = context_.device();
  if (fence_) vkDestroyFence(device, fence_, nullptr);
  if (queries_) vkDestroyQueryPool(device, queries_, nullptr);
  if (descriptor_pool_) vkDestroyDescriptorPool(device, descriptor_pool_, nullptr);
  if (pool_) vkDestroyCommandPool(device, pool_, nullptr);
}

Status FrameCommands::Begin() {
  error_ = Status();
  timestamps_ = 0;
  vkResetDescriptorPool(context_.device(), descriptor_pool_, 0);
  vkResetCommandBuffer(commands_, 0);
  VkCommandBufferBeginInfo begin{};
  begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  if (VkResult r = vkBeginCommandBuffer(commands_, &begin); r != VK_SUCCESS)
    return Status::Error("Vulkan: cannot begin the frame's command buffer: " + ResultName(r));
  if (queries_) vkCmdResetQueryPool(commands_, queries_, 0, max_timestamps_);
  return Status();
}

void FrameCommands::Dispatch(const ComputePipeline& pipeline, std::initializer_list<const Buffer*> buffers,
                             const void* push, std::uint32_t groups_x, std::uint32_t groups_y) {
  assert(buffers.size() == pipeline.bindings() && buffers.size() <= kMaxBindings);
  VkDescriptorSetLayout layout = pipeline.set_layout();
  VkDescriptorSetAllocateInfo allocate{};
  allocate.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
  allocate.descriptorPool = descriptor_pool_;
  allocate.descriptorSetCount = 1;
  allocate.pSetLayouts = &layout;
  VkDescriptorSet set = VK_NULL_HANDLE;
  if (VkResult r = vkAllocateDescriptorSets(context_.device(), &allocate, &set); r != VK_SUCCESS) {
    if (error_.ok())
      error_ =
          Status::Error("Vulkan: out of descriptor sets for '" + pipeline.name() + "': " + ResultName(r));
    return;
  }
  VkDescriptorBufferInfo infos[kMaxBindings];
  VkWriteDescriptorSet writes[kMaxBindings];
  std::uint32_t i = 0;
  for (const Buffer* buffer : buffers) {
    infos[i] = {buffer->handle(), 0, VK_WHOLE_SIZE};
    writes[i] = {};
    writes[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
    writes[i].dstSet = set;
    writes[i].dstBinding = i;
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[i].pBufferInfo = &infos[i];
    ++i;
  }
  vkUpdateDescriptorSets(context_.device(), i, writes, 0, nullptr);
  vkCmdBindPipeline(commands_, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.pipeline());
  vkCmdBindDescriptorSets(commands_, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.layout(), 0, 1, &set, 0,
                          nullptr);
  if (pipeline.push_bytes())
    vkCmdPushConstants(commands_, pipeline.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, pipeline.push_bytes(),
                       push);
  if (groups_x > 0 && groups_y > 0) vkCmdDispatch(commands_, groups_x, groups_y, 1);
}

void FrameCommands::Fill(const Buffer& buffer, std::uint32_t value) {
  vkCmdFillBuffer(commands_, buffer.handle(), 0, VK_WHOLE_SIZE, value);
}

void FrameCommands::Barrier() {
  VkMemoryBarrier barrier{};
  barrier.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                          VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  const VkPipelineStageFlags stages = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
  vkCmdPipelineBarrier(commands_, stages, stages, 0, 1, &barrier, 0, nullptr, 0, nullptr);
}

void FrameCommands::Timestamp() {
  if (!queries_ || timestamps_ >= max_timestamps_) return;
  vkCmdWriteTimestamp(commands_, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, timestamps_++);
}

Status FrameCommands::SubmitAndWait() {
  VkMemoryBarrier barrier{};
  barrier.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(commands_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0, nullptr, 0, nullptr);
  if (VkResult r = vkEndCommandBuffer(commands_); r != VK_SUCCESS)
    return Status::Error("Vulkan: cannot record the frame: " + ResultName(r));
  if (!error_.ok()) return error_;
  VkSubmitInfo submit{};
  submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &commands_;
  vkResetFences(context_.device(), 1, &fence_);
  if (VkResult r = vkQueueSubmit(context_.queue(), 1, &submit, fence_); r != VK_SUCCESS)
    return Status::Error("Vulkan: cannot submit the frame: " + ResultName(r));
  if (VkResult r = vkWaitForFences(context_.device(), 1, &fence_, VK_TRUE, UINT64_MAX); r != VK_SUCCESS)
    return Status::Error("Vulkan: the frame did not finish: " + ResultName(r));
  return Status();
}

std::vector<double> FrameCommands::IntervalsMs() const {
  std::vector<double> intervals;
  if (timestamps_ < 2) return intervals;
  std::vector<std::uint64_t> ticks(timestamps_);
  if (vkGetQueryPoolResults(context_.device(), queries_, 0, timestamps_, ticks.size() * sizeof(std::uint64_t),
                            ticks.data(), sizeof(std::uint64_t), VK_QUERY_RESULT_64_BIT) != VK_SUCCESS)
    return intervals;
  const double ms_per_tick = context_.limits().timestampPeriod * 1e-6;
  for (std::uint32_t i = 1; i < timestamps_; ++i)
    intervals.push_back((ticks[i] - ticks[i - 1]) * ms_per_tick);
  return intervals;
}

}  // namespace uf::splat::vk
