#include "tools/region_backend.hpp"

#include <map>
#include <memory>

#include "tools/cli_common.hpp"
#ifdef CMR_WITH_VULKAN
#include "vk/region_vk.hpp"
#endif

namespace cmr::cli {
namespace {

double g_last_setup_seconds = 0;

// Blocks the host leaves undecided at this side length go to the device.
constexpr int kDeviceBlock = 4;

#ifdef CMR_WITH_VULKAN
// One renderer per device name for the life of the process: contexts and
// compiled pipelines are reused across calls (every point of a spline, every
// figure).
vk::RegionRenderer& renderer_for(const std::string& device) {
  static std::map<std::string, std::unique_ptr<vk::RegionRenderer>> renderers;
  auto it = renderers.find(device);
  if (it != renderers.end()) return *it->second;
  vk::ContextOptions co;
  co.device_name = device;
  co.require_float64 = false;  // fp64 is checked per render, so fp32 works on any device
  auto ctx = vk::Context::create(co);
  if (!ctx) {
    std::string message = ctx.error().message;
    if (message.find("VK_DRIVER_FILES") == std::string::npos)
      message += " (for lavapipe: install mesa-vulkan-drivers or export "
                 "VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json)";
    throw EnvironmentError(message + "; or use --backend cpu");
  }
  auto r = std::make_unique<vk::RegionRenderer>(ctx.take());
  return *renderers.emplace(device, std::move(r)).first->second;
}
#endif

}  // namespace

double last_setup_seconds() { return g_last_setup_seconds; }

RegionImage render_region(const RegionSetup& setup, const BackendOptions& options) {
  g_last_setup_seconds = 0;
  if (options.backend == Backend::cpu) return region_cpu(setup, options.threads);
#ifdef CMR_WITH_VULKAN
  // The host decides whole blocks where the certified path holds over them
  // (most of a typical image); the device classifies the pixels of the
  // blocks left undecided at the device block size.
  // The device is opened first, so a missing one is reported whatever the scene.
  vk::RegionRenderer& r = renderer_for(options.device);
  RegionImage img = blank_image(setup);
  std::vector<std::array<int, 2>> pixels;
  if (options.cull) {
    pixels = region_cull(setup, img, kDeviceBlock, options.threads);
  } else {
    for (int j = 0; j < img.height; ++j)
      for (int i = 0; i < img.width; ++i) pixels.push_back({i, j});
  }
  if (pixels.empty()) return img;
  const double before = r.pipeline_seconds();
  auto words = r.run(setup, options.precision == Precision::fp32 ? vk::RegionPrecision::fp32
                                                                  : vk::RegionPrecision::fp64, pixels);
  if (!words) {
    if (words.error().code == vk::Errc::size_unsupported) throw InputError(words.error().message);
    throw EnvironmentError(words.error().message);
  }
  g_last_setup_seconds = r.pipeline_seconds() - before;
  const RegionOptions& o = setup.options;
  for (std::size_t k = 0; k < pixels.size(); ++k) {
    const auto [i, j] = pixels[k];
    const std::size_t at = static_cast<std::size_t>(j) * o.width + i;
    const uint32_t w = words.value()[k];
    if (w & vk::kUncertain) {
      // Not certified on the device (or deeper than its precomputed pieces):
      // the host decides, certified and then exactly.
      const PixelResult pr = classify_position(setup, pixel_center(img.view, o.width, o.height, i, j));
      img.labels[at] = pr.label;
      img.depth[at] = pr.depth;
      img.exact_pixels += pr.exact;
    } else {
      img.labels[at] = static_cast<uint8_t>(w & 0xff);
      img.depth[at] = static_cast<uint8_t>((w >> 8) & 0xff);
    }
  }
  if (!o.depth) std::fill(img.depth.begin(), img.depth.end(), 0);
  return img;
#else
  throw EnvironmentError("this cmr was built without Vulkan; use --backend cpu");
#endif
}

}  // namespace cmr::cli
