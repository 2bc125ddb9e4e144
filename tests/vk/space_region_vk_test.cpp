// The Vulkan backend of space-curve plane regions (vk/space_region_vk.hpp,
// issue 25) against the CPU backend: identical labels and depths, pixel by
// pixel, on seeded planes, near-boundary zooms and a closed spline (lavapipe).
#include "vk/space_region_vk.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <random>

namespace cmr {
namespace {

const std::vector<Vec2> kFig8 = {{1.3, -1.43}, {1.05, -0.06}, {2.15, -1.31}, {1.97, -3.83}, {-2.23, -6.95}, {-6.78, -9.78}};

SpaceSpline fig8_lifted(const std::vector<double>& z) {
  std::vector<Vec3> p;
  for (std::size_t i = 0; i < kFig8.size(); ++i) p.emplace_back(kFig8[i].x, kFig8[i].y, z[i]);
  return SpaceSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7}, p);
}

/// Renders on both backends; counts the device-certified pixels.
void expect_identical(const SpaceSpline& s, const SpaceRegionRequest& r, const std::string& what,
                      std::size_t* device_pixels = nullptr) {
  const SpaceRegionProblem p = SpaceRegionProblem::make(s, r);
  const RegionResult cpu = p.render(1);
  vk::SpaceRegionVkStats stats;
  auto gpu = vk::render_space_region_vulkan(p, {}, &stats);
  ASSERT_TRUE(gpu.has_value()) << what << ": " << gpu.error().message;
  ASSERT_EQ(gpu.value().labels.size(), cpu.labels.size()) << what;
  int diff = 0;
  for (std::size_t k = 0; k < cpu.labels.size(); ++k) {
    if (gpu.value().labels[k] != cpu.labels[k] || gpu.value().depth[k] != cpu.depth[k]) {
      if (++diff <= 5)
        ADD_FAILURE() << what << ": pixel " << k % r.width << "," << k / r.width << " cpu " << to_string(cpu.labels[k])
                      << "/" << int(cpu.depth[k]) << " vulkan " << to_string(gpu.value().labels[k]) << "/"
                      << int(gpu.value().depth[k]);
    }
  }
  EXPECT_EQ(diff, 0) << what;
  if (device_pixels) *device_pixels += stats.device_pixels;
}

std::optional<View> boundary_zoom(const SpaceRegionProblem& problem, const RegionResult& img, double half_width) {
  for (int j = 0; j < img.height; ++j)
    for (int i = 0; i + 1 < img.width; ++i) {
      const std::size_t k = static_cast<std::size_t>(j) * img.width + i;
      if (img.labels[k] == img.labels[k + 1]) continue;
      Vec2 p = pixel_center(img.view, img.width, img.height, i, j);
      Vec2 q = pixel_center(img.view, img.width, img.height, i + 1, j);
      const Direction lp = img.labels[k];
      for (int it = 0; it < 60; ++it) {
        const Vec2 m = 0.5 * (p + q);
        (problem.classify(m.x, m.y).label == lp ? p : q) = m;
      }
      const Vec2 c = 0.5 * (p + q);
      return View{c.x - half_width, c.y - half_width, c.x + half_width, c.y + half_width};
    }
  return std::nullopt;
}

TEST(SpaceRegionVulkan, LabelsEqualTheCpuBackendsOnSeededPlanesAndNearBoundaryZooms) {
  std::mt19937_64 rng(2525);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  std::size_t device = 0, zooms = 0;
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<double> z(6);
    for (double& x : z) x = trial == 0 ? 0.0 : u(rng);
    const SpaceSpline s = fig8_lifted(z);
    SpaceRegionRequest r;
    r.point = 1 + trial % 4;
    r.plane = SpacePlane{s.points()[static_cast<std::size_t>(r.point)], {1, u(rng), u(rng)}, {u(rng), 1, u(rng)}};
    r.width = r.height = 24;
    r.view = View{-0.6, -0.6, 0.6, 0.6};
    const std::string at = "trial " + std::to_string(trial);
    expect_identical(s, r, at, &device);
    const SpaceRegionProblem p = SpaceRegionProblem::make(s, r);
    if (const auto zoom = boundary_zoom(p, p.render(1), 1e-12)) {
      r.view = zoom;
      r.width = r.height = 8;
      expect_identical(s, r, "zoom of " + at);
      ++zooms;
    }
  }
  EXPECT_GT(device, 5u * 24 * 24 / 2);  // the device certified most pixels
  EXPECT_GE(zooms, 2u);
}

TEST(SpaceRegionVulkan, LabelsEqualTheCpuBackendsForDegreesTwoAndFiveAndAClosedSpline) {
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> u(-2, 2);
  for (const int d : {2, 5}) {  // (each degree compiles its own pipeline: slow on lavapipe)
    const int m = d + 3;
    std::vector<Vec3> P;
    for (int i = 0; i < m; ++i) P.emplace_back(i, 0.3 * i * i + 0.2 * u(rng), 0.2 * u(rng));
    std::vector<double> knots;
    for (int i = 0; i < m + d - 1; ++i) knots.push_back(i);
    const SpaceSpline s = SpaceSpline::make(d, knots, P);
    SpaceRegionRequest r;
    r.point = m / 2;
    r.plane = SpacePlane{P[static_cast<std::size_t>(r.point)], {1, 0, 0.1}, {0, 1, -0.2}};
    r.width = r.height = 16;
    r.view = View{-1, -1, 1, 1};
    expect_identical(s, r, "degree " + std::to_string(d));
  }
  const SpaceSpline c = SpaceSpline::make_closed(3, {0, 1, 2, 3, 4, 5},
                                                 {{2, 0, 0}, {0.5, 1.5, 0.5}, {-1.5, 1, 1}, {-1.5, -1, 0.5}, {0.5, -1.5, 0}});
  SpaceRegionRequest r;
  r.point = 0;
  r.plane = SpacePlane{{2, 0, 0}, {1, 0, 0.5}, {0, 1, 0.25}};
  r.width = r.height = 16;
  r.view = View{-1, -1, 1, 1};
  expect_identical(c, r, "closed");
}

TEST(SpaceRegionVulkan, RationalCurvesAreLeftToTheCpuBackend) {
  const SpaceSpline s = SpaceSpline::bezier({{0, 0, 0}, {1, 1, 0}, {2, 1, 1}, {3, 0, 1}}, "", {1, 2, 1, 1});
  SpaceRegionRequest r;
  r.point = 1;
  r.plane = SpacePlane{{1, 1, 0}, {1, 0, 0}, {0, 1, 0}};
  r.width = r.height = 4;
  auto out = vk::render_space_region_vulkan(SpaceRegionProblem::make(s, r));
  ASSERT_FALSE(out.has_value());
  EXPECT_EQ(out.error().code, vk::Errc::size_unsupported);
  EXPECT_NE(out.error().message.find("rational space curves run on the CPU backend only"), std::string::npos);
}

}  // namespace
}  // namespace cmr
