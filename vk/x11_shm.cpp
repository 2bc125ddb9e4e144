#include "vk/x11_shm.hpp"

#ifdef CMR_HAVE_XSHM

#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <X11/extensions/XShm.h>
#include <sys/ipc.h>
#include <sys/shm.h>

#include <cerrno>
#include <cstring>
#include <utility>

namespace cmr::vk::detail {

namespace {

// Set by the handler below while XShmAttach is checked; Xlib calls handlers
// on the thread that reads the reply, the one calling XSync here.
bool g_x_error = false;
int note_x_error(Display*, XErrorEvent*) {
  g_x_error = true;
  return 0;
}

}  // namespace

struct XShmTarget::Impl {
  Display* display = nullptr;
  Window window = 0;
  Visual* visual = nullptr;
  int depth = 0;
  GC gc = nullptr;
  XImage* image = nullptr;
  XShmSegmentInfo info{};
  bool attached = false;

  void release() {
    if (attached) {
      XShmDetach(display, &info);
      XSync(display, False);
      attached = false;
    }
    if (image != nullptr) {
      image->data = nullptr;  // the segment's memory, not Xlib's
      XDestroyImage(image);
      image = nullptr;
    }
    if (info.shmaddr != nullptr) {
      shmdt(info.shmaddr);
      info.shmaddr = nullptr;
    }
    info.shmid = -1;
  }
  ~Impl() {
    release();
    if (gc != nullptr) XFreeGC(display, gc);
  }
};

XShmTarget::XShmTarget(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
XShmTarget::~XShmTarget() = default;

std::unique_ptr<XShmTarget> XShmTarget::open(void* display_ptr, unsigned long window, std::string& why_not) {
  auto* display = static_cast<Display*>(display_ptr);
  if (display == nullptr || window == 0) {
    why_not = "not an X11 window";
    return nullptr;
  }
  if (XShmQueryExtension(display) != True) {
    why_not = "the X server has no MIT-SHM";
    return nullptr;
  }
  XWindowAttributes attributes{};
  if (XGetWindowAttributes(display, window, &attributes) == 0) {
    why_not = "XGetWindowAttributes failed";
    return nullptr;
  }
  const Visual* v = attributes.visual;
  if (attributes.depth != 24 || v == nullptr || v->red_mask != 0xff0000 || v->green_mask != 0xff00 ||
      v->blue_mask != 0xff || ImageByteOrder(display) != LSBFirst) {
    why_not = "the window's visual is not 24-bit BGRX";
    return nullptr;
  }
  auto impl = std::make_unique<Impl>();
  impl->display = display;
  impl->window = window;
  impl->visual = attributes.visual;
  impl->depth = attributes.depth;
  impl->info.shmid = -1;
  impl->gc = XCreateGC(display, window, 0, nullptr);
  if (impl->gc == nullptr) {
    why_not = "XCreateGC failed";
    return nullptr;
  }
  return std::unique_ptr<XShmTarget>(new XShmTarget(std::move(impl)));
}

bool XShmTarget::resize(uint32_t width, uint32_t height, std::string& why_not) {
  Impl& m = *impl_;
  m.release();
  m.image = XShmCreateImage(m.display, m.visual, static_cast<unsigned>(m.depth), ZPixmap, nullptr, &m.info, width,
                            height);
  if (m.image == nullptr || m.image->bits_per_pixel != 32) {
    why_not = "XShmCreateImage gave no 32-bit image";
    m.release();
    return false;
  }
  const std::size_t bytes = static_cast<std::size_t>(m.image->bytes_per_line) * height;
  m.info.shmid = shmget(IPC_PRIVATE, bytes, IPC_CREAT | 0600);
  if (m.info.shmid < 0) {
    why_not = std::string("shmget failed: ") + std::strerror(errno);
    m.release();
    return false;
  }
  void* address = shmat(m.info.shmid, nullptr, 0);
  if (address == reinterpret_cast<void*>(-1)) {
    why_not = std::string("shmat failed: ") + std::strerror(errno);
    shmctl(m.info.shmid, IPC_RMID, nullptr);
    m.release();
    return false;
  }
  m.info.shmaddr = static_cast<char*>(address);
  m.image->data = m.info.shmaddr;
  m.info.readOnly = False;
  XSync(m.display, False);  // errors of earlier requests are not ours
  g_x_error = false;
  XErrorHandler previous = XSetErrorHandler(note_x_error);
  const Status status = XShmAttach(m.display, &m.info);
  XSync(m.display, False);
  XSetErrorHandler(previous);
  // Marked for removal now: it lives while the server and we are attached,
  // and goes when both detach or exit.
  shmctl(m.info.shmid, IPC_RMID, nullptr);
  if (status == 0 || g_x_error) {
    why_not = "XShmAttach failed (the X server cannot share memory with this process)";
    m.release();
    return false;
  }
  m.attached = true;
  return true;
}

void XShmTarget::put(const void* bgra, uint32_t width, uint32_t height) {
  Impl& m = *impl_;
  const std::size_t row = std::size_t{width} * 4;
  const auto* src = static_cast<const char*>(bgra);
  if (static_cast<std::size_t>(m.image->bytes_per_line) == row) {
    std::memcpy(m.image->data, src, row * height);
  } else {
    for (uint32_t y = 0; y < height; ++y)
      std::memcpy(m.image->data + static_cast<std::size_t>(m.image->bytes_per_line) * y, src + row * y, row);
  }
  XShmPutImage(m.display, m.window, m.gc, m.image, 0, 0, 0, 0, width, height, False);
  XSync(m.display, False);  // the server has copied the segment: it may be rewritten
}

}  // namespace cmr::vk::detail

#else  // built without libX11/libXext: never MIT-SHM, the swapchain presents

namespace cmr::vk::detail {

struct XShmTarget::Impl {};
XShmTarget::XShmTarget(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
XShmTarget::~XShmTarget() = default;
std::unique_ptr<XShmTarget> XShmTarget::open(void*, unsigned long, std::string& why_not) {
  why_not = "built without libXext";
  return nullptr;
}
bool XShmTarget::resize(uint32_t, uint32_t, std::string& why_not) {
  why_not = "built without libXext";
  return false;
}
void XShmTarget::put(const void*, uint32_t, uint32_t) {}

}  // namespace cmr::vk::detail

#endif
