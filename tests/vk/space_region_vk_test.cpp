// The Vulkan backend of space-curve plane regions (vk/space_region_vk.hpp,
// issue 25) against the CPU backend: identical labels and depths, pixel by
// pixel, on seeded planes, near-boundary zooms and a closed spline, for
// polynomial and rational curves (lavapipe).
#include "vk/space_region_vk.hpp"

#include <gtest/gtest.h>

#include <algorithm>
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
/// With pixels_per_run, each run of the device takes at most that many pixels.
void expect_identical(const SpaceSpline& s, const SpaceRegionRequest& r, const std::string& what,
                      std::size_t* device_pixels = nullptr, std::size_t pixels_per_run = 0) {
  const SpaceRegionProblem p = SpaceRegionProblem::make(s, r);
  const RegionResult cpu = p.render(1);
  vk::SpaceRegionVkStats stats;
  vk::SpaceRegionVkOptions o;
  o.pixels_per_run = pixels_per_run;
  auto gpu = vk::render_space_region_vulkan(p, o, &stats);
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
    // The same frame split into dispatches of 37 pixels (runs ending inside rows).
    if (trial == 1) expect_identical(s, r, at + " in 37-pixel runs", nullptr, 37);
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

// Rational curves: the host derives lambda3's coefficients (and the joints'
// jump terms) as polynomials in the plane coordinates, the device evaluates
// them with error bounds and runs the same Algorithm 1.
SpaceSpline rational_bspline(int d, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-0.3, 0.3), w(0.8, 1.25);
  std::vector<Vec3> P;
  std::vector<double> weights;
  for (std::size_t i = 0; i < 6 || static_cast<int>(i) <= d; ++i) {
    const Vec2 q = kFig8[i % kFig8.size()] + Vec2(static_cast<double>(i / kFig8.size()) * 3.0, 0.0);
    P.emplace_back(q.x, q.y, u(rng));
    weights.push_back(w(rng));
  }
  std::vector<double> knots;
  for (std::size_t i = 0; i < P.size() + static_cast<std::size_t>(d) - 1; ++i) knots.push_back(static_cast<double>(i));
  return SpaceSpline::make(d, knots, P, "", weights);
}

TEST(SpaceRegionVulkan, RationalCurvesOfDegreesTwoAndThreeGetTheCpuLabelsAlsoNearBoundaries) {
  std::mt19937_64 rng(2526);
  std::size_t device = 0, pixels = 0;
  for (const int d : {2, 3}) {
    // Degree 2: a conic arc with its vertex near P0, so moving P1 moves
    // the vertex in or out of the arc (|kappa| monotone or not).
    const SpaceSpline s = d == 2 ? SpaceSpline::bezier({{0, 0, 0}, {1, 0, 0.1}, {2, 2, 0.2}}, "", {1, 1.1, 0.9})
                                 : rational_bspline(d, rng);
    SpaceRegionRequest r;
    r.width = r.height = 32;
    // The first point and smallest view where the label changes.
    std::optional<View> zoom;
    for (const int k : d == 2 ? std::vector<int>{1, 0, 2} : std::vector<int>{3, 2, 1, 4}) {
      r.point = k;
      r.plane = SpacePlane{s.points()[static_cast<std::size_t>(k)], {1, 0, 0.1}, {0, 1, -0.2}};
      for (const double h : {0.6, 1.2}) {
        r.view = View{-h, -h, h, h};
        const SpaceRegionProblem p = SpaceRegionProblem::make(s, r);
        if ((zoom = boundary_zoom(p, p.render(1), 1e-12))) break;
      }
      if (zoom) break;
    }
    const std::string at = "rational degree " + std::to_string(d) + ", point " + std::to_string(r.point);
    EXPECT_TRUE(zoom.has_value()) << at << ": no label boundary in the views";
    expect_identical(s, r, at, &device);
    pixels += 32 * 32;
    if (zoom) {
      r.view = zoom;
      r.width = r.height = 8;
      expect_identical(s, r, "zoom of " + at);
    }
  }
  EXPECT_GT(device, pixels / 2);  // the device certified most pixels
}

TEST(SpaceRegionVulkan, RationalLiftedFig8AndAClosedRationalSplineGetTheCpuLabels) {
  std::vector<Vec3> p;
  const std::vector<double> z = {0, 0.3, 0.8, 1.5, 2.4, 3.5};
  for (std::size_t i = 0; i < kFig8.size(); ++i) p.emplace_back(kFig8[i].x, kFig8[i].y, z[i]);
  const SpaceSpline s = SpaceSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7}, p, "", {1, 1.5, 0.7, 1.2, 2, 1});
  SpaceRegionRequest r;
  r.point = 3;
  r.plane = SpacePlane{p[3], {1, 0, 0}, {0, 1, 0}};
  r.width = r.height = 40;
  r.view = View{-1.2, -1.2, 0.8, 0.8};
  std::size_t device = 0;
  expect_identical(s, r, "rational fig8", &device);
  EXPECT_GT(device, 40u * 40 / 2);
  // A double knot: a C1 joint whose curvature jump the device judges (mode 3).
  const SpaceSpline c1 = SpaceSpline::make(3, {0, 1, 2, 3, 3, 4, 5, 6}, p, "", {1, 1.1, 0.9, 1, 1.2, 1});
  r.view = View{-2, -2, 2, 2};
  const SpaceRegionProblem p1 = SpaceRegionProblem::make(c1, r);
  ASSERT_FALSE(p1.moved_joints().empty());
  const RegionResult cpu1 = p1.render(1);
  EXPECT_GT(std::count(cpu1.labels.begin(), cpu1.labels.end(), Direction::decreasing), 10);  // both labels
  EXPECT_GT(std::count(cpu1.labels.begin(), cpu1.labels.end(), Direction::none), 10);
  device = 0;
  expect_identical(c1, r, "rational fig8 with a double knot", &device);
  EXPECT_GT(device, 40u * 40 / 2);
  const SpaceSpline c = SpaceSpline::make_closed(
      3, {0, 1, 2, 3, 4, 5}, {{2, 0, 0}, {0.5, 1.5, 0.5}, {-1.5, 1, 1}, {-1.5, -1, 0.5}, {0.5, -1.5, 0}}, "",
      {1, 2, 0.8, 1.3, 1});
  r.point = 0;
  r.plane = SpacePlane{{2, 0, 0}, {1, 0, 0.5}, {0, 1, 0.25}};
  r.width = r.height = 24;
  r.view = View{-1, -1, 1, 1};
  expect_identical(c, r, "closed rational");
}

TEST(SpaceRegionVulkan, RationalCurvesOfDegreesFourToSixGetTheCpuLabels) {
  std::mt19937_64 rng(4747);
  for (const int d : {4, 5, 6}) {  // (each degree compiles its own pipeline: slow on lavapipe)
    const SpaceSpline s = rational_bspline(d, rng);
    SpaceRegionRequest r;
    r.point = 3;
    r.plane = SpacePlane{s.points()[3], {1, 0, 0.1}, {0, 1, -0.2}};
    r.width = r.height = 16;
    r.view = View{-0.6, -0.6, 0.6, 0.6};
    std::size_t device = 0;
    expect_identical(s, r, "rational degree " + std::to_string(d), &device);
    EXPECT_GT(device, 16u * 16 / 2) << d;
  }
}

TEST(SpaceRegionVulkan, RationalCurvesAboveTheSupportedDegreeAreRefusedWithTheDegree) {
  std::mt19937_64 rng(9);
  const SpaceSpline s = rational_bspline(7, rng);
  SpaceRegionRequest r;
  r.point = 4;
  r.plane = SpacePlane{s.points()[4], {1, 0, 0}, {0, 1, 0}};
  r.width = r.height = 4;
  auto out = vk::render_space_region_vulkan(SpaceRegionProblem::make(s, r));
  ASSERT_FALSE(out.has_value());
  EXPECT_EQ(out.error().code, vk::Errc::size_unsupported);
  EXPECT_NE(out.error().message.find("rational space curves of degree 2..6 only (this one has degree 7"),
            std::string::npos)
      << out.error().message;
}

}  // namespace
}  // namespace cmr
