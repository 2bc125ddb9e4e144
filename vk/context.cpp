#include "vk/context.hpp"

#include "vk/internal.hpp"

#include <dlfcn.h>
#include <link.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <string_view>
#include <utility>

#include "spline/fields.hpp"

namespace cmr::vk {
namespace detail {

DeviceState::~DeviceState() {
  if (device != VK_NULL_HANDLE) {
    // Objects made from the Context are gone by now (they hold this state),
    // but the queue may still be executing their last submission.
    vkDeviceWaitIdle(device);
    if (pipeline_cache != VK_NULL_HANDLE) vkDestroyPipelineCache(device, pipeline_cache, nullptr);
    vkDestroyDevice(device, nullptr);
  }
  if (surface != VK_NULL_HANDLE) vkDestroySurfaceKHR(instance, surface, nullptr);
  if (instance != VK_NULL_HANDLE) vkDestroyInstance(instance, nullptr);
}

std::string vk_result_name(VkResult result) {
  switch (result) {
#define CMR_VK_RESULT_CASE(name) \
  case name: return #name;
    CMR_VK_RESULT_CASE(VK_SUCCESS)
    CMR_VK_RESULT_CASE(VK_NOT_READY)
    CMR_VK_RESULT_CASE(VK_TIMEOUT)
    CMR_VK_RESULT_CASE(VK_INCOMPLETE)
    CMR_VK_RESULT_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
    CMR_VK_RESULT_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    CMR_VK_RESULT_CASE(VK_ERROR_INITIALIZATION_FAILED)
    CMR_VK_RESULT_CASE(VK_ERROR_DEVICE_LOST)
    CMR_VK_RESULT_CASE(VK_ERROR_MEMORY_MAP_FAILED)
    CMR_VK_RESULT_CASE(VK_ERROR_LAYER_NOT_PRESENT)
    CMR_VK_RESULT_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
    CMR_VK_RESULT_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
    CMR_VK_RESULT_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
    CMR_VK_RESULT_CASE(VK_ERROR_TOO_MANY_OBJECTS)
    CMR_VK_RESULT_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
    CMR_VK_RESULT_CASE(VK_ERROR_FRAGMENTED_POOL)
    CMR_VK_RESULT_CASE(VK_ERROR_UNKNOWN)
    CMR_VK_RESULT_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
    CMR_VK_RESULT_CASE(VK_ERROR_INVALID_EXTERNAL_HANDLE)
    CMR_VK_RESULT_CASE(VK_ERROR_FRAGMENTATION)
    CMR_VK_RESULT_CASE(VK_ERROR_INVALID_SHADER_NV)
#undef CMR_VK_RESULT_CASE
    default: return "VkResult(" + std::to_string(static_cast<int>(result)) + ")";
  }
}

Errc errc_from(VkResult result) {
  switch (result) {
    case VK_ERROR_OUT_OF_HOST_MEMORY:
    case VK_ERROR_OUT_OF_DEVICE_MEMORY:
    case VK_ERROR_OUT_OF_POOL_MEMORY:
    case VK_ERROR_FRAGMENTED_POOL:
    case VK_ERROR_FRAGMENTATION:
    case VK_ERROR_MEMORY_MAP_FAILED: return Errc::out_of_memory;
    case VK_ERROR_DEVICE_LOST: return Errc::device_lost;
    case VK_ERROR_INCOMPATIBLE_DRIVER: return Errc::no_device;
    case VK_ERROR_LAYER_NOT_PRESENT:
    case VK_ERROR_EXTENSION_NOT_PRESENT:
    case VK_ERROR_FEATURE_NOT_PRESENT:
    case VK_ERROR_FORMAT_NOT_SUPPORTED: return Errc::missing_feature;
    case VK_ERROR_INVALID_SHADER_NV: return Errc::shader_invalid;
    default: return Errc::other;
  }
}

Error vk_error(VkResult result, std::string_view what) {
  const Errc code = errc_from(result);
  std::string message = std::string(what) + " failed: " + vk_result_name(result);
  switch (code) {
    case Errc::out_of_memory: message += "; free GPU memory or render a smaller image"; break;
    case Errc::device_lost:
      message += "; the GPU was reset (driver watchdog?), render in smaller bands or a smaller image";
      break;
    case Errc::no_device: message += "; install or update the Vulkan driver"; break;
    default: break;
  }
  return Error{code, result, std::move(message)};
}

std::optional<uint32_t> find_memory_type(const VkPhysicalDeviceMemoryProperties& memory,
                                         uint32_t type_bits, VkMemoryPropertyFlags required,
                                         VkMemoryPropertyFlags preferred) {
  for (const VkMemoryPropertyFlags wanted : {required | preferred, required}) {
    for (uint32_t i = 0; i < memory.memoryTypeCount; ++i) {
      const bool allowed = (type_bits & (1u << i)) != 0;
      if (allowed && (memory.memoryTypes[i].propertyFlags & wanted) == wanted) return i;
    }
  }
  return std::nullopt;
}

void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                   VkAccessFlags src_access, VkAccessFlags dst_access, VkPipelineStageFlags src_stage,
                   VkPipelineStageFlags dst_stage) {
  VkImageMemoryBarrier b{};
  b.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER;
  b.oldLayout = from;
  b.newLayout = to;
  b.srcAccessMask = src_access;
  b.dstAccessMask = dst_access;
  b.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.image = image;
  b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  vkCmdPipelineBarrier(cmd, src_stage, dst_stage, 0, 0, nullptr, 0, nullptr, 1, &b);
}

void buffer_barrier(VkCommandBuffer cmd, VkBuffer buffer, VkDeviceSize offset, VkDeviceSize size,
                    VkAccessFlags src_access, VkAccessFlags dst_access, VkPipelineStageFlags src_stage,
                    VkPipelineStageFlags dst_stage) {
  VkBufferMemoryBarrier b{};
  b.sType = VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER;
  b.srcAccessMask = src_access;
  b.dstAccessMask = dst_access;
  b.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.buffer = buffer;
  b.offset = offset;
  b.size = size;
  vkCmdPipelineBarrier(cmd, src_stage, dst_stage, 0, 0, nullptr, 1, &b, 0, nullptr);
}

Result<void> begin_one_time(VkCommandBuffer cmd) {
  VkCommandBufferBeginInfo begin{};
  begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  if (VkResult r = vkBeginCommandBuffer(cmd, &begin); r != VK_SUCCESS) return vk_error(r, "vkBeginCommandBuffer");
  return {};
}

Result<void> create_storage_set(VkDevice device, VkDescriptorSetLayout set_layout, uint32_t storage_buffers,
                                VkDescriptorPool& pool, VkDescriptorSet& set, std::string_view what) {
  VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, storage_buffers};
  VkDescriptorPoolCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
  info.maxSets = 1;
  info.poolSizeCount = 1;
  info.pPoolSizes = &size;
  if (VkResult r = vkCreateDescriptorPool(device, &info, nullptr, &pool); r != VK_SUCCESS) {
    pool = VK_NULL_HANDLE;
    return vk_error(r, "vkCreateDescriptorPool (" + std::string(what) + ")");
  }
  VkDescriptorSetAllocateInfo alloc{};
  alloc.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
  alloc.descriptorPool = pool;
  alloc.descriptorSetCount = 1;
  alloc.pSetLayouts = &set_layout;
  if (VkResult r = vkAllocateDescriptorSets(device, &alloc, &set); r != VK_SUCCESS) {
    vkDestroyDescriptorPool(device, pool, nullptr);
    pool = VK_NULL_HANDLE;
    set = VK_NULL_HANDLE;
    return vk_error(r, "vkAllocateDescriptorSets (" + std::string(what) + ")");
  }
  return {};
}

Result<void> create_buffer(const DeviceState& state, Buffer& out, VkDeviceSize size, VkBufferUsageFlags usage,
                           VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred, std::string_view what) {
  const VkDevice device = state.device;
  const std::string label = std::string(what) + " (" + std::to_string(size) + " bytes)";
  // On failure nothing half-made is left behind in `out`.
  const auto fail = [&](Error e) {
    destroy_buffer(device, out);
    return e;
  };
  VkBufferCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
  info.size = size;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  if (VkResult r = vkCreateBuffer(device, &info, nullptr, &out.buffer); r != VK_SUCCESS) {
    out.buffer = VK_NULL_HANDLE;
    return fail(vk_error(r, "vkCreateBuffer for " + label));
  }
  out.size = size;

  VkMemoryRequirements req{};
  vkGetBufferMemoryRequirements(device, out.buffer, &req);
  const auto type = find_memory_type(state.memory, req.memoryTypeBits, required, preferred);
  if (!type) {
    return fail(Error{Errc::out_of_memory, VK_SUCCESS, "no suitable memory type for " + label});
  }
  VkMemoryAllocateInfo alloc{};
  alloc.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex = *type;
  if (VkResult r = vkAllocateMemory(device, &alloc, nullptr, &out.memory); r != VK_SUCCESS) {
    out.memory = VK_NULL_HANDLE;
    return fail(vk_error(r, "vkAllocateMemory for " + label));
  }
  if (VkResult r = vkBindBufferMemory(device, out.buffer, out.memory, 0); r != VK_SUCCESS) {
    return fail(vk_error(r, "vkBindBufferMemory for " + label));
  }
  const VkMemoryPropertyFlags flags = state.memory.memoryTypes[*type].propertyFlags;
  out.coherent = (flags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT) != 0;
  if ((required & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) != 0) {
    void* mapped = nullptr;
    if (VkResult r = vkMapMemory(device, out.memory, 0, VK_WHOLE_SIZE, 0, &mapped); r != VK_SUCCESS) {
      return fail(vk_error(r, "vkMapMemory for " + label));
    }
    out.mapped = static_cast<std::byte*>(mapped);
  }
  return {};
}

void destroy_buffer(VkDevice device, Buffer& buffer) {
  // Freeing memory implicitly unmaps it.
  if (buffer.buffer != VK_NULL_HANDLE) vkDestroyBuffer(device, buffer.buffer, nullptr);
  if (buffer.memory != VK_NULL_HANDLE) vkFreeMemory(device, buffer.memory, nullptr);
  buffer = Buffer{};
}

Result<void> submit(VkQueue queue, VkCommandBuffer cmd, VkFence fence) {
  VkSubmitInfo info{};
  info.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
  info.commandBufferCount = 1;
  info.pCommandBuffers = &cmd;
  if (VkResult r = vkQueueSubmit(queue, 1, &info, fence); r != VK_SUCCESS) return vk_error(r, "vkQueueSubmit");
  return {};
}

namespace {

// Decodes a SPIR-V literal string: nul-terminated, packed little-endian.
std::string spirv_string(std::span<const uint32_t> words) {
  std::string out;
  for (const uint32_t word : words) {
    for (int byte = 0; byte < 4; ++byte) {
      const char ch = static_cast<char>((word >> (8 * byte)) & 0xff);
      if (ch == '\0') return out;
      out.push_back(ch);
    }
  }
  return out;
}

}  // namespace

Result<void> check_spirv(std::span<const uint32_t> words, ShaderStage stage) {
  constexpr uint32_t kMagic = 0x07230203;
  constexpr uint32_t kMaxVersion = 0x00010300;  // SPIR-V 1.3 = Vulkan 1.1
  constexpr uint32_t kOpEntryPoint = 15;
  constexpr std::size_t kHeaderWords = 5;
  // SPIR-V execution models: Fragment 4, GLCompute 5.
  const uint32_t model = stage == ShaderStage::fragment ? 4 : 5;
  const std::string name = stage == ShaderStage::fragment ? "fragment" : "compute";
  const auto fail = [](std::string message) { return Error{Errc::shader_invalid, VK_SUCCESS, std::move(message)}; };

  if (words.size() < kHeaderWords || words[0] != kMagic) {
    return fail(name + " shader is not SPIR-V (no 0x07230203 magic number); "
                "pass the words from a cmr_add_shader() header");
  }
  if (words[1] > kMaxVersion) {
    return fail(name + " shader is SPIR-V " + std::to_string((words[1] >> 16) & 0xff) + "." +
                std::to_string((words[1] >> 8) & 0xff) +
                ", but only up to 1.3 is accepted; compile with --target-env vulkan1.1");
  }
  bool has_main = false;
  for (std::size_t at = kHeaderWords; at < words.size();) {
    const uint32_t word_count = words[at] >> 16;
    const uint32_t opcode = words[at] & 0xffff;
    if (word_count == 0 || at + word_count > words.size()) {
      return fail(name + " shader SPIR-V is truncated or corrupt at word " + std::to_string(at));
    }
    if (opcode == kOpEntryPoint && word_count >= 4 && words[at + 1] == model &&
        spirv_string(words.subspan(at + 3, word_count - 3)) == "main") {
      has_main = true;
    }
    at += word_count;
  }
  if (!has_main) {
    return fail("SPIR-V has no " + name + "-stage entry point named 'main'; is it a " + name + " shader?");
  }
  return {};
}


ShaderModule::~ShaderModule() {
  if (handle != VK_NULL_HANDLE) vkDestroyShaderModule(device, handle, nullptr);
}

Result<void> ShaderModule::create(VkDevice dev, std::span<const uint32_t> words, std::string_view what) {
  device = dev;
  VkShaderModuleCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
  info.codeSize = words.size_bytes();
  info.pCode = words.data();
  if (VkResult r = vkCreateShaderModule(device, &info, nullptr, &handle); r != VK_SUCCESS) {
    handle = VK_NULL_HANDLE;
    Error e = vk_error(r, "vkCreateShaderModule (" + std::string(what) + ")");
    if (e.code == Errc::other) e.code = Errc::shader_invalid;
    return e;
  }
  return {};
}

Specialization::Specialization(std::span<const uint32_t> values) : entries(values.size()) {
  for (uint32_t i = 0; i < entries.size(); ++i) entries[i] = {i, i * 4u, 4u};
  data.mapEntryCount = static_cast<uint32_t>(entries.size());
  data.pMapEntries = entries.data();
  data.dataSize = values.size_bytes();
  data.pData = values.data();
}

void PipelineCore::wait_if_pending() {
  if (device != VK_NULL_HANDLE && pending) vkDeviceWaitIdle(device);
  pending = false;
}

Result<void> PipelineCore::create_layouts_and_set(uint32_t storage_buffers, VkShaderStageFlags stage,
                                                  uint32_t push_constant_bytes, std::string_view what) {
  if (auto r = create_storage_layout(device, storage_buffers, stage, push_constant_bytes, set_layout, pipeline_layout,
                                     what);
      !r)
    return r;
  return create_storage_set(device, set_layout, storage_buffers, descriptor_pool, descriptor_set, what);
}

PipelineCore::~PipelineCore() {
  if (device == VK_NULL_HANDLE) return;
  wait_if_pending();
  if (fence != VK_NULL_HANDLE) vkDestroyFence(device, fence, nullptr);
  if (command_pool != VK_NULL_HANDLE) vkDestroyCommandPool(device, command_pool, nullptr);
  if (pipeline != VK_NULL_HANDLE) vkDestroyPipeline(device, pipeline, nullptr);
  if (pipeline_layout != VK_NULL_HANDLE) vkDestroyPipelineLayout(device, pipeline_layout, nullptr);
  if (descriptor_pool != VK_NULL_HANDLE) vkDestroyDescriptorPool(device, descriptor_pool, nullptr);
  if (set_layout != VK_NULL_HANDLE) vkDestroyDescriptorSetLayout(device, set_layout, nullptr);
}

Result<void> create_one_shot_commands(PipelineCore& core) {
  VkCommandPoolCreateInfo pool_info{};
  pool_info.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
  pool_info.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;  // re-recorded for every submission
  pool_info.queueFamilyIndex = core.state->queue_family_index;
  if (VkResult r = vkCreateCommandPool(core.device, &pool_info, nullptr, &core.command_pool); r != VK_SUCCESS) {
    core.command_pool = VK_NULL_HANDLE;
    return vk_error(r, "vkCreateCommandPool");
  }
  VkCommandBufferAllocateInfo alloc{};
  alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
  alloc.commandPool = core.command_pool;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  if (VkResult r = vkAllocateCommandBuffers(core.device, &alloc, &core.command_buffer); r != VK_SUCCESS) {
    core.command_buffer = VK_NULL_HANDLE;
    return vk_error(r, "vkAllocateCommandBuffers");
  }
  VkFenceCreateInfo fence_info{};
  fence_info.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
  if (VkResult r = vkCreateFence(core.device, &fence_info, nullptr, &core.fence); r != VK_SUCCESS) {
    core.fence = VK_NULL_HANDLE;
    return vk_error(r, "vkCreateFence");
  }
  return {};
}

Result<void> submit_and_wait(PipelineCore& core, uint64_t timeout_ns, const std::string& timeout_message) {
  const auto fail = [&](VkResult r, const std::string& what) -> Error {
    Error e = vk_error(r, what);
    if (e.code == Errc::device_lost) core.lost = true;
    return e;
  };
  if (VkResult r = vkResetFences(core.device, 1, &core.fence); r != VK_SUCCESS) return fail(r, "vkResetFences");
  if (auto r = submit(core.state->queue, core.command_buffer, core.fence); !r) {
    if (r.error().code == Errc::device_lost) core.lost = true;
    return r.error();
  }
  core.pending = true;
  const VkResult r = vkWaitForFences(core.device, 1, &core.fence, VK_TRUE, timeout_ns);
  if (r == VK_TIMEOUT) {
    core.lost = true;  // the command buffer may still be executing: never reuse it
    return Error{Errc::device_lost, r, timeout_message};
  }
  if (r != VK_SUCCESS) return fail(r, "vkWaitForFences");
  core.pending = false;
  return {};
}

Result<void> create_storage_layout(VkDevice device, uint32_t storage_buffers, VkShaderStageFlags stage,
                                   uint32_t push_constant_bytes, VkDescriptorSetLayout& set_layout,
                                   VkPipelineLayout& pipeline_layout, std::string_view what) {
  std::vector<VkDescriptorSetLayoutBinding> bindings(storage_buffers);
  for (uint32_t i = 0; i < storage_buffers; ++i) {
    bindings[i].binding = i;
    bindings[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    bindings[i].descriptorCount = 1;
    bindings[i].stageFlags = stage;
  }
  VkDescriptorSetLayoutCreateInfo set_info{};
  set_info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
  set_info.bindingCount = storage_buffers;
  set_info.pBindings = bindings.data();
  if (VkResult r = vkCreateDescriptorSetLayout(device, &set_info, nullptr, &set_layout); r != VK_SUCCESS) {
    set_layout = VK_NULL_HANDLE;
    return vk_error(r, "vkCreateDescriptorSetLayout (" + std::string(what) + ")");
  }
  VkPushConstantRange push_range{stage, 0, push_constant_bytes};
  VkPipelineLayoutCreateInfo layout_info{};
  layout_info.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
  layout_info.setLayoutCount = 1;
  layout_info.pSetLayouts = &set_layout;
  layout_info.pushConstantRangeCount = push_constant_bytes > 0 ? 1 : 0;
  layout_info.pPushConstantRanges = push_constant_bytes > 0 ? &push_range : nullptr;
  if (VkResult r = vkCreatePipelineLayout(device, &layout_info, nullptr, &pipeline_layout); r != VK_SUCCESS) {
    pipeline_layout = VK_NULL_HANDLE;
    return vk_error(r, "vkCreatePipelineLayout (" + std::string(what) + ")");
  }
  return {};
}

void write_storage_set(VkDevice device, VkDescriptorSet set, std::span<const VkDescriptorBufferInfo> buffers) {
  std::vector<VkWriteDescriptorSet> writes(buffers.size());
  for (std::size_t i = 0; i < buffers.size(); ++i) {
    writes[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
    writes[i].dstSet = set;
    writes[i].dstBinding = static_cast<uint32_t>(i);
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[i].pBufferInfo = &buffers[i];
  }
  vkUpdateDescriptorSets(device, static_cast<uint32_t>(writes.size()), writes.data(), 0, nullptr);
}

}  // namespace detail

namespace {

using detail::vk_error;

#if defined(__aarch64__)
constexpr std::string_view kLavapipeIcd = "/usr/share/vulkan/icd.d/lvp_icd.aarch64.json";
#else
constexpr std::string_view kLavapipeIcd = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json";
#endif

// One actionable line for "the loader found nothing". The library reads no
// environment: a program that knows the loader's driver selection adds it
// (BackendChoice::loader_selection, set by tools/cli_common.cpp).
Error no_device_error(VkResult result) {
  std::string message = "no Vulkan device found";
  message += "; install mesa-vulkan-drivers or select lavapipe with VK_DRIVER_FILES=";
  message += kLavapipeIcd;
  return Error{Errc::no_device, result, std::move(message)};
}

// Owns a VkInstance until released into a DeviceState.
class InstanceHandle {
 public:
  explicit InstanceHandle(VkInstance instance) : instance_(instance) {}
  InstanceHandle(InstanceHandle&& other) noexcept : instance_(std::exchange(other.instance_, VK_NULL_HANDLE)) {}
  InstanceHandle& operator=(InstanceHandle&&) = delete;
  InstanceHandle(const InstanceHandle&) = delete;
  InstanceHandle& operator=(const InstanceHandle&) = delete;
  ~InstanceHandle() {
    if (instance_ != VK_NULL_HANDLE) vkDestroyInstance(instance_, nullptr);
  }
  VkInstance get() const { return instance_; }
  VkInstance release() { return std::exchange(instance_, VK_NULL_HANDLE); }

 private:
  VkInstance instance_;
};

// Vulkan 1.1 gives SPIR-V 1.3, which cmr_add_shader() targets.
constexpr uint32_t kApiVersion = VK_API_VERSION_1_1;

Result<InstanceHandle> create_instance(const std::vector<std::string>& extensions) {
  // libvulkan is linked directly, so a missing library stops the program
  // before main(); what can still happen is a broken or 1.0-only loader.
  if (vkGetInstanceProcAddr(VK_NULL_HANDLE, "vkCreateInstance") == nullptr) {
    return Error{Errc::loader_missing, VK_SUCCESS,
                 "the Vulkan loader does not provide vkCreateInstance; reinstall libvulkan1"};
  }
  const auto enumerate_version = reinterpret_cast<PFN_vkEnumerateInstanceVersion>(
      vkGetInstanceProcAddr(VK_NULL_HANDLE, "vkEnumerateInstanceVersion"));
  if (enumerate_version == nullptr) {
    return Error{Errc::loader_missing, VK_SUCCESS,
                 "the Vulkan loader only supports Vulkan 1.0; install libvulkan1 >= 1.1"};
  }
  uint32_t loader_version = 0;
  if (VkResult r = enumerate_version(&loader_version); r != VK_SUCCESS) {
    return vk_error(r, "vkEnumerateInstanceVersion");
  }
  if (loader_version < kApiVersion) {
    return Error{Errc::loader_missing, VK_SUCCESS,
                 "the Vulkan loader only supports Vulkan 1.0; install libvulkan1 >= 1.1"};
  }

  VkApplicationInfo app{};
  app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  app.pApplicationName = "cmr";
  app.applicationVersion = 1;
  app.pEngineName = "cmr::vk";
  app.engineVersion = 1;
  app.apiVersion = kApiVersion;

  // No layers; extensions only as asked (none: headless, no surface).
  std::vector<const char*> names;
  for (const std::string& e : extensions) names.push_back(e.c_str());
  VkInstanceCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
  info.pApplicationInfo = &app;
  info.enabledExtensionCount = static_cast<uint32_t>(names.size());
  info.ppEnabledExtensionNames = names.data();

  VkInstance instance = VK_NULL_HANDLE;
  const VkResult r = vkCreateInstance(&info, nullptr, &instance);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER || r == VK_ERROR_INITIALIZATION_FAILED) {
    // The loader reports "no usable ICD" with these two codes.
    return no_device_error(r);
  }
  if (r == VK_ERROR_EXTENSION_NOT_PRESENT) {
    std::string list;
    for (const std::string& e : extensions) list += (list.empty() ? "" : ", ") + e;
    return Error{Errc::missing_feature, r, "the Vulkan loader lacks an instance extension of " + list};
  }
  if (r != VK_SUCCESS) return vk_error(r, "vkCreateInstance");
  return InstanceHandle(instance);
}

struct Candidate {
  VkPhysicalDevice handle = VK_NULL_HANDLE;
  DeviceInfo info;
  uint32_t api_version = 0;
  std::optional<uint32_t> graphics_family;
  bool presents = true;  // with a surface: graphics_family presents to it and VK_KHR_swapchain exists
};

// Every library loaded so far, the Vulkan driver among them, stays mapped
// until exit. The loader unloads the driver with each instance, and
// - NVIDIA's driver (580, seen on an H200) can then be loaded only 29 times
//   in a process: the 30th vkCreateInstance fails ("Could not get
//   'vkCreateInstance' via 'vk_icdGetInstanceProcAddr'"), so a program that
//   opens and closes Contexts (a test suite, a service) would lose its GPU;
// - LeakSanitizer would report the driver's process-lifetime caches from
//   "<unknown module>", which no suppression can name; mapped, they are
//   named and suppressed (tools/lsan.supp).
void keep_loaded_libraries() {
  std::vector<std::string> names;
  dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* out) {
        if (info->dlpi_name != nullptr && info->dlpi_name[0] != '\0')
          static_cast<std::vector<std::string>*>(out)->emplace_back(info->dlpi_name);
        return 0;
      },
      &names);
  for (const std::string& name : names) ::dlopen(name.c_str(), RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
}

// All physical devices with what device selection needs to know about them.
// Zero devices is an error (no_device).
Result<std::vector<Candidate>> list_devices(VkInstance instance) {
  std::vector<VkPhysicalDevice> handles;
  VkResult r = VK_INCOMPLETE;
  while (r == VK_INCOMPLETE) {  // the count may change between the two calls
    uint32_t count = 0;
    r = vkEnumeratePhysicalDevices(instance, &count, nullptr);
    if (r != VK_SUCCESS) break;
    handles.resize(count);
    r = vkEnumeratePhysicalDevices(instance, &count, handles.data());
    handles.resize(count);
  }
  if (r == VK_ERROR_INITIALIZATION_FAILED) return no_device_error(r);
  if (r != VK_SUCCESS) return vk_error(r, "vkEnumeratePhysicalDevices");
  if (handles.empty()) return no_device_error(VK_SUCCESS);
  keep_loaded_libraries();

  std::vector<Candidate> devices;
  devices.reserve(handles.size());
  for (VkPhysicalDevice handle : handles) {
    VkPhysicalDeviceProperties props{};
    vkGetPhysicalDeviceProperties(handle, &props);
    VkPhysicalDeviceFeatures features{};
    vkGetPhysicalDeviceFeatures(handle, &features);

    uint32_t family_count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(handle, &family_count, nullptr);
    std::vector<VkQueueFamilyProperties> families(family_count);
    vkGetPhysicalDeviceQueueFamilyProperties(handle, &family_count, families.data());

    Candidate c;
    c.handle = handle;
    c.info.name = props.deviceName;
    c.info.type = props.deviceType;
    c.info.float64 = features.shaderFloat64 == VK_TRUE;
    c.info.fragment_stores = features.fragmentStoresAndAtomics == VK_TRUE;
    c.info.max_image_dimension_2d = props.limits.maxImageDimension2D;
    c.api_version = props.apiVersion;
    for (uint32_t i = 0; i < family_count; ++i) {
      if ((families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) != 0 && families[i].queueCount > 0) {
        c.graphics_family = i;
        break;
      }
    }
    devices.push_back(std::move(c));
  }
  return devices;
}

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return out;
}

// Empty when the device is usable, otherwise why not ("device 'x' lacks ...").
std::string unusable_reason(const Candidate& c, const ContextOptions& options) {
  const std::string who = "device '" + c.info.name + "'";
  if (c.api_version < kApiVersion) return who + " supports only Vulkan 1.0 (1.1 is required)";
  if (!c.graphics_family) return who + " has no graphics queue";
  if (options.require_float64 && !c.info.float64) return who + " lacks shaderFloat64";
  if (!c.presents) return who + " cannot present to the window (no presenting graphics queue or VK_KHR_swapchain)";
  return {};
}

bool has_device_extension(VkPhysicalDevice device, std::string_view name) {
  uint32_t count = 0;
  if (vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr) != VK_SUCCESS) return false;
  std::vector<VkExtensionProperties> props(count);
  if (vkEnumerateDeviceExtensionProperties(device, nullptr, &count, props.data()) != VK_SUCCESS) return false;
  return std::any_of(props.begin(), props.end(), [&](const VkExtensionProperties& p) { return name == p.extensionName; });
}

// With a surface, the graphics family becomes the first one that also
// presents to it; a device with none, or without VK_KHR_swapchain, is marked.
void check_presentation(Candidate& c, VkSurfaceKHR surface) {
  uint32_t family_count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(c.handle, &family_count, nullptr);
  std::vector<VkQueueFamilyProperties> families(family_count);
  vkGetPhysicalDeviceQueueFamilyProperties(c.handle, &family_count, families.data());
  c.graphics_family.reset();
  for (uint32_t i = 0; i < family_count; ++i) {
    VkBool32 supported = VK_FALSE;
    if ((families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) == 0 || families[i].queueCount == 0) continue;
    if (vkGetPhysicalDeviceSurfaceSupportKHR(c.handle, i, surface, &supported) == VK_SUCCESS && supported) {
      c.graphics_family = i;
      break;
    }
  }
  c.presents = c.graphics_family.has_value() && has_device_extension(c.handle, VK_KHR_SWAPCHAIN_EXTENSION_NAME);
  if (!c.graphics_family) c.graphics_family = 0;  // reported through `presents`, not as "no graphics queue"
}

}  // namespace

Result<std::vector<DeviceInfo>> enumerate_devices() {
  auto instance = create_instance({});
  if (!instance) return instance.error();
  auto devices = list_devices(instance.value().get());
  if (!devices) return devices.error();
  std::vector<DeviceInfo> infos;
  infos.reserve(devices.value().size());
  for (const Candidate& c : devices.value()) infos.push_back(c.info);
  return infos;
}

Result<Context> Context::create(const ContextOptions& options) {
  auto instance = create_instance(options.instance_extensions);
  if (!instance) return instance.error();
  auto state = std::make_shared<detail::DeviceState>();
  state->instance = instance.value().release();
  if (options.make_surface) {
    auto surface = options.make_surface(state->instance);
    if (!surface) return surface.error();
    state->surface = surface.value();
  }

  auto listed = list_devices(state->instance);
  if (!listed) return listed.error();
  std::vector<Candidate>& devices = listed.value();
  if (state->surface != VK_NULL_HANDLE) {
    for (Candidate& c : devices) check_presentation(c, state->surface);
  }

  // Name filter first: a name that matches nothing must not fall back to
  // some other device.
  std::vector<const Candidate*> matching;
  const std::string wanted = lower(options.device_name);
  for (const Candidate& c : devices) {
    if (wanted.empty() || lower(c.info.name).find(wanted) != std::string::npos) matching.push_back(&c);
  }
  if (matching.empty()) {
    std::string available;
    for (const Candidate& c : devices) {
      available += (available.empty() ? "'" : ", '") + c.info.name + "'";
    }
    return Error{Errc::device_not_found, VK_SUCCESS,
                 "no Vulkan device named '" + options.device_name + "' (available: " + available + ")"};
  }

  const Candidate* chosen = nullptr;
  std::vector<std::string> reasons;
  for (const Candidate* c : matching) {
    std::string reason = unusable_reason(*c, options);
    if (reason.empty()) {
      chosen = c;
      break;
    }
    reasons.push_back(std::move(reason));
  }
  if (chosen == nullptr) {
    std::string message = reasons.size() == 1 ? reasons.front() : "no usable Vulkan device: ";
    if (reasons.size() > 1) {
      for (std::size_t i = 0; i < reasons.size(); ++i) message += (i ? "; " : "") + reasons[i];
    }
    const bool fp64_problem = std::any_of(reasons.begin(), reasons.end(), [](const std::string& r) {
      return r.find("shaderFloat64") != std::string::npos;
    });
    if (fp64_problem) message += "; use " + field("precision") + " fp32";
    return Error{Errc::missing_feature, VK_SUCCESS, std::move(message)};
  }

  state->physical_device = chosen->handle;
  state->queue_family_index = *chosen->graphics_family;
  state->info = chosen->info;
  VkPhysicalDeviceProperties props{};
  vkGetPhysicalDeviceProperties(chosen->handle, &props);
  state->limits = props.limits;
  state->properties = props;
  vkGetPhysicalDeviceMemoryProperties(chosen->handle, &state->memory);

  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queue_info{};
  queue_info.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
  queue_info.queueFamilyIndex = state->queue_family_index;
  queue_info.queueCount = 1;
  queue_info.pQueuePriorities = &priority;

  VkPhysicalDeviceFeatures features{};
  features.shaderFloat64 = chosen->info.float64 ? VK_TRUE : VK_FALSE;
  features.fragmentStoresAndAtomics = chosen->info.fragment_stores ? VK_TRUE : VK_FALSE;

  VkDeviceCreateInfo device_info{};
  device_info.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
  device_info.queueCreateInfoCount = 1;
  device_info.pQueueCreateInfos = &queue_info;
  device_info.pEnabledFeatures = &features;
  const char* swapchain_extension = VK_KHR_SWAPCHAIN_EXTENSION_NAME;
  if (state->surface != VK_NULL_HANDLE) {
    device_info.enabledExtensionCount = 1;
    device_info.ppEnabledExtensionNames = &swapchain_extension;
  }

  if (VkResult r = vkCreateDevice(state->physical_device, &device_info, nullptr, &state->device);
      r != VK_SUCCESS) {
    state->device = VK_NULL_HANDLE;
    return vk_error(r, "vkCreateDevice on '" + chosen->info.name + "'");
  }
  vkGetDeviceQueue(state->device, state->queue_family_index, 0, &state->queue);
  Context context(std::move(state));
  if (auto r = context.load_pipeline_cache({}); !r) return r.error();
  return context;
}

bool pipeline_cache_matches(std::span<const std::byte> data, uint32_t vendor_id, uint32_t device_id,
                            const uint8_t (&uuid)[VK_UUID_SIZE]) {
  // VkPipelineCacheHeaderVersionOne: headerSize, headerVersion, vendorID,
  // deviceID (4 bytes each, the host's byte order), pipelineCacheUUID.
  constexpr std::size_t kHeader = 16 + VK_UUID_SIZE;
  if (data.size() < kHeader) return false;
  uint32_t word[4];
  std::memcpy(word, data.data(), sizeof word);
  return word[0] >= kHeader && word[0] <= data.size() && word[1] == VK_PIPELINE_CACHE_HEADER_VERSION_ONE &&
         word[2] == vendor_id && word[3] == device_id && std::memcmp(data.data() + 16, uuid, VK_UUID_SIZE) == 0;
}

Result<void> Context::load_pipeline_cache(std::span<const std::byte> data) {
  detail::DeviceState& s = *state_;
  const bool usable = !data.empty() && pipeline_cache_matches(data, s.properties.vendorID, s.properties.deviceID,
                                                              s.properties.pipelineCacheUUID);
  VkPipelineCacheCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO;
  info.initialDataSize = usable ? data.size() : 0;
  info.pInitialData = usable ? data.data() : nullptr;
  VkPipelineCache cache = VK_NULL_HANDLE;
  if (VkResult r = vkCreatePipelineCache(s.device, &info, nullptr, &cache); r != VK_SUCCESS)
    return vk_error(r, "vkCreatePipelineCache");
  if (s.pipeline_cache != VK_NULL_HANDLE) vkDestroyPipelineCache(s.device, s.pipeline_cache, nullptr);
  s.pipeline_cache = cache;
  if (!data.empty() && !usable)
    return Error{Errc::other, VK_SUCCESS,
                 "the pipeline cache is not one of this device and driver (its header does not match); it "
                 "starts empty"};
  return {};
}

std::vector<std::byte> Context::pipeline_cache_data() const {
  const detail::DeviceState& s = *state_;
  std::size_t size = 0;
  if (vkGetPipelineCacheData(s.device, s.pipeline_cache, &size, nullptr) != VK_SUCCESS) return {};
  std::vector<std::byte> out(size);
  if (vkGetPipelineCacheData(s.device, s.pipeline_cache, &size, out.data()) != VK_SUCCESS) return {};
  out.resize(size);
  return out;
}

Context::Context(std::shared_ptr<detail::DeviceState> state) : state_(std::move(state)) {}
Context::Context(Context&&) noexcept = default;
Context& Context::operator=(Context&&) noexcept = default;
Context::~Context() = default;

const DeviceInfo& Context::device() const { return state_->info; }
VkInstance Context::instance() const { return state_->instance; }
VkPhysicalDevice Context::physical_device() const { return state_->physical_device; }
VkDevice Context::device_handle() const { return state_->device; }
VkQueue Context::queue() const { return state_->queue; }
uint32_t Context::queue_family_index() const { return state_->queue_family_index; }
VkSurfaceKHR Context::surface() const { return state_->surface; }

}  // namespace cmr::vk
