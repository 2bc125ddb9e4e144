#pragma once
// The Vulkan backend of space-curve plane regions (issue 25): the device
// judges each moved segment (Algorithm 1 on lambda3) and each varying
// joint's curvature jump per pixel, with certified double-precision
// arithmetic (shaders/space_region_fp64.comp); for a rational curve from
// polynomials in the plane coordinates that the host derives exactly once
// per render (SpaceRegionProblem::rational_lambda3 / rational_jump);
// the host folds the parts with SpaceRegionProblem::compose, and classifies
// on the CPU (SpaceRegionProblem::classify: error bounds, then exact) every
// pixel where some part was not certified. So the labels (and depths) equal
// the CPU backend's.
#include <cstddef>
#include <optional>
#include <string>
#include <utility>

#include "region/space_region.hpp"
#include "vk/context.hpp"
#include "vk/error.hpp"

namespace cmr::vk {

struct SpaceRegionVkOptions {
  std::string device;  ///< device name (case-insensitive substring); empty: the first with shaderFloat64
  int threads = 0;     ///< host threads for the uncertain pixels; 0: all cores
  /// Most pixels one dispatch takes (0: as the 2^27-byte storage buffers
  /// every device allows hold; tests set fewer to cover the split runs).
  std::size_t pixels_per_run = 0;
};

/// Renders `problem` on a Vulkan device. Errors: as Context::create
/// (no_device, device_not_found, loader_missing, missing_feature when no
/// device has shaderFloat64) and ComputePipeline::create / run;
/// size_unsupported for a degree outside 2..7 (polynomial) or 2..6
/// (rational): the shader's range; use the CPU backend.
/// What a render did: pixels the device certified, and those it left to the CPU.
struct SpaceRegionVkStats {
  std::size_t device_pixels = 0, host_pixels = 0;
};

Result<RegionResult> render_space_region_vulkan(const SpaceRegionProblem& problem,
                                                const SpaceRegionVkOptions& options = {},
                                                SpaceRegionVkStats* stats = nullptr);

/// render_space_region_vulkan as a SpaceRegionBackend: size_unsupported
/// throws InputError with its message, any other error EnvironmentError.
class VulkanSpaceRegionBackend final : public SpaceRegionBackend {
 public:
  explicit VulkanSpaceRegionBackend(SpaceRegionVkOptions options = {}) : options_(std::move(options)) {}
  RegionResult render(const SpaceRegionProblem& problem) override;
  std::string name() const override { return "vulkan"; }
  std::optional<std::size_t> host_pixels() const override { return stats_.host_pixels; }

 private:
  SpaceRegionVkOptions options_;
  SpaceRegionVkStats stats_;
};

}  // namespace cmr::vk
