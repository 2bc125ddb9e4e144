#include "vk/region_draw.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <vector>

#include "region/region_setup.hpp"
#include "shaders/region_layout.h"
#include "vk/internal.hpp"

#include "region_present_fp32_frag.h"
#include "region_present_fp64_frag.h"

namespace cmr::vk {
namespace {

using detail::vk_error;

/// Uncertain pixels one frame can list; more are found again next time.
constexpr uint32_t kUncertainCapacity = 1u << 16;

using detail::Buffer;

/// One layer's buffers and descriptor set for one frame slot.
struct SlotLayer {
  Buffer data, overrides, uncertain;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VkDescriptorSet set = VK_NULL_HANDLE;
  uint64_t version = 0;  ///< host version uploaded
  uint64_t drawn = 0;    ///< serial of the problem the slot last drew (0: none)
  VkPipeline pipeline = VK_NULL_HANDLE;
  uint32_t width = 0, height = 0;
};

/// A layer on the host: its problem and the labels decided here.
struct HostLayer {
  std::optional<RegionProblem> problem;
  std::vector<uint32_t> overrides;  ///< label + 1 per pixel, 0: the shader decides
  uint64_t version = 0;
  uint64_t serial = 0;  ///< which problem (a new one gets the next number)
};

struct PipelineKey {
  int degree, depth;
  bool cmr, joints;
  bool operator==(const PipelineKey&) const = default;
};

}  // namespace

struct RegionDrawer::Impl {
  std::shared_ptr<detail::DeviceState> state;
  VkRenderPass render_pass = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout pipeline_layout = VK_NULL_HANDLE;
  std::vector<std::pair<PipelineKey, VkPipeline>> pipelines;
  RegionPrecision precision = RegionPrecision::fp32;
  std::vector<HostLayer> host;
  std::vector<std::vector<SlotLayer>> slots;  ///< [slot][layer]
  std::vector<std::size_t> drawn_layers;      ///< layers prepared per slot
  uint64_t host_pixels = 0;
  uint64_t serials = 0;

  VkDevice dev() const { return state->device; }

  ~Impl() {
    if (!state) return;
    vkDeviceWaitIdle(dev());
    for (auto& slot : slots)
      for (SlotLayer& l : slot) release(l);
    for (auto& [k, p] : pipelines) vkDestroyPipeline(dev(), p, nullptr);
    if (pipeline_layout != VK_NULL_HANDLE) vkDestroyPipelineLayout(dev(), pipeline_layout, nullptr);
    if (set_layout != VK_NULL_HANDLE) vkDestroyDescriptorSetLayout(dev(), set_layout, nullptr);
  }

  void release(Buffer& b) { detail::destroy_buffer(dev(), b); }
  void release(SlotLayer& l) {
    release(l.data);
    release(l.overrides);
    release(l.uncertain);
    if (l.pool != VK_NULL_HANDLE) vkDestroyDescriptorPool(dev(), l.pool, nullptr);
    l = {};
  }

  /// A host-visible, coherent storage buffer of at least `size` bytes, mapped.
  /// Returns true when it was (re)allocated.
  Result<bool> ensure(Buffer& b, VkDeviceSize size) {
    if (b.size >= size) return false;
    release(b);
    if (auto r = detail::create_buffer(*state, b, size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                       VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                                       VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, "the region draw buffer");
        !r)
      return r.error();
    return true;
  }

  Result<void> write_set(SlotLayer& l) {
    if (l.pool == VK_NULL_HANDLE) {
      if (auto r = detail::create_storage_set(dev(), set_layout, 3, l.pool, l.set, "region draw"); !r)
        return r.error();
    }
    std::array<VkDescriptorBufferInfo, 3> buffers{{{l.data.buffer, 0, l.data.size},
                                                   {l.overrides.buffer, 0, l.overrides.size},
                                                   {l.uncertain.buffer, 0, l.uncertain.size}}};
    detail::write_storage_set(dev(), l.set, buffers);
    return {};
  }

  Result<VkPipeline> pipeline_for(const cmr::backend::RegionSetup& s) {
    const PipelineKey key{s.spline().degree(), s.options.max_depth, s.options.mode == Mode::cmr, !s.varying.empty()};
    for (const auto& [k, p] : pipelines)
      if (k == key) return p;
    const std::array<uint32_t, 4> spec{static_cast<uint32_t>(key.degree), static_cast<uint32_t>(key.depth),
                                       key.cmr ? 1u : 0u, key.joints ? 1u : 0u};
    const std::span<const uint32_t> spirv = precision == RegionPrecision::fp64
                                                ? std::span<const uint32_t>(cmr_region_present_fp64_frag_spv)
                                                : std::span<const uint32_t>(cmr_region_present_fp32_frag_spv);
    // dst - src on colour (absorption from white), alpha kept.
    VkPipelineColorBlendAttachmentState blend{};
    blend.blendEnable = VK_TRUE;
    blend.srcColorBlendFactor = VK_BLEND_FACTOR_ONE;
    blend.dstColorBlendFactor = VK_BLEND_FACTOR_ONE;
    blend.colorBlendOp = VK_BLEND_OP_REVERSE_SUBTRACT;
    blend.srcAlphaBlendFactor = VK_BLEND_FACTOR_ZERO;
    blend.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
    blend.alphaBlendOp = VK_BLEND_OP_ADD;
    blend.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT |
                           VK_COLOR_COMPONENT_A_BIT;
    auto p = detail::create_fullscreen_pipeline(*state, pipeline_layout, render_pass, spirv, spec, blend);
    if (!p) return p.error();
    pipelines.emplace_back(key, p.value());
    return p.value();
  }

  /// The pixels slot's last frame of layer i could not certify, decided here.
  void collect(SlotLayer& l, HostLayer& h) {
    if (l.drawn == 0 || l.drawn != h.serial || l.uncertain.mapped == nullptr) return;
    const auto* words = reinterpret_cast<const uint32_t*>(l.uncertain.mapped);
    const uint32_t count = std::min(words[0], kUncertainCapacity);
    const RegionRequest& r = h.problem->request();
    bool changed = false;
    for (uint32_t n = 0; n < count; ++n) {
      const uint32_t at = words[2 + n];
      if (at >= h.overrides.size() || h.overrides[at] != 0) continue;
      const int i = static_cast<int>(at % r.width), j = static_cast<int>(at / r.width);
      const cmr::backend::PixelResult p =
          cmr::backend::classify_position(h.problem->setup(), pixel_center(*r.view, r.width, r.height, i, j));
      h.overrides[at] = p.label + 1u;
      ++host_pixels;
      changed = true;
    }
    if (changed) ++h.version;
  }
};

Result<RegionDrawer> RegionDrawer::create(Context& context, VkRenderPass render_pass, uint32_t frames_in_flight,
                                          std::optional<RegionPrecision> precision) {
  if (precision == RegionPrecision::fp64 && !context.device().float64)
    return Error{Errc::missing_feature, VK_SUCCESS,
                 "device '" + context.device().name + "' lacks shaderFloat64; use fp32"};
  if (!context.device().fragment_stores)
    return Error{Errc::missing_feature, VK_SUCCESS,
                 "device '" + context.device().name + "' lacks fragmentStoresAndAtomics (the region draw lists "
                 "uncertain pixels from the fragment shader)"};
  auto impl = std::make_unique<Impl>();
  impl->state = context.state();
  impl->render_pass = render_pass;
  impl->precision = precision.value_or(context.device().float64 ? RegionPrecision::fp64 : RegionPrecision::fp32);
  impl->slots.resize(frames_in_flight);
  impl->drawn_layers.assign(frames_in_flight, 0);
  if (auto r = detail::create_storage_layout(impl->dev(), 3, VK_SHADER_STAGE_FRAGMENT_BIT, 0, impl->set_layout,
                                             impl->pipeline_layout, "region draw");
      !r)
    return r.error();
  return RegionDrawer(std::move(impl));
}

Result<void> RegionDrawer::prepare(uint32_t slot, std::span<const RegionProblem> layers) {
  Impl& m = *impl_;
  std::vector<SlotLayer>& mine = m.slots.at(slot);
  if (m.host.size() < layers.size()) m.host.resize(layers.size());
  if (mine.size() < layers.size()) mine.resize(layers.size());
  for (std::size_t i = 0; i < layers.size(); ++i) {
    HostLayer& h = m.host[i];
    SlotLayer& l = mine[i];
    m.collect(l, h);  // before the problem may change: the list belongs to the drawn one
    const RegionProblem& p = layers[i];
    if (!h.problem || &h.problem->setup() != &p.setup()) {
      h.problem = p;
      h.serial = ++m.serials;
      h.overrides.assign(static_cast<std::size_t>(p.request().width) * p.request().height, 0);
      ++h.version;
    }
    const RegionRequest& r = p.request();
    bool rebind = false;
    if (l.version != h.version || l.drawn != h.serial) {
      const std::vector<std::byte> data = detail::pack_region(p.setup(), m.precision, {});
      auto a = m.ensure(l.data, data.size());
      if (!a) return a.error();
      auto b = m.ensure(l.overrides, std::max<VkDeviceSize>(4, h.overrides.size() * 4));
      if (!b) return b.error();
      auto c = m.ensure(l.uncertain, 4 * (2 + VkDeviceSize{kUncertainCapacity}));
      if (!c) return c.error();
      rebind = a.value() || b.value() || c.value() || l.set == VK_NULL_HANDLE;
      std::memcpy(l.data.mapped, data.data(), data.size());
      std::memcpy(l.overrides.mapped, h.overrides.data(), h.overrides.size() * 4);
      l.version = h.version;
    }
    if (rebind) {
      if (auto w = m.write_set(l); !w) return w.error();
    }
    auto* words = reinterpret_cast<uint32_t*>(l.uncertain.mapped);
    words[0] = 0;
    words[1] = kUncertainCapacity;
    auto pipeline = m.pipeline_for(p.setup());
    if (!pipeline) return pipeline.error();
    l.pipeline = pipeline.value();
    l.drawn = h.serial;
    l.width = static_cast<uint32_t>(r.width);
    l.height = static_cast<uint32_t>(r.height);
  }
  m.drawn_layers[slot] = layers.size();
  return {};
}

void RegionDrawer::draw(VkCommandBuffer cmd, uint32_t slot, VkExtent2D framebuffer) const {
  const Impl& m = *impl_;
  const VkViewport viewport{0.0f, 0.0f, static_cast<float>(framebuffer.width), static_cast<float>(framebuffer.height),
                            0.0f, 1.0f};
  for (std::size_t i = 0; i < m.drawn_layers[slot]; ++i) {
    const SlotLayer& l = m.slots[slot][i];
    const VkRect2D canvas{{0, 0}, {std::min(l.width, framebuffer.width), std::min(l.height, framebuffer.height)}};
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, l.pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, m.pipeline_layout, 0, 1, &l.set, 0, nullptr);
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &canvas);
    vkCmdDraw(cmd, 3, 1, 0, 0);
  }
}

RegionPrecision RegionDrawer::precision() const { return impl_->precision; }
uint64_t RegionDrawer::host_pixels() const { return impl_->host_pixels; }

RegionDrawer::RegionDrawer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
RegionDrawer::RegionDrawer(RegionDrawer&&) noexcept = default;
RegionDrawer& RegionDrawer::operator=(RegionDrawer&&) noexcept = default;
RegionDrawer::~RegionDrawer() = default;

}  // namespace cmr::vk
