#include "bezierize/analyze.hpp"

#include <gtest/gtest.h>

#include "spline/curvature.hpp"
#include "spline/errors.hpp"
#include "tests/test_util.hpp"

namespace cmr {
namespace {

// A clockwise class A cubic whose legs grow: signed curvature (negative)
// rises towards 0, written as a B-spline with the given knots.
BSpline growing_spiral(std::vector<double> knots) {
  return test::polynomial_as_bspline(test::class_a_bezier(3, -0.35, 1.25), std::move(knots));
}

TEST(Analyze, ClockwiseGrowingSpiralIncreasesEverywhere) {
  const BSpline s = growing_spiral({0, 0, 0, 1, 2, 3, 3, 3});
  const SplineAnalysis a = analyze(s);
  for (const SegmentClass& c : a.segments) {
    EXPECT_EQ(c.monotonicity.curvature, Curvature::increasing);
    EXPECT_EQ(c.inflection.kappa_sign, -1);
  }
  EXPECT_EQ(a.cmrwi, Direction::increasing);
  EXPECT_EQ(a.cmr, Direction::increasing);
  // Dense sampling agrees: signed curvature rises.
  double prev = -1e300;
  for (int i = 0; i <= 300; ++i) {
    const double k = curvature(s, 3.0 * i / 300);
    EXPECT_GE(k, prev - 1e-12) << "i=" << i;
    prev = k;
  }
}

TEST(Analyze, UniformKnotsToo) {
  const SplineAnalysis a = analyze(growing_spiral({0, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(a.cmrwi, Direction::increasing);
  EXPECT_EQ(a.cmr, Direction::increasing);
}

TEST(Analyze, ReversalKeepsTheDirectionAndMirroringFlipsIt) {
  // Reversed, the curve turns counter-clockwise (kappa > 0) and |kappa| grows:
  // dkappa/ds is unchanged. Mirrored, kappa changes sign: decreasing.
  const BSpline s = growing_spiral({0, 0, 0, 1, 2, 3, 3, 3});
  EXPECT_EQ(analyze(s.reversed()).cmrwi, Direction::increasing);
  std::vector<Vec2> mirrored = s.points();
  for (Vec2& p : mirrored) p.y = -p.y;
  EXPECT_EQ(analyze(BSpline::make(3, s.knots(), mirrored)).cmrwi, Direction::decreasing);
}

TEST(Analyze, SplitCombinesTheTwoParts) {
  EXPECT_EQ(combine_split(Direction::increasing, Direction::decreasing), Split::inc_dec);
  EXPECT_EQ(combine_split(Direction::decreasing, Direction::increasing), Split::dec_inc);
  EXPECT_EQ(combine_split(Direction::undecided, Direction::none), Split::none);
  EXPECT_EQ(combine_split(Direction::undecided, Direction::increasing), Split::undecided);
  const SplineAnalysis a = analyze(growing_spiral({0, 0, 0, 1, 2, 3, 3, 3}), {{}, 2, Mode::cmr, {}, {}});
  EXPECT_EQ(*a.split, Split::inc_inc);
}

TEST(Analyze, SplitOutsideTheJointsIsAnInputError) {
  const BSpline s = growing_spiral({0, 0, 0, 1, 2, 3, 3, 3});
  EXPECT_THROW(analyze(s, {{}, 0, Mode::cmrwi, {}, {}}), InputError);
  EXPECT_THROW(analyze(s, {{}, 3, Mode::cmrwi, {}, {}}), InputError);
}

TEST(Analyze, CurvatureJumpAtAC1JointMustFollowTheDirection) {
  // Double knot at 1.5: the joint is C1 and curvature jumps. The exact jump
  // sign must agree with the two one-sided values.
  std::mt19937_64 rng(61);
  for (int trial = 0; trial < 50; ++trial) {
    const BSpline s = BSpline::make(3, {0, 0, 0, 1.5, 1.5, 3, 3, 3}, test::random_points(rng, 6));
    const SplineAnalysis a = analyze(s);
    ASSERT_EQ(a.joints.size(), 1u);
    const Joint& j = a.joints[0];
    EXPECT_EQ(j.continuity, 1);
    const double diff = j.kappa_right - j.kappa_left;
    if (std::abs(diff) > 1e-9 * (std::abs(j.kappa_left) + std::abs(j.kappa_right))) {
      EXPECT_EQ(j.jump, diff > 0 ? 1 : -1) << "trial " << trial;
    }
    if (a.cmrwi == Direction::increasing) {
      EXPECT_GE(j.jump, 0) << "trial " << trial;
    }
    if (a.cmrwi == Direction::decreasing) {
      EXPECT_LE(j.jump, 0) << "trial " << trial;
    }
  }
}

TEST(Analyze, QuadraticBSplineJointsAreC1AndJumpsCount) {
  // Degree 2: every simple knot is C1 (multiplicity 1 >= d-1).
  const BSpline s = BSpline::make(2, {0, 1, 2, 3, 4}, {{0, 0}, {1, 1}, {3, 1.5}, {6, 1}});
  const SplineAnalysis a = analyze(s);
  ASSERT_EQ(a.joints.size(), 1u);
  EXPECT_EQ(a.joints[0].continuity, 1);
  EXPECT_NE(a.joints[0].jump, 0);
}

}  // namespace
}  // namespace cmr
