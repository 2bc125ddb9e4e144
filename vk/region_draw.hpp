// Certified regions drawn straight into a window's colour image, inside the
// caller's render pass (cmr edit on a GPU): no image readback.
//
// Each layer (one RegionProblem, the region of one moved point) is one
// full-screen draw of shaders/region_present.glsl over the canvas, the
// top-left request.width x request.height pixels of the framebuffer, with
// a reverse-subtract blend: the framebuffer must hold white there before the
// pass, and overlapping layers darken as `cmr region --png` draws them (one
// 8-bit rounding per layer instead of one for the sum: with one layer, or
// plain labels, the bytes are the same). The shader classifies every pixel
// with the region shader's certified arithmetic (region_common.glsl); a
// pixel it cannot certify is left white and listed in a small per-frame
// buffer. The next time that frame slot comes round, prepare() decides the
// listed pixels on the host (cmr::backend::classify_position: certified, then
// exact) and from then on the shader takes their labels from an override
// buffer: after two frames of an unchanged problem every pixel carries the
// label CpuRegionBackend gives it. Depth shading is not drawn here.
//
// Needs fragmentStoresAndAtomics (DeviceInfo::fragment_stores); fp64 is used
// when the device has shaderFloat64, fp32 otherwise (labels are certified
// either way).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "region/region.hpp"
#include "vk/context.hpp"
#include "vk/error.hpp"
#include "vk/region_vk.hpp"

namespace cmr::vk {

class RegionDrawer {
 public:
  /// Errors: missing_feature (no fragmentStoresAndAtomics), shader_invalid,
  /// out_of_memory, other. `render_pass` is the pass draw() is recorded in
  /// (one colour attachment, 8-bit UNORM).
  /// precision: the shader's arithmetic; empty: fp64 where the device has
  /// shaderFloat64, fp32 otherwise (missing_feature for fp64 without it).
  static Result<RegionDrawer> create(Context& context, VkRenderPass render_pass, uint32_t frames_in_flight,
                                     std::optional<RegionPrecision> precision = std::nullopt);

  RegionDrawer(RegionDrawer&&) noexcept;
  RegionDrawer& operator=(RegionDrawer&&) noexcept;
  RegionDrawer(const RegionDrawer&) = delete;
  RegionDrawer& operator=(const RegionDrawer&) = delete;
  ~RegionDrawer();

  /// Before the pass of a frame on `slot`, once that slot's previous frame
  /// has finished (after Presenter::begin_frame): decides the pixels that
  /// frame left uncertain, then uploads what changed for these layers. A
  /// problem is the same layer as before when it shares its prepared state
  /// (a copy of the same RegionProblem).
  Result<void> prepare(uint32_t slot, std::span<const RegionProblem> layers);
  /// Inside the render pass: draws the layers prepare() was given.
  void draw(VkCommandBuffer cmd, uint32_t slot, VkExtent2D framebuffer) const;

  RegionPrecision precision() const;
  /// Pixels the host decided because the device could not certify them.
  uint64_t host_pixels() const;

 private:
  struct Impl;
  explicit RegionDrawer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace cmr::vk
