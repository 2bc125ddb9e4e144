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

}  // namespace
}  // namespace cmr
