#include "tools/bench/published_method_vk.hpp"

#include <array>
#include <cstring>
#include <map>
#include <memory>
#include <stdexcept>
#include <tuple>

#include "published_fp64_comp.h"
#include "published_fp64_frag.h"
#include "vk/compute_pipeline.hpp"
#include "vk/context.hpp"
#include "vk/fragment_pipeline.hpp"

namespace cmr::bench {
namespace {

/// The shader's push constants (std430 offsets: view 0, anchor 32, ints 48..60).
struct Push {
  double view[4];
  double anchor[2];
  int32_t width, height, segments;
  uint32_t fixed_directions;
};
static_assert(sizeof(Push) == 64, "published_fp64.frag's push-constant block is 64 bytes");

/// The device and the pipelines, for the whole run; never destroyed, since a
/// GPU driver may be gone by the time static destructors run (vk/context.hpp).
vk::Context& context() {
  static auto& ctx = *new std::unique_ptr<vk::Context>([] {
    vk::ContextOptions o;
    o.require_float64 = true;
    auto c = vk::Context::create(o);
    if (!c) throw std::runtime_error("published_region_vulkan: " + c.error().message);
    return std::make_unique<vk::Context>(c.take());
  }());
  return *ctx;
}

vk::FragmentPipeline& pipeline(int degree, int depth, int width, int height) {
  static auto& cache = *new std::map<std::tuple<int, int, int, int>, std::unique_ptr<vk::FragmentPipeline>>;
  std::unique_ptr<vk::FragmentPipeline>& p = cache[{degree, depth, width, height}];
  if (!p) {
    const std::array<uint32_t, 2> spec{static_cast<uint32_t>(degree), static_cast<uint32_t>(depth)};
    auto made = vk::FragmentPipeline::create(context(), cmr_published_fp64_frag_spv, static_cast<uint32_t>(width),
                                             static_cast<uint32_t>(height), sizeof(Push),
                                             vk::FragmentPipeline::kDefaultBandRows, spec);
    if (!made) throw std::runtime_error("published_region_vulkan: " + made.error().message);
    p = std::make_unique<vk::FragmentPipeline>(made.take());
  }
  return *p;
}

vk::ComputePipeline& compute_pipeline(int degree, int depth) {
  static auto& cache = *new std::map<std::tuple<int, int>, std::unique_ptr<vk::ComputePipeline>>;
  std::unique_ptr<vk::ComputePipeline>& p = cache[{degree, depth}];
  if (!p) {
    const std::array<uint32_t, 2> spec{static_cast<uint32_t>(degree), static_cast<uint32_t>(depth)};
    auto made = vk::ComputePipeline::create(context(), cmr_published_fp64_comp_spv, sizeof(Push), spec);
    if (!made) throw std::runtime_error("published_region_vulkan: " + made.error().message);
    p = std::make_unique<vk::ComputePipeline>(made.take());
  }
  return *p;
}

}  // namespace

std::vector<uint8_t> published_region_vulkan(const BSpline& spline, const PublishedRegion& r, ShaderStage stage) {
  const PublishedHostPart h = published_host_part(spline, r);
  std::vector<uint8_t> labels(static_cast<std::size_t>(r.width) * r.height, 0);
  if (h.all_zero) return labels;
  Push push{{r.view.x0, r.view.y0, r.view.x1, r.view.y1}, {h.anchor.x, h.anchor.y}, r.width, r.height, h.segments,
            h.fixed_directions};
  std::array<std::byte, sizeof(Push)> pc;
  std::memcpy(pc.data(), &push, sizeof(Push));
  const std::span<const std::byte> data(reinterpret_cast<const std::byte*>(h.data.data()),
                                        h.data.size() * sizeof(double));
  auto out = stage == ShaderStage::fragment
                 ? pipeline(h.degree, r.max_depth, r.width, r.height).run(data, pc)
                 : compute_pipeline(h.degree, r.max_depth).run(data, static_cast<uint32_t>(labels.size()), pc);
  if (!out) throw std::runtime_error("published_region_vulkan: " + out.error().message);
  const std::vector<uint32_t> words = out.take();
  for (std::size_t k = 0; k < labels.size(); ++k) labels[k] = static_cast<uint8_t>(words[k]);
  return labels;
}

}  // namespace cmr::bench
