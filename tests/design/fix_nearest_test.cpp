// Nearest means nearest (issue 36, item 4): the one-point fix search against
// a dense certified label map, for requirements whose passing region has
// slivers and wedge tips thinner than one cell of the search's first grid
// (cmr: monotone and no inflection, on seeded random cubic Beziers).
//
// Tolerance: the fix's distance d_fix is at most 1% above the nearest
// passing pixel centre d_bf of a 384 x 384 map of the square of half-width
// 1.05 d_fix around the point (plus FixRequest::tolerance * curve size);
// the map's own resolution error (a pixel diagonal, 0.8% of d_fix) only
// makes d_bf larger than the true nearest distance, never smaller.
#include "design/fix.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "region/region.hpp"

namespace cmr {
namespace {

double norm(Vec2 v) { return std::sqrt(dot(v, v)); }

/// The nearest passing pixel centre's displacement of point k (Mode mode,
/// RegionProblem labels: the classifier the fix search itself certifies with)
/// within the square of half-width w around it; infinity when none passes.
double brute_nearest(const BSpline& s, int k, Mode mode, double w, Vec2& at) {
  const Vec2 p = s.points()[k];
  RegionRequest rr;
  rr.point = k;
  rr.mode = mode;
  rr.width = rr.height = 384;
  rr.depth = false;
  rr.view = View{p.x - w, p.y - w, p.x + w, p.y + w};
  const RegionResult map = CpuRegionBackend(2).render(RegionProblem::make(s, rr));
  double d = std::numeric_limits<double>::infinity();
  for (int j = 0; j < map.height; ++j)
    for (int i = 0; i < map.width; ++i) {
      const Direction l = map.labels[static_cast<std::size_t>(j) * map.width + i];
      const Vec2 c = pixel_center(*rr.view, map.width, map.height, i, j);
      if ((l == Direction::increasing || l == Direction::decreasing) && norm(c - p) < d) d = norm(c - p), at = c - p;
    }
  return d;
}

/// Seeded splines from `make` failing cmr, point `point(trial)` fixed alone:
/// each distance within 1% (+ tolerance) of the brute force; returns the worst
/// excess over it.
template <class Make, class Point>
double check_against_brute_force(std::uint32_t seed, int want, Make make, Point point) {
  std::mt19937 rng(seed);
  const FixRequirement req = parse_fix_requirement("cmr");
  int cases = 0;
  double worst = 0;
  for (int trial = 0; trial < 10 * want && cases < want; ++trial) {
    const BSpline s = make(rng);
    if (requirement_holds(s, req)) continue;
    const int k = point(trial);
    FixRequest r;
    r.requirement = req;
    r.points = {k};
    r.keep = Keep::none;
    r.threads = 2;
    const FixResult f = fix(s, r);
    if (!f.fixed) continue;
    ++cases;
    EXPECT_EQ(f.moves.size(), 1u) << "trial " << trial;
    if (f.moves.size() != 1) continue;
    const double d_fix = f.moves[0].distance;
    Vec2 at_bf(0.0);
    const double d_bf = brute_nearest(s, k, Mode::cmr, 1.05 * d_fix, at_bf);
    EXPECT_TRUE(std::isfinite(d_bf)) << "trial " << trial << ": the brute-force map has no passing pixel";
    const Vec2 at_fix = f.moves[0].to - f.moves[0].from;
    worst = std::max(worst, d_fix / d_bf - 1);
    EXPECT_LE(d_fix, 1.01 * d_bf + r.tolerance * f.size)
        << "trial " << trial << " point " << k << ": the brute force passes at (" << at_bf.x << ", " << at_bf.y
        << "), distance " << d_bf << "; the fix moved to (" << at_fix.x << ", " << at_fix.y << "), distance " << d_fix;
    // Every answer stays certified.
    EXPECT_TRUE(f.certificate_holds) << "trial " << trial;
    EXPECT_TRUE(requirement_holds(*f.spline, req)) << "trial " << trial;
  }
  std::printf("cases %d, worst excess over the brute force %.2f%%\n", cases, 100 * worst);
  EXPECT_GE(cases, want / 2) << "too few seeded failing cases were fixable";
  return worst;
}

TEST(FixNearest, CmrOnePointIsWithinOnePercentOfTheBruteForce) {
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  check_against_brute_force(
      36040, 40,
      [&](std::mt19937& rng) {
        const double x1 = 1 + 0.8 * U(rng), y1 = 1.2 * U(rng);  // named: the order of draws is fixed
        const double x2 = 2 + 0.8 * U(rng), y2 = 1.2 * U(rng);
        const double y3 = 0.8 * U(rng);
        return BSpline::bezier({{0, 0}, {x1, y1}, {x2, y2}, {3, y3}});
      },
      [](int trial) { return 1 + trial % 2; });
}

/// A uniform cubic B-spline of five points (gently waving: point 2 alone can
/// fix it often), point 2 (`--points 2`).
TEST(FixNearest, UniformBSplinePoint2IsWithinOnePercentOfTheBruteForce) {
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  check_against_brute_force(
      36041, 20,
      [&](std::mt19937& rng) {
        std::vector<Vec2> pts;
        for (int i = 0; i < 5; ++i) {
          const double x = i + 0.2 * U(rng);
          pts.emplace_back(x, 0.4 * U(rng));
        }
        return BSpline::make(3, {0, 1, 2, 3, 4, 5, 6}, pts);
      },
      [](int) { return 2; });
}

}  // namespace
}  // namespace cmr
