// Headless Vulkan context: instance, one physical device, one logical device
// and a graphics queue. No window-system extensions are used, so it works on
// a display-less server (Mesa lavapipe) as well as on a real GPU.
//
// Thread safety: a Context and everything created from it must be used from
// one thread at a time (they share one VkQueue). Distinct Contexts are
// independent.
#pragma once

#include "vk/error.hpp"

#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace cmr::vk {

struct DeviceInfo {
  std::string name;                                           // VkPhysicalDeviceProperties::deviceName
  VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;  // CPU for lavapipe, DISCRETE_GPU, ...
  bool float64 = false;                                       // shaderFloat64 supported
  bool fragment_stores = false;                               // fragmentStoresAndAtomics supported (enabled when so)
  uint32_t max_image_dimension_2d = 0;                        // largest width/height of a 2D image
};

// Lists the physical devices the Vulkan loader exposes, in loader order.
// Honours the loader's environment (VK_DRIVER_FILES, VK_ICD_FILENAMES, ...).
// Errors: loader_missing, no_device (no driver or zero devices),
//         out_of_memory, other.
Result<std::vector<DeviceInfo>> enumerate_devices();

struct ContextOptions {
  // Empty: the first device (loader order) that has the needed features.
  // Otherwise a case-insensitive substring of the device name ("llvmpipe",
  // "nvidia"); the first matching device with the needed features is used.
  // A name that matches nothing is an error, never a silent fallback.
  std::string device_name;
  // Whether a device without shaderFloat64 is rejected. shaderFloat64 is
  // enabled whenever the device supports it, independent of this flag, so
  // device().float64 tells whether fp64 shaders may be used.
  bool require_float64 = true;
  // Instance extensions to enable (e.g. what glfwGetRequiredInstanceExtensions
  // lists for a window). Empty: a headless instance with no extensions.
  std::vector<std::string> instance_extensions;
  // For presentation: called once with the new instance, returns a surface
  // the Context then owns (destroyed after the device, before the instance).
  // A device qualifies only if one queue family has graphics and presents to
  // this surface and it offers VK_KHR_swapchain, which is then enabled.
  std::function<Result<VkSurfaceKHR>(VkInstance)> make_surface;
};

// Whether `data` starts with the VkPipelineCacheHeaderVersionOne of this
// device and driver (header size at least 32 and within the data, version
// one, vendor and device ids, pipelineCacheUUID). Only such data is handed
// to vkCreatePipelineCache; a driver that changed (a new UUID) or a foreign
// or truncated file fails here.
bool pipeline_cache_matches(std::span<const std::byte> data, uint32_t vendor_id, uint32_t device_id,
                            const uint8_t (&uuid)[VK_UUID_SIZE]);

namespace detail {
struct DeviceState;  // Vulkan handles; shared with objects made from a Context
}

class Context {
 public:
  // Creates the instance (Vulkan 1.1) and a device with one graphics queue.
  // Errors: loader_missing; no_device (no driver / no physical device);
  //   device_not_found (options.device_name matches nothing; the message
  //   lists the available devices); missing_feature (matching devices lack
  //   shaderFloat64 while required, Vulkan 1.1 or a graphics queue, or with
  //   make_surface a presenting queue or VK_KHR_swapchain; also an instance
  //   extension the loader lacks); errors of make_surface as it returns them;
  //   out_of_memory; device_lost; other.
  static Result<Context> create(const ContextOptions& options = {});

  Context(Context&&) noexcept;
  Context& operator=(Context&&) noexcept;
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
  // Objects created from this Context (ComputePipeline, FragmentPipeline) keep the device
  // alive, so they may outlive it. Destroy them all before exit() starts:
  // NVIDIA's driver (580, seen on an H200) tears itself down in an exit
  // handler registered when it loads, so a Context or pipeline that a static
  // destructor destroys afterwards calls into unmapped code. Whatever lives
  // for the whole run belongs in a static that is never destroyed.
  ~Context();

  // The chosen device. Must not be called on a moved-from Context.
  const DeviceInfo& device() const;

  // Raw handles, for code that records its own Vulkan work on this device.
  VkInstance instance() const;
  VkPhysicalDevice physical_device() const;
  VkDevice device_handle() const;
  VkQueue queue() const;
  uint32_t queue_family_index() const;
  // The surface made by ContextOptions::make_surface, else VK_NULL_HANDLE.
  VkSurfaceKHR surface() const;

  // The VkPipelineCache every pipeline made from this Context goes through:
  // created empty; load_pipeline_cache replaces it with `data` (what
  // pipeline_cache_data gave in an earlier run, e.g. a file under the user's
  // cache directory) when pipeline_cache_matches says it is this device's
  // and driver's. Errors: other (the header does not match, or empty data
  // is not passed and it is shorter than a header: the cache is then empty
  // and usable), out_of_memory, device_lost.
  Result<void> load_pipeline_cache(std::span<const std::byte> data);
  // The cache's contents now (empty when the driver cannot say).
  std::vector<std::byte> pipeline_cache_data() const;

  // Internal: shared ownership of the Vulkan handles.
  const std::shared_ptr<detail::DeviceState>& state() const { return state_; }

 private:
  explicit Context(std::shared_ptr<detail::DeviceState> state);
  std::shared_ptr<detail::DeviceState> state_;
};

}  // namespace cmr::vk
