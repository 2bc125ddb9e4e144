#include "bezierize/analyze.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "numeric/exact.hpp"
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
  const SplineAnalysis a = analyze(growing_spiral({0, 0, 0, 1, 2, 3, 3, 3}), {{}, 2, Mode::cmr, {}, {}, {}});
  EXPECT_EQ(*a.split, Split::inc_inc);
}

TEST(Analyze, SplitOutsideTheJointsIsAnInputError) {
  const BSpline s = growing_spiral({0, 0, 0, 1, 2, 3, 3, 3});
  EXPECT_THROW(analyze(s, {{}, 0, Mode::cmrwi, {}, {}, {}}), InputError);
  EXPECT_THROW(analyze(s, {{}, 3, Mode::cmrwi, {}, {}, {}}), InputError);
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


// ---- Semantics (README, "Semantics"): straights, zero curvature at an end,
// cusps, G1/G2 with tolerances, certified joint curvature.

// Three cubic Bezier pieces joined at C0 knots (multiplicity 3).
BSpline bezier_chain(const std::vector<Vec2>& points) {
  const int pieces = (static_cast<int>(points.size()) - 1) / 3;
  std::vector<double> knots;
  for (int k = 0; k <= pieces; ++k)
    for (int r = 0; r < 3; ++r) knots.push_back(k);
  return BSpline::make(3, knots, points);
}

// Signed curvature sampled densely on one segment, away from its ends.
// Returns +1 if it rises, -1 if it falls, 0 if it does both (within slack).
int sampled_direction(const BSpline& s, const Segment& seg) {
  bool up = false, down = false;
  double prev = curvature(s, seg.a + 1e-6 * (seg.b - seg.a));
  for (int i = 1; i <= 400; ++i) {
    const double k = curvature(s, seg.a + (seg.b - seg.a) * (1e-6 + (1 - 2e-6) * i / 400));
    const double slack = 1e-12 * (std::fabs(k) + std::fabs(prev));
    up = up || k > prev + slack;
    down = down || k < prev - slack;
    prev = k;
  }
  return up && down ? 0 : (up ? 1 : -1);
}

TEST(Semantics, StraightSegmentIsConstantWithoutInflection) {
  // lambda == 0 == eta: the paper's Algorithm 1 would call (1) and (2)
  // together "not monotone" and its Algorithm 2 (nu_0 nu_n = 0 <= 0) an
  // inflection. cmr: constant, no inflection; alone it is reported increasing.
  const SplineAnalysis a = analyze(BSpline::bezier({{0, 0}, {1, 1}, {2, 2}, {4, 4}}));
  EXPECT_EQ(a.segments[0].monotonicity.curvature, Curvature::constant);
  EXPECT_TRUE(a.shapes[0].straight);
  EXPECT_FALSE(a.shapes[0].cusp);
  EXPECT_EQ(a.shapes[0].inflection, Inflection::none);
  EXPECT_EQ(a.shapes[0].kappa_sign, 0);
  EXPECT_EQ(a.segments[0].inflection.inflection, Inflection::present);  // Algorithm 2 as the paper states it
  EXPECT_STREQ(shape_class(a.shapes[0]), "straight");
  EXPECT_EQ(a.cmrwi, Direction::increasing);
  EXPECT_EQ(a.cmr, Direction::increasing);
  EXPECT_EQ(a.cmr_algorithm2, Direction::none);
}

TEST(Semantics, LeavingAStraightWithZeroCurvatureIsNoInflection) {
  // A straight, then a cubic whose first three points are collinear with it:
  // eta = 0 at the joint (zero curvature) and > 0 inside, so kappa rises
  // from 0 and never changes sign. Joint: G1 and G2 (kappa 0 on both sides).
  const BSpline s = bezier_chain({{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 0}, {5, 0}, {5.5, 0.5}});
  const SplineAnalysis a = analyze(s);
  ASSERT_EQ(a.shapes.size(), 2u);
  EXPECT_TRUE(a.shapes[0].straight);
  const SegmentShape& c = a.shapes[1];
  EXPECT_FALSE(c.straight);
  EXPECT_TRUE(c.kappa_zero_start);
  EXPECT_FALSE(c.kappa_zero_end);
  EXPECT_STREQ(kappa_zero_at(c), "start");
  EXPECT_EQ(c.inflection, Inflection::none);
  EXPECT_EQ(c.kappa_sign, 1);
  EXPECT_EQ(a.segments[1].inflection.inflection, Inflection::present);  // the paper's rule (1) fires at the zero end
  // Independent: kappa sampled inside the curved segment is > 0 throughout.
  for (int i = 1; i < 100; ++i) EXPECT_GT(curvature(s, 1 + i / 100.0), 0) << "t = " << 1 + i / 100.0;
  const int dir = sampled_direction(s, s.segments()[1]);
  ASSERT_NE(dir, 0);
  const Direction want = dir > 0 ? Direction::increasing : Direction::decreasing;
  EXPECT_EQ(a.cmrwi, want);
  EXPECT_EQ(a.cmr, want);                      // no inflection: CMR holds
  EXPECT_EQ(a.cmr_algorithm2, Direction::none);  // what the region engine draws for --mode cmr
  ASSERT_EQ(a.joints.size(), 1u);
  EXPECT_EQ(a.joints[0].continuity, 0);
  EXPECT_TRUE(a.joints[0].g1);
  EXPECT_TRUE(a.joints[0].g2);
  EXPECT_EQ(a.joints[0].angle_deg, 0.0);
  EXPECT_EQ(a.joints[0].kappa_left, 0.0);
  EXPECT_EQ(a.joints[0].kappa_right, 0.0);
}

TEST(Semantics, CurvatureSignChangeAcrossAStraightIsAnInflection) {
  // Clockwise into the straight, counter-clockwise out of it: kappa goes
  // - -> 0 -> +, an inflection spread over the straight.
  const BSpline s = bezier_chain(
      {{-5.5, -0.5}, {-5, 0}, {-4, 0}, {-3, 0}, {-2, 0}, {-1, 0}, {0, 0}, {1, 0}, {2, 0}, {2.5, 0.5}});
  const SplineAnalysis a = analyze(s);
  EXPECT_LT(curvature(s, 0.5), 0);
  EXPECT_GT(curvature(s, 2.5), 0);
  for (const SegmentShape& sh : a.shapes) EXPECT_EQ(sh.inflection, Inflection::none);
  EXPECT_EQ(a.cmr, Direction::none);
  EXPECT_EQ(a.cmr_algorithm2, Direction::none);
}

TEST(Semantics, LineArcLineFailsOnlyAsDocumented) {
  // A polynomial segment cannot have constant non-zero curvature: the usual
  // cubic quarter-circle (k = 0.5523) has kappa symmetric about its middle,
  // so an extremum there: not monotone, whatever the straights around it.
  const double k = 0.5522847498;
  const BSpline s = bezier_chain({{-2, 1}, {-5.0 / 3, 1}, {-4.0 / 3, 1}, {-1, 1}, {-1 + k, 1}, {0, k}, {0, 0},
                                  {0, -1.0 / 3}, {0, -2.0 / 3}, {0, -1}});
  const SplineAnalysis a = analyze(s);
  EXPECT_EQ(a.segments[0].monotonicity.curvature, Curvature::constant);
  EXPECT_EQ(a.segments[1].monotonicity.curvature, Curvature::non_monotone);
  EXPECT_EQ(a.segments[2].monotonicity.curvature, Curvature::constant);
  EXPECT_EQ(sampled_direction(s, s.segments()[1]), 0);  // independent: kappa rises and falls
  EXPECT_EQ(a.cmrwi, Direction::none);
  // Line to arc: G1 with a curvature jump (0 to about -1), so not G2.
  EXPECT_TRUE(a.joints[0].g1);
  EXPECT_FALSE(a.joints[0].g2);
  EXPECT_LT(a.joints[0].jump, 0);
  // A single straight-only spline is "increasing" (documented), never "none".
  EXPECT_EQ(analyze(bezier_chain({{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 0}, {5, 0}, {6, 0}})).cmrwi,
            Direction::increasing);
}

TEST(Semantics, ZeroTangentInsideIsACusp) {
  // x' = 6(1-2t)^2, y' = 6(1-2t): P'(1/2) = 0.
  const BSpline s = BSpline::bezier({{0, 0}, {2, 2}, {0, 2}, {2, 0}});
  EXPECT_EQ(derivative(s, 0.5, 1), Vec2(0, 0));  // independent (de Boor derivative)
  const SplineAnalysis a = analyze(s);
  EXPECT_TRUE(a.shapes[0].cusp);
  EXPECT_STREQ(shape_class(a.shapes[0]), "cusp");
  EXPECT_TRUE(a.cusp);
  // A retracted handle (P0 = P1): P'(0) = 0, kappa unbounded at the start,
  // so eta(0) = 0 there is a cusp, not zero curvature.
  const SplineAnalysis h = analyze(BSpline::bezier({{0, 0}, {0, 0}, {1, 1}, {3, 1}}));
  EXPECT_TRUE(h.shapes[0].cusp);
  EXPECT_FALSE(h.shapes[0].kappa_zero_start);
  EXPECT_GT(std::fabs(curvature(BSpline::bezier({{0, 0}, {0, 0}, {1, 1}, {3, 1}}), 1e-6)), 1e4);
  // A regular curve close to it is not.
  const SplineAnalysis b = analyze(BSpline::bezier({{0, 0}, {2, 2}, {0, 2.001}, {2, 0}}));
  EXPECT_FALSE(b.shapes[0].cusp);
  EXPECT_FALSE(b.cusp);
}

TEST(Semantics, ZeroTangentAtAJointFailsSmoothness) {
  // Right piece starts with a zero leg (a retracted handle): P'(1+) = 0.
  const SplineAnalysis a = analyze(bezier_chain({{0, 0}, {1, 1}, {2, 1}, {3, 0}, {3, 0}, {4, -1}, {5, 0}}));
  const Joint& j = a.joints[0];
  EXPECT_TRUE(j.zero_tangent);
  EXPECT_FALSE(j.g1);
  EXPECT_FALSE(j.g2);
  EXPECT_TRUE(std::isnan(j.kappa_right));
  EXPECT_TRUE(std::isnan(j.angle_deg));
  EXPECT_TRUE(a.shapes[1].cusp);
  // A C2 joint (uniform knots) whose tangent is zero: P'(joint) ~ P_{i+1} - P_{i-1}.
  const SplineAnalysis u = analyze(BSpline::make(3, {0, 1, 2, 3, 4, 5, 6}, {{0, 0}, {1, 2}, {3, 1}, {1, 2}, {0, 5}}));
  ASSERT_EQ(u.joints.size(), 1u);
  EXPECT_EQ(u.joints[0].continuity, 2);
  EXPECT_TRUE(u.joints[0].zero_tangent);
  EXPECT_FALSE(u.joints[0].g1);
  EXPECT_TRUE(u.cusp);
}

TEST(Semantics, AngleToleranceDecidesG1AtIntegerFontJoints) {
  // Quadratic outline in integer font units, C0 at the on-curve point
  // (171, 170) between the off-curve points (100, 100) and (241, 240):
  // directions (71, 70) and (70, 70), angle atan2(70, 9870) = 0.4063 degrees.
  const BSpline s = BSpline::make(2, {0, 0, 1, 1, 2, 2}, {{0, 0}, {100, 100}, {171, 170}, {241, 240}, {400, 250}});
  const double want = std::atan2(70.0, 9870.0) * 180 / 3.14159265358979323846;
  const SplineAnalysis strict = analyze(s);  // default 1e-3 degrees
  EXPECT_NEAR(strict.joints[0].angle_deg, want, 1e-12);
  EXPECT_FALSE(strict.joints[0].g1);
  AnalyzeOptions o;
  o.continuity.angle_deg = 0.5;
  const SplineAnalysis loose = analyze(s, o);
  EXPECT_TRUE(loose.joints[0].g1);
  EXPECT_FALSE(loose.joints[0].g2);  // curvature differs by far more than 1e-6
  o.continuity.curvature_rel = 1;    // any two curvatures of one sign are within 100%
  EXPECT_TRUE(analyze(s, o).joints[0].g2);
  // Horizontal and vertical extrema, the usual smooth points of outlines, are exact.
  const BSpline h = BSpline::make(2, {0, 0, 1, 1, 2, 2}, {{0, 0}, {100, 0}, {171, 0}, {241, 0}, {400, 250}});
  EXPECT_TRUE(analyze(h).joints[0].g1);
  EXPECT_EQ(analyze(h).joints[0].angle_deg, 0.0);
  // Bad tolerances are input errors.
  o.continuity.angle_deg = -1;
  EXPECT_THROW(analyze(s, o), InputError);
  o.continuity.angle_deg = std::nan("");
  EXPECT_THROW(analyze(s, o), InputError);
  o.continuity = {};
  o.continuity.curvature_rel = 2;
  EXPECT_THROW(analyze(s, o), InputError);
}

TEST(Semantics, JointCurvatureIsCertifiedForAQuadraticAtOneE8) {
  // Uniform quadratic B-splines at 1e8, 3e-6 long, whose control polygon
  // bends by a few units in the last place (1.5e-8) across. At the joint between segments 0 and 1 (independent formula
  // from the control points): kappa_left = det(D1, D2)/|D2|^3 and
  // kappa_right = det(D2, D3)/|D2|^3 with D_i = P_i - P_{i-1}; det exact in
  // rationals, |D2|^2 exact, each rounded once.
  std::mt19937_64 rng(20240);
  std::uniform_real_distribution<double> u(-1, 1);
  const double ulp = std::nextafter(1e8, 2e8) - 1e8;  // 2^-26: the y offsets are a few units of it
  int sign_checked = 0;
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<Vec2> P;
    for (int i = 0; i < 4; ++i) P.push_back({1e8 + i * 1e-6, 1e8 + ulp * std::round(4 * u(rng))});
    const BSpline s = BSpline::make(2, {0, 1, 2, 3, 4}, P);
    const SplineAnalysis a = analyze(s);
    // (GMP expressions are lazy: every difference is made a Rational at once.)
    auto d = [&](int i) {
      return std::pair<Rational, Rational>{Rational(Rational(P[i].x) - Rational(P[i - 1].x)),
                                           Rational(Rational(P[i].y) - Rational(P[i - 1].y))};
    };
    using Pair = std::pair<Rational, Rational>;
    auto det = [](const Pair& p, const Pair& q) { return Rational(p.first * q.second - p.second * q.first); };
    const auto D1 = d(1), D2 = d(2), D3 = d(3);
    const double g = Rational(D2.first * D2.first + D2.second * D2.second).get_d();
    const double left = det(D1, D2).get_d() / g / std::sqrt(g), right = det(D2, D3).get_d() / g / std::sqrt(g);
    const Joint& j = a.joints[0];
    EXPECT_EQ(j.kappa_left > 0, left > 0) << "trial " << trial;
    EXPECT_EQ(j.kappa_right > 0, right > 0) << "trial " << trial;
    EXPECT_LE(std::fabs(j.kappa_left - left), 2 * kKappaRelError * std::fabs(left)) << "trial " << trial;
    EXPECT_LE(std::fabs(j.kappa_right - right), 2 * kKappaRelError * std::fabs(right)) << "trial " << trial;
    EXPECT_EQ(j.jump, right > left ? 1 : (right < left ? -1 : 0)) << "trial " << trial;
    // The plain double evaluation this replaced gets signs wrong here.
    sign_checked += (segment_end_curvature(s, s.segments()[0], 1) > 0) != (left > 0);
  }
  EXPECT_GT(sign_checked, 0) << "the test no longer exercises the hard case";
}

}  // namespace
}  // namespace cmr
