#include "bezierize/region.hpp"

#include <gtest/gtest.h>

#include <random>

#include "bezierize/analyze.hpp"
#include "bezierize/region_setup.hpp"
#include "spline/errors.hpp"
#include "tests/test_util.hpp"

namespace cmr {
namespace {

TEST(Region, PixelCentresFollowTheDocumentedFormula) {
  const View v{-1, 2, 3, 5};
  const Vec2 a = pixel_center(v, 4, 3, 0, 0);
  EXPECT_EQ(a.x, -1 + (4.0 * 0.5) / 4);
  EXPECT_EQ(a.y, 5 - (3.0 * 0.5) / 3);
  const Vec2 b = pixel_center(v, 4, 3, 3, 2);
  EXPECT_EQ(b.x, -1 + (4.0 * 3.5) / 4);
  EXPECT_EQ(b.y, 5 - (3.0 * 2.5) / 3);
}

TEST(Region, DefaultViewContainsThePolygonWithSquarePixels) {
  const BSpline s = BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7}, {{0, 0}, {1, 2}, {3, 3}, {5, 2.5}, {6.5, 1}, {7, -1}});
  const View v = default_view(s, 400, 200);
  for (const Vec2& p : s.points()) {
    EXPECT_GT(p.x, v.x0);
    EXPECT_LT(p.x, v.x1);
    EXPECT_GT(p.y, v.y0);
    EXPECT_LT(p.y, v.y1);
  }
  EXPECT_NEAR((v.x1 - v.x0) / 400, (v.y1 - v.y0) / 200, 1e-12);
}

TEST(Region, InvalidOptionsAreInputErrors) {
  const BSpline s = BSpline::bezier({{0, 0}, {1, 1}, {2, 0}, {3, 1}});
  auto bad = [&](auto tweak) {
    RegionRequest o;
    tweak(o);
    EXPECT_THROW(RegionProblem::make(s, o), InputError);
  };
  bad([](RegionRequest& o) { o.point = 4; });
  bad([](RegionRequest& o) { o.point = -1; });
  bad([](RegionRequest& o) { o.width = 0; });
  bad([](RegionRequest& o) { o.height = kMaxImageSize + 1; });
  bad([](RegionRequest& o) { o.split = 1; });  // one segment: no joint
  bad([](RegionRequest& o) { o.max_depth = 31; });
  bad([](RegionRequest& o) { o.with = {0}; });  // the moved point itself
  bad([](RegionRequest& o) { o.view = View{1, 0, 0, 1}; });
}

// The same curve at a higher degree has the same curvature, so for every
// position of the moved point the label agrees (or one of them is undecided:
// Algorithm 1's subdivision sees different coefficients).
TEST(Region, DegreeElevatedCurveKeepsItsRegion) {
  const BSpline cubic = test::class_a_bezier(3, -0.4, 1.3);
  RegionRequest o;
  o.point = 0;
  o.width = 40;
  o.height = 40;
  const RegionResult img = CpuRegionBackend().render(RegionProblem::make(cubic, o));
  int compared = 0, in_region = 0;
  for (int j = 0; j < o.height; j += 3)
    for (int i = 0; i < o.width; i += 3) {
      const Vec2 p = pixel_center(img.view, o.width, o.height, i, j);
      std::vector<Vec2> P = cubic.points();
      P[0] = p;
      // Exact elevation in rationals would change nothing; in double the
      // elevated points round, so compare only where both are decided.
      std::vector<Vec2> E(5);
      E[0] = P[0];
      E[4] = P[3];
      for (int k = 1; k <= 3; ++k) E[k] = (k / 4.0) * P[k - 1] + (1 - k / 4.0) * P[k];
      const SplineAnalysis a = analyze(BSpline::bezier(E));
      const int elevated = detail::label_of(a.cmrwi), original = code(img.labels[j * o.width + i]);
      if (elevated == 3 || original == 3) continue;
      EXPECT_EQ(elevated, original) << "pixel (" << i << ", " << j << ")";
      ++compared;
      in_region += original != 0;
    }
  EXPECT_GT(compared, 150);
  EXPECT_GT(in_region, 5) << "the scene must contain part of the region";
}

// Rational splines (fixed weights): the CPU backend's labels are, pixel by
// pixel, those of an independent exact analysis of the moved spline (the
// spline with point k at the pixel centre), in both modes and split.
TEST(Region, RationalSplineLabelsEqualTheExactAnalysisOfTheMovedSpline) {
  // Fig. 9's polygon (tools/figures.cpp) with weights, on its C2 knots and
  // with a C1 joint (double knot) whose curvature jump varies with the position.
  const std::vector<Vec2> P = {{0, 0}, {0.33, 0}, {1.27, -0.27}, {3.46, -2.1}, {5.45, -4.7}, {6.57, -6.46}};
  const std::vector<double> w = {1, 1.03125, 1, 1, 0.96875, 1.0625};
  for (const BSpline& s : {BSpline::make(3, {0, 0, 0, 1, 2, 3, 3, 3}, P, "C2", w),
                           BSpline::make(3, {0, 0, 0, 1, 1, 2, 2, 2}, P, "C1", w)}) {
  ASSERT_TRUE(s.is_rational());
  int region_pixels = 0;
  for (int mode = 0; mode < 2; ++mode)
    for (const std::optional<int> split : {std::optional<int>(), std::optional<int>(1)}) {
      RegionRequest o;
      o.point = 3;
      o.width = 24;
      o.height = 24;
      o.mode = mode ? Mode::cmr : Mode::cmrwi;
      o.view = View{2.9, -2.6, 4.1, -1.4};  // around P3
      o.split = split;
      const RegionProblem problem = RegionProblem::make(s, o);
      const RegionResult img = CpuRegionBackend().render(problem);
      int in_region = 0;
      for (int j = 0; j < o.height; ++j)
        for (int i = 0; i < o.width; ++i) {
          const Vec2 p = pixel_center(img.view, o.width, o.height, i, j);
          AnalyzeOptions ao;
          ao.split = split;
          ao.split_mode = o.mode;
          const SplineAnalysis a = analyze(s.with_point(o.point, p), ao);
          const int want = split ? detail::label_of(*a.split) : detail::label_of(mode ? a.cmr : a.cmrwi);
          ASSERT_EQ(img.code_at(j * o.width + i), want)
              << s.name() << " mode " << mode << " split " << split.has_value() << " pixel (" << i << ", " << j << ")";
          in_region += want != 0;
        }
      EXPECT_LT(in_region, o.width * o.height) << s.name() << " mode " << mode << " split " << split.has_value();
      region_pixels += in_region;
    }
  EXPECT_GT(region_pixels, 50) << s.name() << ": the scene must hold part of the regions";
  }
}

}  // namespace
}  // namespace cmr
