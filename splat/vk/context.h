// Vulkan context of the splat compute renderer: the instance, the chosen physical device (a named one, else
// the first discrete or integrated GPU, else the CPU device, Mesa's lavapipe), the logical device with one
// compute queue and its command pool, and the choice of memory types. Internal to splat/ (includes vulkan.h).
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "odometry/types/status.h"

namespace uf::splat::vk {

struct ContextOptions {
  // Which device: "" picks automatically (discrete GPU, then integrated GPU, then any other GPU, then the CPU
  // device); a decimal number is an index into ListDevices(); anything else is a case-insensitive
  // substring of the device name ("llvmpipe", "nvidia").
  std::string device;
};

struct DeviceInfo {
  std::string name;  // e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string type;  // "discrete GPU", "integrated GPU", "virtual GPU", "CPU", "other"
  std::uint32_t api_version = 0;
};

// The Vulkan devices present. Error (with what to install) when no Vulkan driver answers at all.
Expected<std::vector<DeviceInfo>> ListDevices();

// The index of the device `wanted` names (ContextOptions::device, not empty): a decimal index, else the first
// device whose name contains it (case-insensitive). The error lists the devices present (or, without any,
// says what to install).
Expected<std::size_t> FindDevice(const std::vector<DeviceInfo>& devices, const std::string& wanted);

class Context {
 public:
  static Expected<std::unique_ptr<Context>> Create(const ContextOptions& options);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  VkDevice device() const { return device_; }
  VkPhysicalDevice physical_device() const { return physical_device_; }
  VkQueue queue() const { return queue_; }
  std::uint32_t queue_family() const { return queue_family_; }
  const std::string& device_name() const { return info_.name; }
  bool is_cpu() const { return info_.type == "CPU"; }
  const VkPhysicalDeviceLimits& limits() const { return properties_.limits; }
  bool timestamps_supported() const { return timestamp_valid_bits_ > 0; }

  // A memory type allowed by type_bits with all `required` flags, preferring one that also has `preferred`.
  Expected<std::uint32_t> FindMemoryType(std::uint32_t type_bits, VkMemoryPropertyFlags required,
                                         VkMemoryPropertyFlags preferred) const;

 private:
  Context() = default;
  VkInstance instance_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_device_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  std::uint32_t queue_family_ = 0;
  std::uint32_t timestamp_valid_bits_ = 0;
  DeviceInfo info_;
  VkPhysicalDeviceProperties properties_{};
  VkPhysicalDeviceMemoryProperties memory_{};
};

// "VK_ERROR_OUT_OF_DEVICE_MEMORY" etc., for error messages.
std::string ResultName(VkResult result);

}  // namespace uf::splat::vk
