#pragma once
// Backend choice for the region tests: renders a RegionProblem on the CPU
// backend or on a VulkanRegionBackend (lavapipe), and returns the image as
// label codes so that tests compare pixels with the exact path's codes.
#include <map>
#include <memory>
#include <stdexcept>
#include <tuple>

#include "region/region_setup.hpp"
#include "vk/region_vk.hpp"

namespace cmr::test {

enum class Backend { vulkan, cpu };

struct BackendOptions {
  Backend backend = Backend::vulkan;
  vk::RegionPrecision precision = vk::RegionPrecision::fp64;
  vk::DeviceShare share = vk::DeviceShare::automatic;
  bool cascade = false;  ///< vk::VulkanRegionOptions::cascade
};

/// The Vulkan backend for these options, created once per test program (its
/// pipelines are reused, as the CLI reuses its one backend). Never destroyed:
/// a GPU driver may be gone by the time static destructors run (vk/context.hpp).
inline vk::VulkanRegionBackend& vulkan_backend(const BackendOptions& o) {
  static auto& backends = *new std::map<std::tuple<int, int, bool>, std::unique_ptr<vk::VulkanRegionBackend>>;
  auto& b = backends[{static_cast<int>(o.precision), static_cast<int>(o.share), o.cascade}];
  if (!b) {
    vk::VulkanRegionOptions vo;
    vo.precision = o.precision;
    vo.share = o.share;
    vo.cascade = o.cascade;
    auto created = vk::VulkanRegionBackend::create(vo);
    if (!created) throw std::runtime_error("no Vulkan device: " + created.error().message);
    b = std::make_unique<vk::VulkanRegionBackend>(created.take());
  }
  return *b;
}

inline backend::RegionImage render(const RegionProblem& problem, const BackendOptions& o) {
  RegionResult r = o.backend == Backend::cpu ? CpuRegionBackend().render(problem) : vulkan_backend(o).render(problem);
  backend::RegionImage img;
  img.width = r.width;
  img.height = r.height;
  img.view = r.view;
  img.labels = backend::LabelCodes(r.each_piece    ? backend::Labels::each_piece
                                   : r.alternating ? backend::Labels::alternating
                                   : r.split       ? backend::Labels::split
                                                   : backend::Labels::plain,
                                   r.codes());
  img.depth = r.depth;
  img.exact_pixels = r.exact_pixels;
  return img;
}

}  // namespace cmr::test
