#include "spline/curvature.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/test_util.hpp"

namespace cmr {
namespace {

TEST(Curvature, CounterClockwiseTurnIsPositive) {
  const BSpline ccw = BSpline::bezier({{0, 0}, {1, 0}, {1, 1}});
  EXPECT_GT(curvature(ccw, 0.5), 0);
  EXPECT_LT(curvature(ccw.reversed(), -0.5), 0);
}

TEST(Curvature, QuadraticApexMatchesClosedForm) {
  // y = x^2 traced by P(t) = (2t-1, (2t-1)^2): kappa at the apex is 2.
  const BSpline s = BSpline::bezier({{-1, 1}, {0, -1}, {1, 1}});
  EXPECT_NEAR(curvature(s, 0.5), 2.0, 1e-14);
}

TEST(Curvature, KappaMatchesTurningAnglePerArcLength) {
  std::mt19937_64 rng(21);
  const BSpline s = BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7}, test::random_points(rng, 6));
  const double h = 1e-6;
  for (double t = 2.1; t < 5; t += 0.37) {
    const Vec2 d0 = derivative(s, t - h, 1), d1 = derivative(s, t + h, 1);
    const double dtheta = std::atan2(det(d0, d1), dot(d0, d1));
    const double ds = std::sqrt(dot(derivative(s, t, 1), derivative(s, t, 1))) * 2 * h;
    EXPECT_NEAR(curvature(s, t), dtheta / ds, 1e-5 * (1 + std::abs(curvature(s, t)))) << "t=" << t;
  }
}

TEST(Curvature, DkappaDsMatchesFiniteDifferencesAlongArcLength) {
  std::mt19937_64 rng(22);
  for (int trial = 0; trial < 20; ++trial) {
    const BSpline s = BSpline::make(3, {0, 0, 0, 1, 2, 3, 3, 3}, test::random_points(rng, 6));
    for (double t = 0.05; t < 3; t += 0.29) {
      const double h = 1e-5;
      const double dk = curvature(s, t + h) - curvature(s, t - h);
      const double ds = std::sqrt(dot(derivative(s, t, 1), derivative(s, t, 1))) * 2 * h;
      const CurvatureSample c = curvature_at(s, t);
      const double fd = dk / ds;
      EXPECT_NEAR(c.dkappa_ds, fd, 1e-4 * (1 + std::abs(fd))) << "trial " << trial << " t=" << t;
    }
  }
}

TEST(Curvature, SegmentEndCurvatureMatchesPointwiseOnBothSides) {
  std::mt19937_64 rng(23);
  const BSpline s = BSpline::make(3, {0, 0, 0, 1, 1, 3, 3, 3}, test::random_points(rng, 6));
  const Segment& L = s.segments()[0];
  const Segment& R = s.segments()[1];
  EXPECT_NEAR(segment_end_curvature(s, L, 0), curvature(s, 0.0), 1e-9);
  EXPECT_NEAR(segment_end_curvature(s, R, 1), curvature(s, 3.0), 1e-9);
  EXPECT_NEAR(segment_end_curvature(s, L, 1), curvature(s, 1.0 - 1e-9), 1e-5);
  EXPECT_NEAR(segment_end_curvature(s, R, 0), curvature(s, 1.0), 1e-9);
}

}  // namespace
}  // namespace cmr
