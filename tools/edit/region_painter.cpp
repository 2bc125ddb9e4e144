#include "tools/edit/region_painter.hpp"

#include <algorithm>
#include <array>
#include <cstring>

#include "spline/parallel.hpp"
#include "vk/region_draw.hpp"

namespace cmr::edit {
namespace {

vk::Error fail(VkResult r, const std::string& what) {
  return vk::Error{r == VK_ERROR_OUT_OF_HOST_MEMORY || r == VK_ERROR_OUT_OF_DEVICE_MEMORY ? vk::Errc::out_of_memory
                                                                                           : vk::Errc::other,
                   r, what + " failed (VkResult " + std::to_string(static_cast<int>(r)) + ")"};
}

/// One host-visible staging buffer per frame in flight: the colour bytes are
/// copied in when they changed since that slot last held them.
class UploadPainter final : public RegionPainter {
 public:
  UploadPainter(vk::Context& context, vk::Presenter& presenter) : context_(context), presenter_(presenter) {}
  ~UploadPainter() override {
    presenter_.wait_idle();
    for (Staging& s : staging_) release(s);
  }
  UploadPainter(const UploadPainter&) = delete;
  UploadPainter& operator=(const UploadPainter&) = delete;

  std::string describe() const override {
    return "region: certified CPU engine on " + std::to_string(thread_count(0)) +
           " threads, uploaded beneath the UI (device '" + context_.device().name + "' is a CPU)";
  }

  vk::Result<void> record(Editor& editor, const vk::PresentFrame& frame) override {
    bool changed = false;
    const std::vector<uint8_t>& rgba = editor.region_rgba(&changed);
    if (changed) ++version_;
    const VkDeviceSize bytes = VkDeviceSize{frame.extent.width} * frame.extent.height * 4;
    if (rgba.size() != bytes) {
      return vk::Error{vk::Errc::other, VK_SUCCESS, "region image does not match the window size"};
    }
    Staging& s = staging_[frame.slot];
    if (auto r = ensure(s, bytes); !r) return r.error();
    if (s.version != version_) {
      fill(s, rgba);
      s.version = version_;
    }
    presenter_.to_transfer_dst(frame);
    VkBufferImageCopy copy{};
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    copy.imageExtent = {frame.extent.width, frame.extent.height, 1};
    vkCmdCopyBufferToImage(frame.cmd, s.buffer, frame.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
    presenter_.to_attachment(frame, true);
    return {};
  }

 private:
  struct Staging {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    void* mapped = nullptr;
    VkDeviceSize size = 0;
    uint64_t version = 0;
  };

  void release(Staging& s) {
    VkDevice dev = context_.device_handle();
    if (s.memory != VK_NULL_HANDLE) vkFreeMemory(dev, s.memory, nullptr);  // unmaps too
    if (s.buffer != VK_NULL_HANDLE) vkDestroyBuffer(dev, s.buffer, nullptr);
    s = {};
  }

  vk::Result<void> ensure(Staging& s, VkDeviceSize bytes) {
    if (s.size == bytes) return {};
    presenter_.wait_idle();
    release(s);
    VkDevice dev = context_.device_handle();
    VkBufferCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
    info.size = bytes;
    info.usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    if (VkResult r = vkCreateBuffer(dev, &info, nullptr, &s.buffer); r != VK_SUCCESS) return fail(r, "vkCreateBuffer");
    VkMemoryRequirements req{};
    vkGetBufferMemoryRequirements(dev, s.buffer, &req);
    VkPhysicalDeviceMemoryProperties props{};
    vkGetPhysicalDeviceMemoryProperties(context_.physical_device(), &props);
    const VkMemoryPropertyFlags want = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    uint32_t type = props.memoryTypeCount;
    for (uint32_t i = 0; i < props.memoryTypeCount && type == props.memoryTypeCount; ++i) {
      if ((req.memoryTypeBits & (1u << i)) != 0 && (props.memoryTypes[i].propertyFlags & want) == want) type = i;
    }
    if (type == props.memoryTypeCount)
      return vk::Error{vk::Errc::out_of_memory, VK_SUCCESS, "no host-visible memory for the region upload"};
    VkMemoryAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex = type;
    if (VkResult r = vkAllocateMemory(dev, &alloc, nullptr, &s.memory); r != VK_SUCCESS)
      return fail(r, "vkAllocateMemory");
    if (VkResult r = vkBindBufferMemory(dev, s.buffer, s.memory, 0); r != VK_SUCCESS)
      return fail(r, "vkBindBufferMemory");
    if (VkResult r = vkMapMemory(dev, s.memory, 0, bytes, 0, &s.mapped); r != VK_SUCCESS)
      return fail(r, "vkMapMemory");
    s.size = bytes;
    s.version = 0;
    return {};
  }

  /// RGBA into the swapchain's byte order.
  void fill(Staging& s, const std::vector<uint8_t>& rgba) const {
    auto* out = static_cast<uint8_t*>(s.mapped);
    if (presenter_.format() != VK_FORMAT_B8G8R8A8_UNORM) {
      std::memcpy(out, rgba.data(), rgba.size());
      return;
    }
    for (std::size_t i = 0; i < rgba.size(); i += 4) {
      out[i] = rgba[i + 2];
      out[i + 1] = rgba[i + 1];
      out[i + 2] = rgba[i];
      out[i + 3] = rgba[i + 3];
    }
  }

  vk::Context& context_;
  vk::Presenter& presenter_;
  std::array<Staging, vk::Presenter::kFramesInFlight> staging_{};
  uint64_t version_ = 1;
};

/// The gpu path: every canvas pixel shaded into the swapchain image.
class GpuPainter final : public RegionPainter {
 public:
  GpuPainter(vk::Context& context, vk::Presenter& presenter, vk::RegionDrawer drawer)
      : context_(context), presenter_(presenter), drawer_(std::move(drawer)), upload_(context, presenter) {}
  ~GpuPainter() override { presenter_.wait_idle(); }

  std::string describe() const override {
    return std::string("region: certified ") + (drawer_.precision() == vk::RegionPrecision::fp64 ? "fp64" : "fp32") +
           " region shader drawn into the window on '" + context_.device().name +
           "' (uncertain pixels decided on the host)";
  }

  vk::Result<void> record(Editor& editor, const vk::PresentFrame& frame) override {
    drawing_ = !editor.doc().depth_shading;
    if (!drawing_) return upload_.record(editor, frame);  // Fig. 7 shading: the CPU colours
    // Problems by exact key: an unchanged layer keeps its prepared state
    // (and the labels the host decided for it).
    const BSpline spline = editor.region_spline();
    std::vector<RegionProblem> layers;
    std::vector<std::pair<std::vector<double>, RegionProblem>> kept;
    for (const RegionRequest& r : editor.region_requests()) {
      std::vector<double> key = region_key(spline, r);
      const auto it = std::find_if(problems_.begin(), problems_.end(), [&](const auto& p) { return p.first == key; });
      RegionProblem p = it != problems_.end() ? it->second : RegionProblem::make(spline, r);
      layers.push_back(p);
      kept.emplace_back(std::move(key), std::move(p));
    }
    problems_ = std::move(kept);
    if (auto r = drawer_.prepare(frame.slot, layers); !r) return r.error();
    presenter_.to_transfer_dst(frame);
    const VkClearColorValue white{{1.0f, 1.0f, 1.0f, 1.0f}};
    const VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(frame.cmd, frame.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &white, 1, &all);
    presenter_.to_attachment(frame, true);
    return {};
  }

  void draw(const vk::PresentFrame& frame) override {
    if (drawing_) drawer_.draw(frame.cmd, frame.slot, frame.extent);
  }

  std::string summary() const override {
    return "region shader: " + std::to_string(drawer_.host_pixels()) + " pixels decided on the host";
  }

 private:
  vk::Context& context_;
  vk::Presenter& presenter_;
  vk::RegionDrawer drawer_;
  UploadPainter upload_;
  std::vector<std::pair<std::vector<double>, RegionProblem>> problems_;
  bool drawing_ = false;
};

}  // namespace

vk::Result<std::unique_ptr<RegionPainter>> make_painter(vk::Context& context, vk::Presenter& presenter,
                                                        RegionPath path, std::optional<vk::RegionPrecision> precision) {
  const vk::DeviceInfo& d = context.device();
  const bool gpu = path == RegionPath::gpu ||
                   (path == RegionPath::automatic && d.type != VK_PHYSICAL_DEVICE_TYPE_CPU && d.fragment_stores);
  if (!gpu) return std::unique_ptr<RegionPainter>(std::make_unique<UploadPainter>(context, presenter));
  auto drawer = vk::RegionDrawer::create(context, presenter.render_pass(), vk::Presenter::kFramesInFlight, precision);
  if (!drawer) return drawer.error();
  return std::unique_ptr<RegionPainter>(std::make_unique<GpuPainter>(context, presenter, drawer.take()));
}

}  // namespace cmr::edit
