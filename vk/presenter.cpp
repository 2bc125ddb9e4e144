#include "vk/presenter.hpp"

#include "vk/internal.hpp"
#include "vk/x11_shm.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>
#include <utility>

namespace cmr::vk {

using detail::buffer_barrier;
using detail::image_barrier;
using detail::vk_error;

uint32_t choose_image_count(const VkSurfaceCapabilitiesKHR& caps) {
  uint32_t count = caps.minImageCount + 1;
  if (caps.maxImageCount != 0) count = std::min(count, caps.maxImageCount);  // 0: no upper limit
  return count;
}

VkExtent2D choose_extent(const VkSurfaceCapabilitiesKHR& caps, uint32_t width, uint32_t height) {
  if (caps.currentExtent.width != std::numeric_limits<uint32_t>::max()) return caps.currentExtent;
  return {std::clamp(width, caps.minImageExtent.width, caps.maxImageExtent.width),
          std::clamp(height, caps.minImageExtent.height, caps.maxImageExtent.height)};
}

namespace {

constexpr uint64_t kFenceTimeoutNs = 120'000'000'000ull;  // two minutes: a hung device, not a slow frame

struct SlotSync {
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;
  VkSemaphore acquired = VK_NULL_HANDLE;
};

using Readback = detail::Buffer;  // host-visible, coherent, mapped while it exists

}  // namespace

struct Presenter::Impl {
  std::shared_ptr<detail::DeviceState> state;
  PresenterOptions options;
  VkSurfaceFormatKHR format{};
  VkPresentModeKHR present_mode = VK_PRESENT_MODE_FIFO_KHR;
  VkRenderPass render_pass = VK_NULL_HANDLE;
  VkCommandPool pool = VK_NULL_HANDLE;
  std::array<SlotSync, kFramesInFlight> slots{};
  uint32_t slot = 0;

  VkSwapchainKHR swapchain = VK_NULL_HANDLE;
  VkExtent2D extent{};
  uint32_t min_images = 0;
  std::vector<VkImage> images;
  std::vector<VkImageView> views;
  std::vector<VkFramebuffer> framebuffers;
  std::vector<VkSemaphore> rendered;  // per image: signalled by the submit, waited on by present
  int generation = 0;
  bool stale = false;  // recreate before the next acquire
  Readback readback;
  // MIT-SHM presentation (CPU devices on X11): frames are drawn into
  // `offscreen` (images = {offscreen}), read back and put into the window.
  std::unique_ptr<detail::XShmTarget> shm;
  VkImage offscreen = VK_NULL_HANDLE;
  VkDeviceMemory offscreen_memory = VK_NULL_HANDLE;
  std::string presentation = "presented through the Vulkan swapchain";

  VkDevice dev() const { return state->device; }
  ~Impl() {
    if (!state || dev() == VK_NULL_HANDLE) return;
    vkDeviceWaitIdle(dev());
    destroy_swapchain_parts();
    if (swapchain != VK_NULL_HANDLE) vkDestroySwapchainKHR(dev(), swapchain, nullptr);
    destroy_offscreen();
    free_readback();
    for (SlotSync& s : slots) {
      if (s.fence != VK_NULL_HANDLE) vkDestroyFence(dev(), s.fence, nullptr);
      if (s.acquired != VK_NULL_HANDLE) vkDestroySemaphore(dev(), s.acquired, nullptr);
    }
    if (pool != VK_NULL_HANDLE) vkDestroyCommandPool(dev(), pool, nullptr);
    if (render_pass != VK_NULL_HANDLE) vkDestroyRenderPass(dev(), render_pass, nullptr);
  }

  void destroy_swapchain_parts() {
    for (VkFramebuffer f : framebuffers) vkDestroyFramebuffer(dev(), f, nullptr);
    for (VkImageView v : views) vkDestroyImageView(dev(), v, nullptr);
    for (VkSemaphore s : rendered) vkDestroySemaphore(dev(), s, nullptr);
    framebuffers.clear();
    views.clear();
    rendered.clear();
    images.clear();
  }

  void destroy_offscreen() {
    if (offscreen != VK_NULL_HANDLE) vkDestroyImage(dev(), offscreen, nullptr);
    if (offscreen_memory != VK_NULL_HANDLE) vkFreeMemory(dev(), offscreen_memory, nullptr);
    offscreen = VK_NULL_HANDLE;
    offscreen_memory = VK_NULL_HANDLE;
  }

  void free_readback() {
    detail::destroy_buffer(dev(), readback);
  }

  Result<void> choose_surface_format();
  Result<void> create_render_pass();
  Result<void> create_sync();
  Result<void> create_swapchain(uint32_t width, uint32_t height);
  Result<void> create_image_parts();
  Result<void> create_views();
  bool try_shm(const PresenterOptions& wanted, uint32_t width, uint32_t height);
  Result<void> create_offscreen(uint32_t width, uint32_t height, bool resize_shm);
  Result<void> ensure_readback(VkDeviceSize size);
  void record_readback(const PresentFrame& frame) const;
  void copy_screenshot(VkExtent2D size, Screenshot& out) const;
};

Result<void> Presenter::Impl::choose_surface_format() {
  VkPhysicalDevice pd = state->physical_device;
  uint32_t count = 0;
  if (VkResult r = vkGetPhysicalDeviceSurfaceFormatsKHR(pd, state->surface, &count, nullptr); r != VK_SUCCESS)
    return vk_error(r, "vkGetPhysicalDeviceSurfaceFormatsKHR");
  std::vector<VkSurfaceFormatKHR> formats(count);
  if (VkResult r = vkGetPhysicalDeviceSurfaceFormatsKHR(pd, state->surface, &count, formats.data()); r != VK_SUCCESS)
    return vk_error(r, "vkGetPhysicalDeviceSurfaceFormatsKHR");
  // UNORM, so that the bytes we write are the bytes shown and read back.
  for (VkFormat wanted : {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM}) {
    for (const VkSurfaceFormatKHR& f : formats) {
      if (f.format == wanted) {
        format = f;
        return {};
      }
    }
  }
  return Error{Errc::missing_feature, VK_SUCCESS, "the window surface offers no 8-bit UNORM format"};
}

Result<void> Presenter::Impl::create_render_pass() {
  VkAttachmentDescription colour{};
  colour.format = format.format;
  colour.samples = VK_SAMPLE_COUNT_1_BIT;
  colour.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;  // the caller filled the image before the pass
  colour.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  colour.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  colour.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  colour.initialLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  colour.finalLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
  VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  VkSubpassDescription subpass{};
  subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  subpass.colorAttachmentCount = 1;
  subpass.pColorAttachments = &ref;
  VkSubpassDependency dep{};
  dep.srcSubpass = VK_SUBPASS_EXTERNAL;
  dep.dstSubpass = 0;
  dep.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
  dep.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  dep.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  dep.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  VkRenderPassCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO;
  info.attachmentCount = 1;
  info.pAttachments = &colour;
  info.subpassCount = 1;
  info.pSubpasses = &subpass;
  info.dependencyCount = 1;
  info.pDependencies = &dep;
  if (VkResult r = vkCreateRenderPass(dev(), &info, nullptr, &render_pass); r != VK_SUCCESS)
    return vk_error(r, "vkCreateRenderPass");
  return {};
}

Result<void> Presenter::Impl::create_sync() {
  VkCommandPoolCreateInfo pool_info{};
  pool_info.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
  pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool_info.queueFamilyIndex = state->queue_family_index;
  if (VkResult r = vkCreateCommandPool(dev(), &pool_info, nullptr, &pool); r != VK_SUCCESS)
    return vk_error(r, "vkCreateCommandPool");
  for (SlotSync& s : slots) {
    VkCommandBufferAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
    alloc.commandPool = pool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    if (VkResult r = vkAllocateCommandBuffers(dev(), &alloc, &s.cmd); r != VK_SUCCESS)
      return vk_error(r, "vkAllocateCommandBuffers");
    VkFenceCreateInfo fence{};
    fence.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
    fence.flags = VK_FENCE_CREATE_SIGNALED_BIT;
    if (VkResult r = vkCreateFence(dev(), &fence, nullptr, &s.fence); r != VK_SUCCESS)
      return vk_error(r, "vkCreateFence");
    VkSemaphoreCreateInfo sem{};
    sem.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO;
    if (VkResult r = vkCreateSemaphore(dev(), &sem, nullptr, &s.acquired); r != VK_SUCCESS)
      return vk_error(r, "vkCreateSemaphore");
  }
  return {};
}

Result<void> Presenter::Impl::create_swapchain(uint32_t width, uint32_t height) {
  VkPhysicalDevice pd = state->physical_device;
  VkSurfaceCapabilitiesKHR caps{};
  if (VkResult r = vkGetPhysicalDeviceSurfaceCapabilitiesKHR(pd, state->surface, &caps); r != VK_SUCCESS)
    return vk_error(r, "vkGetPhysicalDeviceSurfaceCapabilitiesKHR");
  const VkImageUsageFlags usage =
      VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  if ((caps.supportedUsageFlags & usage) != usage)
    return Error{Errc::missing_feature, VK_SUCCESS,
                 "the window surface cannot be a transfer source and destination (needed for drawing and screenshots)"};
  const VkExtent2D size = choose_extent(caps, width, height);
  if (size.width == 0 || size.height == 0) return {};  // minimised: keep the old swapchain
  VkSwapchainCreateInfoKHR info{};
  info.sType = VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR;
  info.surface = state->surface;
  info.minImageCount = choose_image_count(caps);
  info.imageFormat = format.format;
  info.imageColorSpace = format.colorSpace;
  info.imageExtent = size;
  info.imageArrayLayers = 1;
  info.imageUsage = usage;
  info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.preTransform = (caps.supportedTransforms & VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR) != 0
                          ? VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR
                          : caps.currentTransform;
  info.compositeAlpha = (caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR) != 0
                            ? VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR
                            : VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR;
  info.presentMode = present_mode;
  info.clipped = VK_TRUE;
  info.oldSwapchain = swapchain;
  VkSwapchainKHR created = VK_NULL_HANDLE;
  if (VkResult r = vkCreateSwapchainKHR(dev(), &info, nullptr, &created); r != VK_SUCCESS)
    return vk_error(r, "vkCreateSwapchainKHR");
  destroy_swapchain_parts();
  if (swapchain != VK_NULL_HANDLE) vkDestroySwapchainKHR(dev(), swapchain, nullptr);
  swapchain = created;
  extent = size;
  min_images = info.minImageCount;
  ++generation;
  stale = false;
  return create_image_parts();
}

Result<void> Presenter::Impl::create_image_parts() {
  uint32_t count = 0;
  if (VkResult r = vkGetSwapchainImagesKHR(dev(), swapchain, &count, nullptr); r != VK_SUCCESS)
    return vk_error(r, "vkGetSwapchainImagesKHR");
  images.resize(count);
  if (VkResult r = vkGetSwapchainImagesKHR(dev(), swapchain, &count, images.data()); r != VK_SUCCESS)
    return vk_error(r, "vkGetSwapchainImagesKHR");
  return create_views();
}

// A view, a framebuffer and a "rendered" semaphore for each of `images`.
Result<void> Presenter::Impl::create_views() {
  for (VkImage image : images) {
    VkImageViewCreateInfo view{};
    view.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO;
    view.image = image;
    view.viewType = VK_IMAGE_VIEW_TYPE_2D;
    view.format = format.format;
    view.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    VkImageView v = VK_NULL_HANDLE;
    if (VkResult r = vkCreateImageView(dev(), &view, nullptr, &v); r != VK_SUCCESS)
      return vk_error(r, "vkCreateImageView");
    views.push_back(v);
    VkFramebufferCreateInfo fb{};
    fb.sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO;
    fb.renderPass = render_pass;
    fb.attachmentCount = 1;
    fb.pAttachments = &v;
    fb.width = extent.width;
    fb.height = extent.height;
    fb.layers = 1;
    VkFramebuffer f = VK_NULL_HANDLE;
    if (VkResult r = vkCreateFramebuffer(dev(), &fb, nullptr, &f); r != VK_SUCCESS)
      return vk_error(r, "vkCreateFramebuffer");
    framebuffers.push_back(f);
    VkSemaphoreCreateInfo sem{};
    sem.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO;
    VkSemaphore s = VK_NULL_HANDLE;
    if (VkResult r = vkCreateSemaphore(dev(), &sem, nullptr, &s); r != VK_SUCCESS)
      return vk_error(r, "vkCreateSemaphore");
    rendered.push_back(s);
  }
  return {};
}

// Decides the presentation path: MIT-SHM for a CPU device on an X11 window
// whose server shares memory with us, else the swapchain (with the reason in
// `presentation`). On success `format` and `shm` are set, with a segment for
// width x height.
bool Presenter::Impl::try_shm(const PresenterOptions& wanted, uint32_t width, uint32_t height) {
  if (wanted.x11_display == nullptr || wanted.x11_window == 0) return false;  // not X11: nothing to say
  if (!wanted.allow_shm) {
    presentation += " (MIT-SHM switched off)";
    return false;
  }
  VkPhysicalDeviceProperties props{};
  vkGetPhysicalDeviceProperties(state->physical_device, &props);
  if (props.deviceType != VK_PHYSICAL_DEVICE_TYPE_CPU) return false;  // a GPU's swapchain is its fast path
#ifdef CMR_HAVE_XSHM
  VkFormatProperties fp{};
  vkGetPhysicalDeviceFormatProperties(state->physical_device, VK_FORMAT_B8G8R8A8_UNORM, &fp);
  const VkFormatFeatureFlags need = VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT | VK_FORMAT_FEATURE_TRANSFER_SRC_BIT |
                                    VK_FORMAT_FEATURE_TRANSFER_DST_BIT;
  if ((fp.optimalTilingFeatures & need) != need) {
    presentation += " (MIT-SHM: the device cannot draw B8G8R8A8)";
    return false;
  }
  std::string why;
  std::unique_ptr<detail::XShmTarget> target =
      detail::XShmTarget::open(wanted.x11_display, wanted.x11_window, why);
  if (target && width > 0 && height > 0 && !target->resize(width, height, why)) target.reset();
  if (!target) {
    presentation += " (MIT-SHM not used: " + why + ")";
    return false;
  }
  shm = std::move(target);
  format = {VK_FORMAT_B8G8R8A8_UNORM, VK_COLOR_SPACE_SRGB_NONLINEAR_KHR};  // the bytes of a BGRX X visual
  presentation = "presented through MIT-SHM (offscreen image, XShmPutImage)";
  return true;
#else
  (void)width;
  (void)height;
  presentation += " (built without libXext: no MIT-SHM)";
  return false;
#endif
}

// The MIT-SHM path's frame image: one offscreen image of `format` (frames
// are finished before end_frame returns, so one is enough), and the shared
// segment resized to match.
Result<void> Presenter::Impl::create_offscreen(uint32_t width, uint32_t height, bool resize_shm) {
  if (width == 0 || height == 0) return {};  // minimised: keep the old image
  destroy_swapchain_parts();
  destroy_offscreen();
  extent = {0, 0};
  if (resize_shm) {
    std::string why;
    if (!shm->resize(width, height, why)) return Error{Errc::other, VK_SUCCESS, "MIT-SHM presentation: " + why};
  }
  VkImageCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO;
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format.format;
  info.extent = {width, height, 1};
  info.mipLevels = 1;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  if (VkResult r = vkCreateImage(dev(), &info, nullptr, &offscreen); r != VK_SUCCESS)
    return vk_error(r, "vkCreateImage (offscreen frame)");
  VkMemoryRequirements req{};
  vkGetImageMemoryRequirements(dev(), offscreen, &req);
  const std::optional<uint32_t> type =
      detail::find_memory_type(state->memory, req.memoryTypeBits, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  if (!type) return Error{Errc::missing_feature, VK_SUCCESS, "no memory type for the offscreen frame"};
  VkMemoryAllocateInfo alloc{};
  alloc.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex = *type;
  if (VkResult r = vkAllocateMemory(dev(), &alloc, nullptr, &offscreen_memory); r != VK_SUCCESS)
    return vk_error(r, "vkAllocateMemory (offscreen frame)");
  if (VkResult r = vkBindImageMemory(dev(), offscreen, offscreen_memory, 0); r != VK_SUCCESS)
    return vk_error(r, "vkBindImageMemory (offscreen frame)");
  images = {offscreen};
  extent = {width, height};
  min_images = 2;
  ++generation;
  stale = false;
  return create_views();
}

Result<void> Presenter::Impl::ensure_readback(VkDeviceSize size) {
  if (readback.size >= size) return {};
  free_readback();
  return detail::create_buffer(*state, readback, size, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                               VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                               VK_MEMORY_PROPERTY_HOST_CACHED_BIT, "the screenshot readback");
}

// After the render pass (image in PRESENT_SRC): copy it to the readback
// buffer, tightly packed, and give it back to presentation.
void Presenter::Impl::record_readback(const PresentFrame& frame) const {
  image_barrier(frame.cmd, frame.image, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT,
                VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {frame.extent.width, frame.extent.height, 1};
  vkCmdCopyImageToBuffer(frame.cmd, frame.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback.buffer, 1, &region);
  image_barrier(frame.cmd, frame.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
                VK_ACCESS_TRANSFER_READ_BIT, 0, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
  buffer_barrier(frame.cmd, readback.buffer, 0, VK_WHOLE_SIZE, VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_HOST_READ_BIT,
                 VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT);
}

Result<Presenter> Presenter::create(Context& context, uint32_t width, uint32_t height,
                                    const PresenterOptions& options) {
  if (context.surface() == VK_NULL_HANDLE)
    return Error{Errc::missing_feature, VK_SUCCESS, "the Vulkan context was made without a window surface"};
  auto impl = std::make_unique<Impl>();
  impl->state = context.state();
  impl->options = options;
  if (impl->try_shm(options, width, height)) {
    if (auto r = impl->create_render_pass(); !r) return r.error();
    if (auto r = impl->create_sync(); !r) return r.error();
    if (auto r = impl->create_offscreen(width, height, false); !r) return r.error();
    return Presenter(std::move(impl));
  }
  if (auto r = impl->choose_surface_format(); !r) return r.error();
  uint32_t mode_count = 0;
  VkPhysicalDevice pd = impl->state->physical_device;
  vkGetPhysicalDeviceSurfacePresentModesKHR(pd, impl->state->surface, &mode_count, nullptr);
  std::vector<VkPresentModeKHR> modes(mode_count);
  vkGetPhysicalDeviceSurfacePresentModesKHR(pd, impl->state->surface, &mode_count, modes.data());
  impl->present_mode = VK_PRESENT_MODE_FIFO_KHR;  // always supported
  if (!options.vsync) {
    for (VkPresentModeKHR wanted : {VK_PRESENT_MODE_MAILBOX_KHR, VK_PRESENT_MODE_IMMEDIATE_KHR}) {
      if (std::find(modes.begin(), modes.end(), wanted) != modes.end()) impl->present_mode = wanted;
    }
  }
  if (auto r = impl->create_render_pass(); !r) return r.error();
  if (auto r = impl->create_sync(); !r) return r.error();
  if (auto r = impl->create_swapchain(width, height); !r) return r.error();
  return Presenter(std::move(impl));
}

Result<std::optional<PresentFrame>> Presenter::begin_frame(uint32_t width, uint32_t height) {
  Impl& m = *impl_;
  SlotSync& s = m.slots[m.slot];
  if (VkResult r = vkWaitForFences(m.dev(), 1, &s.fence, VK_TRUE, kFenceTimeoutNs); r != VK_SUCCESS)
    return r == VK_TIMEOUT ? Error{Errc::device_lost, r, "a frame did not finish within two minutes"}
                           : vk_error(r, "vkWaitForFences");
  if (width == 0 || height == 0) return std::optional<PresentFrame>{};
  if (m.shm) {
    if (width != m.extent.width || height != m.extent.height) {
      vkDeviceWaitIdle(m.dev());
      if (auto r = m.create_offscreen(width, height, true); !r) return r.error();
    }
    if (VkResult rr = vkResetFences(m.dev(), 1, &s.fence); rr != VK_SUCCESS) return vk_error(rr, "vkResetFences");
    vkResetCommandBuffer(s.cmd, 0);
    if (auto rr = detail::begin_one_time(s.cmd); !rr) return rr.error();
    return std::optional<PresentFrame>{PresentFrame{s.cmd, m.offscreen, m.extent, 0, m.slot}};
  }
  if (m.stale || m.swapchain == VK_NULL_HANDLE || width != m.extent.width || height != m.extent.height) {
    vkDeviceWaitIdle(m.dev());
    if (auto r = m.create_swapchain(width, height); !r) return r.error();
  }
  uint32_t index = 0;
  VkResult r = vkAcquireNextImageKHR(m.dev(), m.swapchain, kFenceTimeoutNs, s.acquired, VK_NULL_HANDLE, &index);
  if (r == VK_ERROR_OUT_OF_DATE_KHR) {  // once more with a fresh swapchain
    vkDeviceWaitIdle(m.dev());
    if (auto c = m.create_swapchain(width, height); !c) return c.error();
    r = vkAcquireNextImageKHR(m.dev(), m.swapchain, kFenceTimeoutNs, s.acquired, VK_NULL_HANDLE, &index);
  }
  if (r == VK_SUBOPTIMAL_KHR) m.stale = true;  // usable now, recreate next frame
  else if (r != VK_SUCCESS) return vk_error(r, "vkAcquireNextImageKHR");
  if (VkResult rr = vkResetFences(m.dev(), 1, &s.fence); rr != VK_SUCCESS) return vk_error(rr, "vkResetFences");
  vkResetCommandBuffer(s.cmd, 0);
  if (auto rr = detail::begin_one_time(s.cmd); !rr) return rr.error();
  return std::optional<PresentFrame>{PresentFrame{s.cmd, m.images[index], m.extent, index, m.slot}};
}

void Presenter::to_transfer_dst(const PresentFrame& frame) const {
  image_barrier(frame.cmd, frame.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0,
                VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
}

void Presenter::to_attachment(const PresentFrame& frame, bool from_transfer) const {
  image_barrier(frame.cmd, frame.image,
                from_transfer ? VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED,
                VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, from_transfer ? VK_ACCESS_TRANSFER_WRITE_BIT : 0,
                VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                from_transfer ? VK_PIPELINE_STAGE_TRANSFER_BIT : VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
                VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT);
}

void Presenter::begin_pass(const PresentFrame& frame) const {
  VkRenderPassBeginInfo info{};
  info.sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO;
  info.renderPass = impl_->render_pass;
  info.framebuffer = impl_->framebuffers[frame.image_index];
  info.renderArea = {{0, 0}, frame.extent};
  vkCmdBeginRenderPass(frame.cmd, &info, VK_SUBPASS_CONTENTS_INLINE);
}

Result<void> Presenter::end_frame(const PresentFrame& frame, Screenshot* screenshot) {
  Impl& m = *impl_;
  SlotSync& s = m.slots[frame.slot];
  vkCmdEndRenderPass(frame.cmd);
  // What the frame's shaders wrote to buffers (a region drawer's list of
  // uncertain pixels) is visible to the host once the slot's fence signals.
  VkMemoryBarrier to_host{};
  to_host.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  to_host.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  to_host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(frame.cmd, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &to_host, 0,
                       nullptr, 0, nullptr);
  const VkDeviceSize bytes = VkDeviceSize{frame.extent.width} * frame.extent.height * 4;
  if (m.shm) {
    // Read the frame back, wait for it, and put it into the window.
    if (auto r = m.ensure_readback(bytes); !r) {
      vkEndCommandBuffer(frame.cmd);
      return r.error();
    }
    m.record_readback(frame);
    if (VkResult r = vkEndCommandBuffer(frame.cmd); r != VK_SUCCESS) return vk_error(r, "vkEndCommandBuffer");
    if (auto r = detail::submit(m.state->queue, frame.cmd, s.fence); !r) return r.error();
    m.slot = (m.slot + 1) % kFramesInFlight;
    if (VkResult r = vkWaitForFences(m.dev(), 1, &s.fence, VK_TRUE, kFenceTimeoutNs); r != VK_SUCCESS)
      return r == VK_TIMEOUT ? Error{Errc::device_lost, r, "a frame did not finish within two minutes"}
                             : vk_error(r, "vkWaitForFences");
#ifdef CMR_HAVE_XSHM
    m.shm->put(m.readback.mapped, frame.extent.width, frame.extent.height);
#endif
    if (screenshot != nullptr) m.copy_screenshot(frame.extent, *screenshot);
    return {};
  }
  if (screenshot != nullptr) {
    if (auto r = m.ensure_readback(bytes); !r) {
      vkEndCommandBuffer(frame.cmd);
      return r.error();
    }
    m.record_readback(frame);
  }
  if (VkResult r = vkEndCommandBuffer(frame.cmd); r != VK_SUCCESS) return vk_error(r, "vkEndCommandBuffer");
  const VkPipelineStageFlags wait_stage = VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  VkSemaphore done = m.rendered[frame.image_index];
  VkSubmitInfo submit{};
  submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
  submit.waitSemaphoreCount = 1;
  submit.pWaitSemaphores = &s.acquired;
  submit.pWaitDstStageMask = &wait_stage;
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &frame.cmd;
  submit.signalSemaphoreCount = 1;
  submit.pSignalSemaphores = &done;
  if (VkResult r = vkQueueSubmit(m.state->queue, 1, &submit, s.fence); r != VK_SUCCESS)
    return vk_error(r, "vkQueueSubmit");
  VkPresentInfoKHR present{};
  present.sType = VK_STRUCTURE_TYPE_PRESENT_INFO_KHR;
  present.waitSemaphoreCount = 1;
  present.pWaitSemaphores = &done;
  present.swapchainCount = 1;
  present.pSwapchains = &m.swapchain;
  present.pImageIndices = &frame.image_index;
  const VkResult pr = vkQueuePresentKHR(m.state->queue, &present);
  if (pr == VK_ERROR_OUT_OF_DATE_KHR || pr == VK_SUBOPTIMAL_KHR) m.stale = true;
  else if (pr != VK_SUCCESS) return vk_error(pr, "vkQueuePresentKHR");
  m.slot = (m.slot + 1) % kFramesInFlight;
  if (screenshot == nullptr) return {};
  if (VkResult r = vkWaitForFences(m.dev(), 1, &s.fence, VK_TRUE, kFenceTimeoutNs); r != VK_SUCCESS)
    return vk_error(r, "vkWaitForFences (screenshot)");
  m.copy_screenshot(frame.extent, *screenshot);
  return {};
}

// The read-back frame (after its fence) as RGBA.
void Presenter::Impl::copy_screenshot(VkExtent2D size, Screenshot& out) const {
  const std::size_t bytes = std::size_t{size.width} * size.height * 4;
  out.width = size.width;
  out.height = size.height;
  out.rgba.resize(bytes);
  std::memcpy(out.rgba.data(), readback.mapped, bytes);
  if (format.format == VK_FORMAT_B8G8R8A8_UNORM) {
    for (std::size_t i = 0; i < out.rgba.size(); i += 4) std::swap(out.rgba[i], out.rgba[i + 2]);
  }
}

Result<void> Presenter::submit_once(const std::function<void(VkCommandBuffer)>& record) {
  Impl& m = *impl_;
  SlotSync& s = m.slots[m.slot];
  if (VkResult r = vkWaitForFences(m.dev(), 1, &s.fence, VK_TRUE, kFenceTimeoutNs); r != VK_SUCCESS)
    return vk_error(r, "vkWaitForFences");
  vkResetFences(m.dev(), 1, &s.fence);
  vkResetCommandBuffer(s.cmd, 0);
  if (auto r = detail::begin_one_time(s.cmd); !r) return r.error();
  record(s.cmd);
  if (VkResult r = vkEndCommandBuffer(s.cmd); r != VK_SUCCESS) return vk_error(r, "vkEndCommandBuffer");
  if (auto r = detail::submit(m.state->queue, s.cmd, s.fence); !r) return r.error();
  if (VkResult r = vkWaitForFences(m.dev(), 1, &s.fence, VK_TRUE, kFenceTimeoutNs); r != VK_SUCCESS)
    return vk_error(r, "vkWaitForFences");
  return {};
}

void Presenter::wait_idle() const { vkDeviceWaitIdle(impl_->dev()); }

Presenter::Presenter(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Presenter::Presenter(Presenter&&) noexcept = default;
Presenter& Presenter::operator=(Presenter&&) noexcept = default;
Presenter::~Presenter() = default;

VkRenderPass Presenter::render_pass() const { return impl_->render_pass; }
VkFormat Presenter::format() const { return impl_->format.format; }
VkExtent2D Presenter::extent() const { return impl_->extent; }
uint32_t Presenter::image_count() const { return static_cast<uint32_t>(impl_->images.size()); }
uint32_t Presenter::min_image_count() const { return impl_->min_images; }
VkPresentModeKHR Presenter::present_mode() const { return impl_->present_mode; }
int Presenter::generation() const { return impl_->generation; }
bool Presenter::shm() const { return impl_->shm != nullptr; }
const std::string& Presenter::presentation() const { return impl_->presentation; }

}  // namespace cmr::vk
