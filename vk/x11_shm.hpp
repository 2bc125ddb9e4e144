// Internal to cmr::vk: a window's pixels handed to the X server through the
// MIT-SHM extension (XShmPutImage from a shared-memory segment), for CPU
// Vulkan devices whose X11 swapchain sends each frame through the X socket.
// Built only when CMake finds libX11 and libXext (CMR_HAVE_XSHM).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

namespace cmr::vk::detail {

class XShmTarget {
 public:
  /// `display` is an Xlib Display*, `window` an X Window. nullptr, with the
  /// reason in `why_not`, when the server lacks MIT-SHM or the window's
  /// visual is not 24-bit TrueColor with BGRX bytes (then: swapchain).
  static std::unique_ptr<XShmTarget> open(void* display, unsigned long window, std::string& why_not);
  ~XShmTarget();
  XShmTarget(const XShmTarget&) = delete;
  XShmTarget& operator=(const XShmTarget&) = delete;

  /// (Re)creates the shared-memory image for width x height; the segment is
  /// marked for removal (IPC_RMID) as soon as the server has attached it.
  /// false, with the reason, when shmget/shmat/XShmAttach fail (an X error
  /// handler catches the server's refusal, e.g. a remote display).
  bool resize(uint32_t width, uint32_t height, std::string& why_not);
  /// Copies width x height tightly packed B8G8R8A8 pixels into the segment,
  /// puts them at the window's origin and waits until the server has read
  /// them (XSync), so the segment can be rewritten at once.
  void put(const void* bgra, uint32_t width, uint32_t height);

 private:
  struct Impl;
  explicit XShmTarget(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace cmr::vk::detail
