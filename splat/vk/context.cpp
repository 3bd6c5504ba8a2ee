#include "splat/vk/context.h"

#include <algorithm>
#include <cctype>
#include <sstream>

namespace uf::splat::vk {

namespace {

constexpr const char* kInstallHint =
    "install mesa-vulkan-drivers for the CPU device (lavapipe), or the Vulkan driver of your GPU";

std::string TypeName(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return "CPU";
    default:
      return "other";
  }
}

// Automatic choice: lower is better.
int TypeRank(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return 3;
    default:
      return 4;
  }
}

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

Expected<VkInstance> CreateInstance() {
  VkApplicationInfo app{};
  app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  app.pApplicationName = "ultrafusion";
  app.apiVersion = VK_API_VERSION_1_2;
  VkInstanceCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
  info.pApplicationInfo = &app;
  VkInstance instance = VK_NULL_HANDLE;
  const VkResult result = vkCreateInstance(&info, nullptr, &instance);
  if (result != VK_SUCCESS)
    return Status::Error("Vulkan: cannot create an instance (" + ResultName(result) +
                         "): no Vulkan driver; " + kInstallHint);
  return instance;
}

std::vector<VkPhysicalDevice> PhysicalDevices(VkInstance instance) {
  std::uint32_t count = 0;
  vkEnumeratePhysicalDevices(instance, &count, nullptr);
  std::vector<VkPhysicalDevice> devices(count);
  vkEnumeratePhysicalDevices(instance, &count, devices.data());
  devices.resize(count);
  return devices;
}

// Why the renderer cannot use this device ("" if it can): Vulkan 1.2, a compute queue, subgroup
// arithmetic and ballot in compute shaders.
std::string Unsupported(VkPhysicalDevice device, std::uint32_t* queue_family) {
  VkPhysicalDeviceSubgroupProperties subgroup{};
  subgroup.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES;
  VkPhysicalDeviceProperties2 properties{};
  properties.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
  properties.pNext = &subgroup;
  vkGetPhysicalDeviceProperties2(device, &properties);
  if (properties.properties.apiVersion < VK_API_VERSION_1_2) return "needs Vulkan 1.2";
  const VkSubgroupFeatureFlags needed =
      VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_ARITHMETIC_BIT | VK_SUBGROUP_FEATURE_BALLOT_BIT;
  if (!(subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) ||
      (subgroup.supportedOperations & needed) != needed)
    return "no subgroup arithmetic/ballot in compute shaders";
  std::uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
  for (std::uint32_t i = 0; i < count; ++i)
    if (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
      *queue_family = i;
      return "";
    }
  return "no compute queue";
}

std::string Listing(const std::vector<DeviceInfo>& devices) {
  std::ostringstream s;
  for (std::size_t i = 0; i < devices.size(); ++i)
    s << (i ? ", " : "") << i << ": " << devices[i].name << " (" << devices[i].type << ")";
  return devices.empty() ? "none" : s.str();
}

DeviceInfo Describe(VkPhysicalDevice device) {
  VkPhysicalDeviceProperties p;
  vkGetPhysicalDeviceProperties(device, &p);
  return {p.deviceName, TypeName(p.deviceType), p.apiVersion};
}

}  // namespace

std::string ResultName(VkResult result) {
  switch (result) {
    case VK_ERROR_OUT_OF_HOST_MEMORY:
      return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY:
      return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED:
      return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST:
      return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_INCOMPATIBLE_DRIVER:
      return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_LAYER_NOT_PRESENT:
      return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT:
      return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT:
      return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_TIMEOUT:
      return "VK_TIMEOUT";
    default:
      return "VkResult " + std::to_string(static_cast<int>(result));
  }
}

Expected<std::vector<DeviceInfo>> ListDevices() {
  Expected<VkInstance> instance = CreateInstance();
  if (!instance.ok()) return instance.status();
  std::vector<DeviceInfo> devices;
  for (VkPhysicalDevice device : PhysicalDevices(*instance)) devices.push_back(Describe(device));
  vkDestroyInstance(*instance, nullptr);
  return devices;
}

Expected<std::size_t> FindDevice(const std::vector<DeviceInfo>& devices, const std::string& wanted) {
  if (devices.empty()) return Status::Error("Vulkan: no device found; " + std::string(kInstallHint));
  const bool is_index =
      std::all_of(wanted.begin(), wanted.end(), [](unsigned char c) { return std::isdigit(c); });
  for (std::size_t i = 0; i < devices.size(); ++i)
    if (is_index ? std::to_string(i) == wanted
                 : Lower(devices[i].name).find(Lower(wanted)) != std::string::npos)
      return i;
  return Status::Error("Vulkan: no device matches '" + wanted + "'; devices present: " + Listing(devices));
}

Expected<std::unique_ptr<Context>> Context::Create(const ContextOptions& options) {
  Expected<VkInstance> instance = CreateInstance();
  if (!instance.ok()) return instance.status();
  std::unique_ptr<Context> context(new Context());
  context->instance_ = *instance;

  // Pick the physical device: by index or name when asked, else the best type that the renderer can use.
  const std::vector<VkPhysicalDevice> physical = PhysicalDevices(context->instance_);
  std::vector<DeviceInfo> infos;
  for (VkPhysicalDevice device : physical) infos.push_back(Describe(device));
  if (physical.empty()) return Status::Error("Vulkan: no device found; " + std::string(kInstallHint));
  int chosen = -1;
  if (!options.device.empty()) {
    Expected<std::size_t> named = FindDevice(infos, options.device);
    if (!named.ok()) return named.status();
    chosen = static_cast<int>(*named);
    const std::string why = Unsupported(physical[chosen], &context->queue_family_);
    if (!why.empty())
      return Status::Error("Vulkan: device '" + infos[chosen].name + "' cannot be used: " + why);
  } else {
    int best_rank = 1 << 30;
    std::uint32_t family = 0;
    for (std::size_t i = 0; i < physical.size(); ++i) {
      VkPhysicalDeviceProperties p;
      vkGetPhysicalDeviceProperties(physical[i], &p);
      if (TypeRank(p.deviceType) < best_rank && Unsupported(physical[i], &family).empty()) {
        best_rank = TypeRank(p.deviceType);
        chosen = static_cast<int>(i);
        context->queue_family_ = family;
      }
    }
    if (chosen < 0)
      return Status::Error("Vulkan: none of the devices supports Vulkan 1.2 compute with subgroups (" +
                           Listing(infos) + "); " + kInstallHint);
  }
  context->physical_device_ = physical[chosen];
  context->info_ = infos[chosen];
  vkGetPhysicalDeviceProperties(context->physical_device_, &context->properties_);
  vkGetPhysicalDeviceMemoryProperties(context->physical_device_, &context->memory_);
  std::uint32_t family_count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(context->physical_device_, &family_count, nullptr);
  std::vector<VkQueueFamilyProperties> families(family_count);
  vkGetPhysicalDeviceQueueFamilyProperties(context->physical_device_, &family_count, families.data());
  context->timestamp_valid_bits_ = families[context->queue_family_].timestampValidBits;

  // Logical device with one compute queue.
  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queue_info{};
  queue_info.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
  queue_info.queueFamilyIndex = context->queue_family_;
  queue_info.queueCount = 1;
  queue_info.pQueuePriorities = &priority;
  VkDeviceCreateInfo device_info{};
  device_info.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
  device_info.queueCreateInfoCount = 1;
  device_info.pQueueCreateInfos = &queue_info;
  const VkResult result = vkCreateDevice(context->physical_device_, &device_info, nullptr, &context->device_);
  if (result != VK_SUCCESS)
    return Status::Error("Vulkan: cannot create a device on '" + context->info_.name +
                         "': " + ResultName(result));
  vkGetDeviceQueue(context->device_, context->queue_family_, 0, &context->queue_);
  return context;
}

Context::~Context() {
  if (device_) vkDestroyDevice(device_, nullptr);
  if (instance_) vkDestroyInstance(instance_, nullptr);
}

Expected<std::uint32_t> Context::FindMemoryType(std::uint32_t type_bits, VkMemoryPropertyFlags required,
                                                VkMemoryPropertyFlags preferred) const {
  for (const VkMemoryPropertyFlags flags : {required | preferred, required})
    for (std::uint32_t i = 0; i < memory_.memoryTypeCount; ++i)
      if ((type_bits & (1u << i)) && (memory_.memoryTypes[i].propertyFlags & flags) == flags) return i;
  return Status::Error("Vulkan: device '" + info_.name + "' has no host-visible memory type for buffers");
}

}  // namespace uf::splat::vk
