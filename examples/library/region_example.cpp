// The README's library examples, built and run by ctest: a CPU region and,
// when a Vulkan device is present, the same region on the Vulkan backend.
#include <cstdio>

#include "region/region.hpp"
#include "vk/region_vk.hpp"

int main() {
  // A CPU region: where may P1 of this cubic Bezier go so that the
  // curvature stays monotone?
  const cmr::BSpline curve = cmr::BSpline::bezier({{0, 0}, {1, 2}, {3, 3}, {5, 2.5}});
  cmr::RegionRequest request;
  request.point = 1;
  request.width = request.height = 128;
  const cmr::RegionProblem problem = cmr::RegionProblem::make(curve, request);  // throws cmr::InputError
  cmr::CpuRegionBackend cpu;
  const cmr::RegionResult region = cpu.render(problem);
  long monotone = 0;
  for (cmr::Direction l : region.labels)
    monotone += l == cmr::Direction::increasing || l == cmr::Direction::decreasing;
  std::printf("cpu: %ld of %zu pixels monotone; P1 where it is: %s\n", monotone, region.labels.size(),
              cmr::to_string(problem.classify(curve.points()[1]).label));

  // The same region on Vulkan (lavapipe without a GPU): identical labels.
  cmr::vk::VulkanRegionOptions options;
  options.precision = cmr::vk::RegionPrecision::fp32;  // any device; labels are certified either way
  auto vulkan = cmr::vk::VulkanRegionBackend::create(options);
  if (!vulkan) {
    std::printf("vulkan: %s\n", vulkan.error().message.c_str());
    return 0;  // no device: an environment failure, not a wrong answer
  }
  const cmr::RegionResult gpu = vulkan.value().render(problem);
  std::printf("vulkan (%s): labels %s the CPU's\n", vulkan.value().device().name.c_str(),
              gpu.labels == region.labels ? "equal" : "DIFFER from");
  return gpu.labels == region.labels ? 0 : 1;
}
