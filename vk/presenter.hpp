// Presentation to a window surface: a swapchain on the Context's surface
// (ContextOptions::make_surface), one render pass that draws over what the
// frame already holds, frames in flight, recreation when the window changes
// size or the swapchain goes out of date, and an exact readback of the
// presented image (screenshots).
//
// A frame:
//   begin_frame()      acquire an image, begin the command buffer; the image
//                      is in an undefined layout
//   (caller)           either to_transfer_dst() + copies + to_attachment(),
//                      or to_attachment() alone (then draw everything)
//   begin_pass()       the render pass (load: keeps what is there)
//   (caller)           draws (region pipeline, ImGui)
//   end_frame()        end the pass, make shader buffer writes visible to the
//                      host (after the slot's fence), optionally copy the
//                      image to host memory, submit, present
//
// The swapchain format is 8-bit UNORM (B8G8R8A8 or R8G8B8A8), never sRGB, so
// the bytes written are the bytes presented and read back. Usage includes
// TRANSFER_DST (uploads beneath the UI) and TRANSFER_SRC (readback).
//
// On a CPU device with an X11 window (PresenterOptions::x11_display), the
// frame's image is an offscreen image of the same format, and end_frame
// copies it to host memory, waits for it and puts it into the window through
// MIT-SHM; the swapchain is the fallback (no MIT-SHM, XShmAttach refused, not
// X11, a real GPU). presentation() says which path is used.
//
// Thread safety: as for Context.
#pragma once

#include "vk/context.hpp"
#include "vk/error.hpp"

#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace cmr::vk {

struct PresenterOptions {
  /// false: prefer IMMEDIATE, then MAILBOX (frame rate not tied to the
  /// display, for benchmarks); true: FIFO (always available).
  bool vsync = true;
  /// The window's X11 Display* and Window (e.g. glfwGetX11Display(),
  /// glfwGetX11Window()), or null/0 when not on X11. With both, a CPU device
  /// (lavapipe) presents through MIT-SHM instead of the swapchain: frames go
  /// to an offscreen image, are copied to host memory and put into the window
  /// with XShmPutImage (lavapipe's X11 swapchain sends every frame through
  /// the X socket). Real GPUs always use the swapchain.
  void* x11_display = nullptr;
  unsigned long x11_window = 0;
  /// false: never MIT-SHM (the swapchain, for comparisons and tests).
  bool allow_shm = true;
};

/// One frame being recorded.
struct PresentFrame {
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VkImage image = VK_NULL_HANDLE;
  VkExtent2D extent{};
  uint32_t image_index = 0;
  uint32_t slot = 0;  ///< frame-in-flight index, 0..frames_in_flight()-1
};

/// RGBA8 pixels, row-major, row 0 at the top.
struct Screenshot {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgba;
};

/// How many swapchain images to ask for, given the surface's limits: one more
/// than the minimum, capped by maxImageCount unless that is 0 (no limit).
uint32_t choose_image_count(const VkSurfaceCapabilitiesKHR& caps);

/// The swapchain extent: the surface's currentExtent, or, when that is the
/// special value 0xFFFFFFFF (the size follows the swapchain), the window's
/// framebuffer size clamped to the allowed range.
VkExtent2D choose_extent(const VkSurfaceCapabilitiesKHR& caps, uint32_t width, uint32_t height);

class Presenter {
 public:
  static constexpr uint32_t kFramesInFlight = 2;

  /// Errors: missing_feature (the Context has no surface; no UNORM 8-bit
  ///   format; the surface cannot be a transfer source/destination);
  ///   out_of_memory; device_lost; other.
  static Result<Presenter> create(Context& context, uint32_t width, uint32_t height,
                                  const PresenterOptions& options = {});

  Presenter(Presenter&&) noexcept;
  Presenter& operator=(Presenter&&) noexcept;
  Presenter(const Presenter&) = delete;
  Presenter& operator=(const Presenter&) = delete;
  ~Presenter();

  /// Waits for the frame slot, acquires an image (recreating the swapchain
  /// for (width, height) when it is out of date or the size changed) and
  /// begins its command buffer. nullopt when the window has zero size
  /// (minimised): skip the frame.
  Result<std::optional<PresentFrame>> begin_frame(uint32_t width, uint32_t height);
  /// Layout barriers for the frame's image: undefined -> transfer dst, and
  /// (from undefined or transfer dst) -> colour attachment.
  void to_transfer_dst(const PresentFrame& frame) const;
  void to_attachment(const PresentFrame& frame, bool from_transfer) const;
  /// Begins the render pass on the frame's image (contents kept).
  void begin_pass(const PresentFrame& frame) const;
  /// Ends the pass, submits and presents. With `screenshot`, the presented
  /// image is copied to host memory in the same submission and returned
  /// (waits for the GPU).
  Result<void> end_frame(const PresentFrame& frame, Screenshot* screenshot = nullptr);

  /// Records commands into a one-time command buffer, submits and waits
  /// (uploads at start-up).
  Result<void> submit_once(const std::function<void(VkCommandBuffer)>& record);
  /// Waits until the device is idle (before destroying resources in use).
  void wait_idle() const;

  VkRenderPass render_pass() const;
  VkFormat format() const;
  VkExtent2D extent() const;
  uint32_t image_count() const;
  uint32_t min_image_count() const;
  VkPresentModeKHR present_mode() const;
  /// Times the swapchain (or the offscreen image) has been (re)created, the
  /// first time included.
  int generation() const;
  /// true when frames are put into the window through MIT-SHM.
  bool shm() const;
  /// One line: "presented through MIT-SHM" or "presented through the Vulkan
  /// swapchain" (with why MIT-SHM is not used, when it was considered).
  const std::string& presentation() const;

 private:
  struct Impl;
  explicit Presenter(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace cmr::vk
