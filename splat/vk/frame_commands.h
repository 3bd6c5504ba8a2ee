// One command buffer per frame: every dispatch of a frame is recorded into it (lavapipe charges 20-50 us per
// submission-level round trip, so a frame is one submit), with a global memory barrier between dependent
// dispatches and optional timestamps between stages. Descriptor sets come from a pool reset every frame.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <initializer_list>
#include <memory>
#include <vector>

#include "odometry/types/status.h"
#include "splat/vk/buffer.h"
#include "splat/vk/compute_pipeline.h"
#include "splat/vk/context.h"

namespace uf::splat::vk {

class FrameCommands {
 public:
  // max_dispatches: descriptor sets available per frame (each binding at most 12 buffers).
  static Expected<std::unique_ptr<FrameCommands>> Create(const Context& context, std::uint32_t max_dispatches,
                                                         std::uint32_t max_timestamps);
  ~FrameCommands();
  FrameCommands(const FrameCommands&) = delete;
  FrameCommands& operator=(const FrameCommands&) = delete;

  Status Begin();
  // Binds `buffers` to bindings 0..n-1 of the pipeline (whole buffers), pushes `push` and dispatches.
  void Dispatch(const ComputePipeline& pipeline, std::initializer_list<const Buffer*> buffers,
                const void* push, std::uint32_t groups_x, std::uint32_t groups_y = 1);
  void Fill(const Buffer& buffer, std::uint32_t value);
  // Makes all earlier shader and transfer writes visible to later shader and transfer reads and writes.
  void Barrier();
  // Records a timestamp (no-op when the queue has none); TimestampsMs gives the differences after a frame.
  void Timestamp();
  // Ends the buffer (with a barrier to host reads), submits it and waits for completion.
  Status SubmitAndWait();
  std::vector<double> IntervalsMs() const;  // between consecutive timestamps of the last frame

 private:
  explicit FrameCommands(const Context& context) : context_(context) {}
  const Context& context_;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkCommandBuffer commands_ = VK_NULL_HANDLE;
  VkDescriptorPool descriptor_pool_ = VK_NULL_HANDLE;
  VkQueryPool queries_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  std::uint32_t max_timestamps_ = 0, timestamps_ = 0;
  Status error_;  // the first recording error of the frame, returned by SubmitAndWait
};

}  // namespace uf::splat::vk
