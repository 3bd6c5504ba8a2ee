#include "splat/vk/buffer.h"

#include <algorithm>
#include <cassert>
#include <cstring>
#include <utility>

namespace uf::splat::vk {

Expected<Buffer> Buffer::Create(const Context& context, std::size_t bytes, const std::string& name) {
  const std::size_t limit = context.limits().maxStorageBufferRange;
  if (bytes > limit)
    return Status::Error("splat buffer '" + name + "' of " + std::to_string(bytes) +
                         " bytes exceeds the device's " + "maxStorageBufferRange of " +
                         std::to_string(limit) + " bytes (" + context.device_name() + ")");
  Buffer b;
  b.device_ = context.device();
  b.bytes_ = std::max<std::size_t>(bytes, 16);  // never an empty buffer
  VkBufferCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
  info.size = b.bytes_;
  info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
               VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VkResult result = vkCreateBuffer(b.device_, &info, nullptr, &b.buffer_);
  if (result != VK_SUCCESS) return Status::Error("splat buffer '" + name + "': " + ResultName(result));

  VkMemoryRequirements requirements;
  vkGetBufferMemoryRequirements(b.device_, b.buffer_, &requirements);
  Expected<std::uint32_t> type = context.FindMemoryType(
      requirements.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
      VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  if (!type.ok()) return type.status();
  VkMemoryAllocateInfo allocate{};
  allocate.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
  allocate.allocationSize = requirements.size;
  allocate.memoryTypeIndex = *type;
  result = vkAllocateMemory(b.device_, &allocate, nullptr, &b.memory_);
  if (result != VK_SUCCESS)
    return Status::Error("splat buffer '" + name + "' of " + std::to_string(bytes) +
                         " bytes: " + ResultName(result));
  vkBindBufferMemory(b.device_, b.buffer_, b.memory_, 0);
  result = vkMapMemory(b.device_, b.memory_, 0, VK_WHOLE_SIZE, 0, &b.mapped_);
  if (result != VK_SUCCESS)
    return Status::Error("splat buffer '" + name + "': cannot map: " + ResultName(result));
  return b;
}

void Buffer::Release() {
  if (!device_) return;
  if (memory_) vkFreeMemory(device_, memory_, nullptr);  // unmaps implicitly
  if (buffer_) vkDestroyBuffer(device_, buffer_, nullptr);
  device_ = VK_NULL_HANDLE;
  buffer_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
  mapped_ = nullptr;
  bytes_ = 0;
}

Buffer::~Buffer() { Release(); }

Buffer::Buffer(Buffer&& other) noexcept { *this = std::move(other); }

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    Release();
    std::swap(device_, other.device_);
    std::swap(buffer_, other.buffer_);
    std::swap(memory_, other.memory_);
    std::swap(mapped_, other.mapped_);
    std::swap(bytes_, other.bytes_);
  }
  return *this;
}

void Buffer::Upload(const void* source, std::size_t bytes, std::size_t offset) {
  assert(offset + bytes <= bytes_);
  if (bytes) std::memcpy(static_cast<char*>(mapped_) + offset, source, bytes);
}

void Buffer::Download(void* destination, std::size_t bytes, std::size_t offset) const {
  assert(offset + bytes <= bytes_);
  if (bytes) std::memcpy(destination, static_cast<const char*>(mapped_) + offset, bytes);
}

Status EnsureBuffer(const Context& context, Buffer& buffer, std::size_t bytes, const std::string& name,
                    bool* grown) {
  if (grown) *grown = false;
  if (buffer.handle() && buffer.size() >= bytes) return Status();
  Expected<Buffer> created = Buffer::Create(context, bytes, name);
  if (!created.ok()) return created.status();
  buffer = std::move(created.value());
  if (grown) *grown = true;
  return Status();
}

}  // namespace uf::splat::vk
