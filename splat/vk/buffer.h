// A Vulkan storage buffer in host-visible, host-coherent memory (device-local too where the device has such
// memory, as lavapipe and resizable-BAR GPUs do), persistently mapped: uploads and downloads are memcpy.
// Sizes are checked against maxStorageBufferRange (128 MiB on lavapipe), since each buffer is bound whole.
#pragma once

#include <vulkan/vulkan.h>

#include <cstddef>
#include <string>

#include "odometry/types/status.h"
#include "splat/vk/context.h"

namespace uf::splat::vk {

class Buffer {
 public:
  Buffer() = default;
  // `name` appears in errors ("splat buffer 'keys' of 200000000 bytes exceeds ...").
  static Expected<Buffer> Create(const Context& context, std::size_t bytes, const std::string& name);
  ~Buffer();
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return buffer_; }
  std::size_t size() const { return bytes_; }
  void* data() const { return mapped_; }
  void Upload(const void* source, std::size_t bytes, std::size_t offset = 0);
  void Download(void* destination, std::size_t bytes, std::size_t offset = 0) const;

 private:
  void Release();
  VkDevice device_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  void* mapped_ = nullptr;
  std::size_t bytes_ = 0;
};

// Makes `buffer` hold at least `bytes` (re-creating it, contents lost, when too small). Returns whether it
// was re-created through `grown` when given.
Status EnsureBuffer(const Context& context, Buffer& buffer, std::size_t bytes, const std::string& name,
                    bool* grown = nullptr);

}  // namespace uf::splat::vk
