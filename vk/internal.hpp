// Private to cmr_vk: shared device state and VkResult -> Error mapping.
// Not part of the public API; do not include from outside vk/.
#pragma once

#include "vk/context.hpp"
#include "vk/error.hpp"
#include "vk/region_vk.hpp"

#include <vulkan/vulkan_core.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace cmr::vk::detail {

// Owns the instance and device. Held through shared_ptr by Context and by
// every object created from it, so the device is destroyed last.
struct DeviceState {
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkSurfaceKHR surface = VK_NULL_HANDLE;  // presentation only; owned here
  VkQueue queue = VK_NULL_HANDLE;
  uint32_t queue_family_index = 0;
  DeviceInfo info{};
  VkPhysicalDeviceLimits limits{};
  VkPhysicalDeviceMemoryProperties memory{};
  VkPhysicalDeviceProperties properties{};  // vendorID, deviceID, pipelineCacheUUID: the pipeline cache's key
  // Every pipeline made on this device goes through this cache
  // (Context::load_pipeline_cache fills it from an earlier run).
  VkPipelineCache pipeline_cache = VK_NULL_HANDLE;

  DeviceState() = default;
  DeviceState(const DeviceState&) = delete;
  DeviceState& operator=(const DeviceState&) = delete;
  ~DeviceState();
};

// "VK_ERROR_DEVICE_LOST", or "VkResult(-1000)" for codes it does not know.
std::string vk_result_name(VkResult result);

// Classifies a failed VkResult.
Errc errc_from(VkResult result);

// Error for a failed call: "<what> failed: VK_ERROR_...; <hint>".
Error vk_error(VkResult result, std::string_view what);

// Index of a memory type allowed by type_bits that has all `required` flags,
// preferring one that also has all `preferred` flags.
std::optional<uint32_t> find_memory_type(const VkPhysicalDeviceMemoryProperties& memory,
                                         uint32_t type_bits, VkMemoryPropertyFlags required,
                                         VkMemoryPropertyFlags preferred);

// A buffer with its own memory, bound; mapped when host-visible.
struct Buffer {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  std::byte* mapped = nullptr;  // non-null for host-visible buffers
  VkDeviceSize size = 0;
  bool coherent = true;
};

// What ComputePipeline and FragmentPipeline both own: the device, the
// layouts, the pipeline, one descriptor set, one command buffer with its
// pool and fence, and the state of the last submission. Their Impl derives
// from it; this destructor (run after theirs) destroys these handles, and
// theirs must first wait for a pending submission (wait_if_pending) before
// destroying what they own besides.
struct PipelineCore {
  std::shared_ptr<DeviceState> state;  // keeps the device alive until the handles are gone
  VkDevice device = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout pipeline_layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
  VkDescriptorPool descriptor_pool = VK_NULL_HANDLE;
  VkDescriptorSet descriptor_set = VK_NULL_HANDLE;
  VkCommandPool command_pool = VK_NULL_HANDLE;
  VkCommandBuffer command_buffer = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;
  bool pending = false;  // a submission may still be executing
  bool lost = false;     // a submission failed or hung; the pipeline is unusable

  PipelineCore() = default;
  PipelineCore(const PipelineCore&) = delete;
  PipelineCore& operator=(const PipelineCore&) = delete;
  ~PipelineCore();
  // Waits for the device when a submission may still run (returns promptly
  // if the device is lost).
  void wait_if_pending();
  // set_layout and pipeline_layout (create_storage_layout) and the one
  // descriptor set (create_storage_set); `what` names the pipeline.
  Result<void> create_layouts_and_set(uint32_t storage_buffers, VkShaderStageFlags stage,
                                      uint32_t push_constant_bytes, std::string_view what);
};

// A shader module for as long as a pipeline is being made from it.
struct ShaderModule {
  VkDevice device = VK_NULL_HANDLE;
  VkShaderModule handle = VK_NULL_HANDLE;
  ShaderModule() = default;
  ShaderModule(const ShaderModule&) = delete;
  ShaderModule& operator=(const ShaderModule&) = delete;
  ~ShaderModule();
  // Errors: shader_invalid (the driver refused the words), out_of_memory;
  // `what` names the shader.
  Result<void> create(VkDevice dev, std::span<const uint32_t> words, std::string_view what);
};

// Specialisation constant i = values[i] (32 bits each), as a stage takes it:
// info() is null when there are none.
struct Specialization {
  std::vector<VkSpecializationMapEntry> entries;
  VkSpecializationInfo data{};
  explicit Specialization(std::span<const uint32_t> values);
  Specialization(const Specialization&) = delete;
  Specialization& operator=(const Specialization&) = delete;
  const VkSpecializationInfo* info() const { return entries.empty() ? nullptr : &data; }
};

// Creates `out` (which must be empty): `size` bytes of `usage` in memory with
// the `required` flags (preferring `preferred`), bound, and mapped when
// host-visible. On failure nothing half-made is left in `out`; `what` names
// the buffer in the error. The one buffer primitive of ComputePipeline, FragmentPipeline,
// Presenter and the region drawing.
Result<void> create_buffer(const DeviceState& state, Buffer& out, VkDeviceSize size, VkBufferUsageFlags usage,
                           VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred, std::string_view what);

// Destroys the buffer and frees its memory (which unmaps it); `buffer` becomes empty.
void destroy_buffer(VkDevice device, Buffer& buffer);

// One descriptor set of `set_layout` from a new pool of `storage_buffers`
// storage-buffer descriptors (the compute and fragment pipelines, the region drawing). On
// failure `pool` and `set` are left VK_NULL_HANDLE; `what` names the caller.
Result<void> create_storage_set(VkDevice device, VkDescriptorSetLayout set_layout, uint32_t storage_buffers,
                                VkDescriptorPool& pool, VkDescriptorSet& set, std::string_view what);

// ---- Command recording and submission shared by Presenter, the pipelines
// and the region drawing: one place for the barrier and submit boilerplate.

// A layout transition / dependency on the whole colour image.
void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                   VkAccessFlags src_access, VkAccessFlags dst_access, VkPipelineStageFlags src_stage,
                   VkPipelineStageFlags dst_stage);

// A memory dependency on bytes [offset, offset + size) of a buffer.
void buffer_barrier(VkCommandBuffer cmd, VkBuffer buffer, VkDeviceSize offset, VkDeviceSize size,
                    VkAccessFlags src_access, VkAccessFlags dst_access, VkPipelineStageFlags src_stage,
                    VkPipelineStageFlags dst_stage);

// Cheap structural check of a shader's SPIR-V, so that obvious mistakes
// (wrong array, truncated data, another stage, too new SPIR-V) are reported
// as shader_invalid instead of reaching the driver, where invalid SPIR-V is
// undefined behaviour: the magic number, version <= 1.3, whole instructions,
// and an entry point "main" of the stage. Implemented in context.cpp.
enum class ShaderStage { fragment, compute };
Result<void> check_spirv(std::span<const uint32_t> words, ShaderStage stage);

// The core's transient command pool (re-recorded for every submission),
// its one primary command buffer and an unsignalled fence. On failure the
// handles made so far are set (the core's destructor frees them).
Result<void> create_one_shot_commands(PipelineCore& core);

// Submits the core's command buffer, signalling its fence (reset first), and
// waits at most timeout_ns. `pending` is true while the submission may still
// run; `lost` becomes true when the device is lost or the wait times out
// (the command buffer may then still execute: never reuse it). A timeout's
// error message is `timeout_message`.
Result<void> submit_and_wait(PipelineCore& core, uint64_t timeout_ns, const std::string& timeout_message);

// The descriptor set layout of `storage_buffers` storage buffers at
// bindings 0.. for `stage`, and a pipeline layout of that one set and, when
// push_constant_bytes > 0, that many bytes of push constants from offset 0.
// On failure what was made is set (the caller frees it) and the rest stays
// VK_NULL_HANDLE; `what` names the caller.
Result<void> create_storage_layout(VkDevice device, uint32_t storage_buffers, VkShaderStageFlags stage,
                                   uint32_t push_constant_bytes, VkDescriptorSetLayout& set_layout,
                                   VkPipelineLayout& pipeline_layout, std::string_view what);

// Points storage-buffer bindings 0.. of `set` at `buffers`, in order.
void write_storage_set(VkDevice device, VkDescriptorSet set, std::span<const VkDescriptorBufferInfo> buffers);

// vkBeginCommandBuffer for one submission.
Result<void> begin_one_time(VkCommandBuffer cmd);

// Submits one command buffer, signalling `fence`, without semaphores.
Result<void> submit(VkQueue queue, VkCommandBuffer cmd, VkFence fence);

// The region shader's storage buffer (shaders/region_layout.h) for a prepared
// problem: `pixels` are the listed (column, row) pairs (none for the window
// shader, shaders/region_present.glsl), or, with every_pixel, none and the
// shader's item k is pixel (k mod W, k / W). Implemented in region_vk.cpp.
std::vector<std::byte> pack_region(const cmr::backend::RegionSetup& setup, RegionPrecision precision,
                                   std::span<const std::array<int, 2>> pixels, bool every_pixel = false);

// A graphics pipeline drawing one full-screen triangle (the built-in vertex
// shader, no vertex input) with `fragment_spirv` (specialisation constant i =
// specialization[i]), dynamic viewport and scissor, for subpass 0 of
// render_pass, through the device's pipeline cache. Errors: shader_invalid (module or pipeline rejected),
// out_of_memory, device_lost. Implemented in fragment_pipeline.cpp.
Result<VkPipeline> create_fullscreen_pipeline(const DeviceState& state, VkPipelineLayout layout, VkRenderPass render_pass,
                                              std::span<const uint32_t> fragment_spirv,
                                              std::span<const uint32_t> specialization,
                                              const VkPipelineColorBlendAttachmentState& colour_blend);

}  // namespace cmr::vk::detail
