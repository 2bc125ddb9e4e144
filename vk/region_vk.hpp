#pragma once
// The Vulkan region backend: packs a cmr::RegionSetup and a list of pixels
// into the storage buffer the region shader reads (shaders/region_common.glsl),
// classifies the listed pixels on the device, one fragment each in a fixed
// work area, and returns their raw words: label | depth << 8, or kUncertain
// when the shader could not certify the pixel (the caller recomputes those on
// the host).
#include <array>
#include <cstddef>
#include <span>
#include <cstdint>
#include <memory>
#include <vector>

#include "bezierize/region.hpp"
#include "vk/context.hpp"
#include "vk/fragment_pipeline.hpp"

namespace cmr::vk {

inline constexpr uint32_t kUncertain = 1u << 16;

enum class RegionPrecision { fp64, fp32 };

/// The storage buffer for the shader (layout documented in region_vk.cpp).
inline constexpr uint32_t kWorkAreaWidth = 256, kWorkAreaHeight = 256;

/// The storage buffer for the shader (layout documented in region_vk.cpp):
/// `pixels` are (column, row) of the image, at most the work area's size.
std::vector<std::byte> pack_region(const RegionSetup& setup, RegionPrecision precision,
                                   std::span<const std::array<int, 2>> pixels, uint32_t area_width);

/// A Context plus pipelines cached by (degree, depth, precision, mode,
/// varying joints: the shader's specialisation constants), so repeated
/// renders (every point of a spline, interactive use) compile once.
class RegionRenderer {
 public:
  explicit RegionRenderer(Context context);
  /// Errors: as FragmentPipeline::create / run; missing_feature when fp64 is
  /// asked of a device without shaderFloat64.
  /// One word per listed pixel, in order.
  Result<std::vector<uint32_t>> run(const RegionSetup& setup, RegionPrecision precision,
                                    std::span<const std::array<int, 2>> pixels);
  const DeviceInfo& device() const { return context_.device(); }
  /// Seconds spent creating pipelines (shader compilation) so far.
  double pipeline_seconds() const { return pipeline_seconds_; }

 private:
  struct Key {
    int degree, depth;
    RegionPrecision precision;
    bool cmr, joints;
    bool operator==(const Key&) const = default;
  };
  Context context_;
  std::vector<std::pair<Key, FragmentPipeline>> pipelines_;
  double pipeline_seconds_ = 0;
};

}  // namespace cmr::vk
