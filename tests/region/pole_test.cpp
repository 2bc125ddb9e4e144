// Poles of rational splines (W = 0 in a closed span, spline/bspline.hpp):
// exact detection (segment_poles) against independent computations, the
// forced verdicts of analyze, weights of mixed sign without a pole, negated
// weights (the same curve), and regions with a pole in or outside the
// judged segments.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "bezierize/analyze.hpp"
#include "region/region.hpp"
#include "region/region_setup.hpp"
#include "spline/curvature.hpp"
#include "tests/test_util.hpp"

namespace cmr {
namespace {

double weight_at(const BSpline& s, double t) { return homogeneous_derivative(s, t, 0).z; }

const std::vector<Vec2> kQuad = {{0, 0}, {1, 2}, {2, 0}};

// Uniform cubic with W(3) = (w1 + 4 w2 + w3) / 6 = 0: a root exactly at the
// knot 3, the joint between segments 0 = [2, 3] and 1 = [3, 4]; segment 2
// = [4, 5] has Bezier weights 3/4, 1, 1, 1 (no pole).
BSpline knot_pole_spline() {
  return BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7}, {{0, 0}, {1, 1.5}, {2.5, 2}, {4, 1}, {5, -0.5}, {6.5, 0.5}}, "knot_pole",
                       {1, 1, -0.5, 1, 1, 1});
}

// Quadratic Bezier weights a, b, c: W = a (1-t)^2 + 2 b t (1-t) + c t^2. With
// s = t / (1 - t), W / (1-t)^2 = a + 2 b s + c s^2, so W has a root in [0, 1]
// iff a = 0 or c = 0 (at an end), or a and c differ in sign, or (same sign)
// b has the other sign and the discriminant b^2 - a c >= 0: the closed form,
// exact on small integers.
bool quadratic_has_root(int a, int b, int c) {
  if (a == 0 || c == 0) return true;
  if ((a > 0) != (c > 0)) return true;
  return (b != 0 && (b > 0) != (a > 0)) && b * b >= a * c;
}

TEST(Pole, QuadraticBezierPolesMatchTheClosedForm) {
  int poles = 0, cases = 0;
  for (int a = -3; a <= 3; ++a)
    for (int b = -3; b <= 3; ++b)
      for (int c = -3; c <= 3; ++c) {
        if (a == 0 && b == 0 && c == 0) continue;
        const BSpline s = BSpline::bezier(kQuad, "", {double(a), double(b), double(c)});
        const std::vector<double> at = segment_poles(s, s.segments()[0]);
        ASSERT_EQ(!at.empty(), quadratic_has_root(a, b, c)) << a << " " << b << " " << c;
        for (double t : at) {
          EXPECT_GE(t, 0.0);
          EXPECT_LE(t, 1.0);
          if (!(a == 0 && b == 0) && !(b == 0 && c == 0)) {  // W == 0 on the span is reported {0, 1}
            EXPECT_LE(std::fabs(weight_at(s, t)), 1e-10) << a << " " << b << " " << c << " t " << t;
          }
        }
        poles += !at.empty();
        ++cases;
      }
  EXPECT_GT(poles, 50);
  EXPECT_LT(poles, cases - 50);
}

TEST(Pole, TouchingRootIsFoundExactlyAndNeighboursAreNot) {
  // (1, -1, 1): W = (1 - 2t)^2, a double root at 1/2 (no sign change).
  const BSpline touch = BSpline::bezier(kQuad, "", {1, -1, 1});
  EXPECT_EQ(segment_poles(touch, touch.segments()[0]), std::vector<double>{0.5});
  // The next double towards 0: W(1/2) = (1 + w1) / 2 > 0, no root at all.
  const BSpline above = BSpline::bezier(kQuad, "", {1, std::nextafter(-1.0, 0.0), 1});
  EXPECT_TRUE(segment_poles(above, above.segments()[0]).empty());
  // The next double away from 0: two simple roots near 1/2.
  const BSpline below = BSpline::bezier(kQuad, "", {1, std::nextafter(-1.0, -2.0), 1});
  const std::vector<double> two = segment_poles(below, below.segments()[0]);
  ASSERT_EQ(two.size(), 2u);
  EXPECT_NEAR(two[0], 0.5, 1e-7);
  EXPECT_NEAR(two[1], 0.5, 1e-7);
  EXPECT_LT(two[0], two[1]);
}

TEST(Pole, RootsAtTheEndsAndAtAKnot) {
  const BSpline start = BSpline::bezier(kQuad, "", {0, 1, 1});
  EXPECT_EQ(segment_poles(start, start.segments()[0]), std::vector<double>{0.0});
  const BSpline end = BSpline::bezier(kQuad, "", {1, 1, 0});
  EXPECT_EQ(segment_poles(end, end.segments()[0]), std::vector<double>{1.0});
  const BSpline s = knot_pole_spline();
  ASSERT_EQ(weight_at(s, 3.0), 0.0);
  EXPECT_EQ(segment_poles(s, s.segments()[0]), std::vector<double>{3.0});
  EXPECT_EQ(segment_poles(s, s.segments()[1]), std::vector<double>{3.0});
  EXPECT_TRUE(segment_poles(s, s.segments()[2]).empty());
  // A polynomial spline never has one.
  const BSpline poly = BSpline::bezier(kQuad);
  EXPECT_TRUE(segment_poles(poly, poly.segments()[0]).empty());
}

TEST(Pole, RandomSplinesAgreeWithDenseSamplingOfW) {
  // Independent route: W sampled densely in double. A strict sign change
  // between two samples must be a reported pole between them; a span without
  // a reported pole keeps one strict sign at every sample; every reported
  // pole is a zero of W (within evaluation error).
  std::mt19937_64 rng(1313);
  std::uniform_real_distribution<double> weight(-1, 2);
  int with = 0, without = 0;
  for (int trial = 0; trial < 60; ++trial) {
    std::vector<double> w;
    for (int i = 0; i < 7; ++i) w.push_back(weight(rng));
    const BSpline s = BSpline::make(3, {0, 0.5, 1, 2, 2.5, 3.5, 4, 5, 6}, test::random_points(rng, 7, 2.0), "", w);
    for (const Segment& seg : s.segments()) {
      const std::vector<double> at = segment_poles(s, seg);
      constexpr int kSamples = 2000;
      double prev = weight_at(s, seg.a);
      bool change = false, zero = prev == 0;
      for (int k = 1; k <= kSamples; ++k) {
        const double t = seg.a + (seg.b - seg.a) * k / kSamples;
        const double cur = k == kSamples ? homogeneous_derivative(s, seg.a + (seg.b - seg.a), 0).z : weight_at(s, t);
        if ((prev < 0 && cur > 0) || (prev > 0 && cur < 0)) {
          change = true;
          const double lo = seg.a + (seg.b - seg.a) * (k - 1) / kSamples;
          bool inside = false;
          for (double p : at) inside = inside || (p >= lo - 1e-12 && p <= t + 1e-12);
          EXPECT_TRUE(inside) << "trial " << trial << " segment " << seg.index << ": sign change in [" << lo << ", " << t
                              << "] without a reported pole";
        }
        zero = zero || cur == 0;
        prev = cur;
      }
      if (at.empty()) {
        EXPECT_FALSE(change || zero) << "trial " << trial << " segment " << seg.index;
      }
      for (double p : at) {
        EXPECT_GE(p, seg.a);
        EXPECT_LE(p, seg.b);
        EXPECT_LE(std::fabs(weight_at(s, p)), 1e-10) << "trial " << trial << " segment " << seg.index << " t " << p;
      }
      (at.empty() ? without : with) += 1;
    }
  }
  EXPECT_GT(with, 20);
  EXPECT_GT(without, 20);
}

TEST(Pole, AnalyzeForcesThePoleSegmentsAndTheirJoints) {
  const BSpline s = knot_pole_spline();
  const SplineAnalysis a = analyze(s);
  EXPECT_TRUE(a.pole);
  ASSERT_EQ(a.shapes.size(), 3u);
  for (int i : {0, 1}) {
    EXPECT_TRUE(a.shapes[i].pole);
    EXPECT_STREQ(shape_class(a.shapes[i]), "pole");
    EXPECT_EQ(a.segments[i].monotonicity.curvature, Curvature::non_monotone);
    EXPECT_EQ(a.segments[i].inflection.inflection, Inflection::present);
  }
  EXPECT_FALSE(a.shapes[2].pole);
  ASSERT_EQ(a.joints.size(), 2u);
  const Joint& j = a.joints[0];  // W(3) = 0: the joint is a pole
  EXPECT_TRUE(j.pole);
  EXPECT_TRUE(std::isnan(j.kappa_left) && std::isnan(j.kappa_right) && std::isnan(j.angle_deg));
  EXPECT_FALSE(j.g1);
  EXPECT_FALSE(j.g2);
  EXPECT_EQ(j.jump, 0);
  // W(4) = 3/4: joint 2 is measured as usual (C2: curvature continuous),
  // against the pointwise formula just before it.
  const Joint& k = a.joints[1];
  EXPECT_FALSE(k.pole);
  EXPECT_TRUE(k.g1 && k.g2);
  EXPECT_NEAR(k.kappa_left, curvature_at(s, 4 - 1e-9).kappa, 1e-6 * std::fabs(k.kappa_left));
  EXPECT_NEAR(k.kappa_right, k.kappa_left, 1e-9 * std::fabs(k.kappa_left));
  EXPECT_EQ(a.shapes[0].inflection, Inflection::present);  // forced
  EXPECT_EQ(a.cmrwi, Direction::none);
  EXPECT_EQ(a.cmr, Direction::none);
  EXPECT_EQ(a.cmr_algorithm2, Direction::none);
  // Judging segment 2 alone: the poles do not matter.
  AnalyzeOptions only2;
  only2.segments = SegmentRange{2, 2};
  const SplineAnalysis b = analyze(s, only2);
  const Curvature c2 = classify_segment(s, s.segments()[2], {}).monotonicity.curvature;
  EXPECT_EQ(b.segments[2].monotonicity.curvature, c2);
  EXPECT_EQ(b.cmrwi, c2 == Curvature::increasing ? Direction::increasing
                     : c2 == Curvature::decreasing ? Direction::decreasing : Direction::none);
}

// Weights (1, -1, -1, -1, -1, -1) on uniform cubic knots: every span's Bezier
// weights are negative (the first is (1 - 4 - 1) / 6), so W < 0 throughout and
// there is no pole, though the weights have mixed signs (so they are kept).
const std::vector<Vec2> kWave = {{0, 0}, {1, 1.2}, {2.2, 1.4}, {3.1, 0.3}, {4.4, -0.6}, {5.5, 0.2}};

TEST(Pole, MixedSignWeightsWithoutARootAreNoPole) {
  const BSpline neg = BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7}, kWave, "", {1, -1, -1, -1, -1, -1});
  ASSERT_TRUE(neg.is_rational());
  for (const Segment& seg : neg.segments()) {
    EXPECT_TRUE(segment_poles(neg, seg).empty());
    EXPECT_EQ(weight_sign(neg, seg), -1);
  }
  // A quadratic whose middle weight is negative and W stays > 0 (min 0.45).
  const BSpline dip = BSpline::bezier(kQuad, "", {1, -0.1, 1});
  EXPECT_TRUE(segment_poles(dip, dip.segments()[0]).empty());
  EXPECT_EQ(weight_sign(dip, dip.segments()[0]), 1);
  const SplineAnalysis a = analyze(dip);
  EXPECT_FALSE(a.pole);
  EXPECT_STRNE(shape_class(a.shapes[0]), "pole");
  // The curvature's sign is W's times D's: check it against the pointwise
  // formula kappa = W^3 D / |h|^3 (curvature.hpp) at the middle.
  const double kappa = curvature_at(dip, 0.5).kappa;
  ASSERT_NE(kappa, 0.0);
  EXPECT_EQ(a.shapes[0].kappa_sign, kappa > 0 ? 1 : -1);
  // A C1 quadratic whose first span has Bezier weights 0.4, -0.2, 0.4 (no
  // pole): the joint's curvatures come from the division-free end_terms;
  // against the pointwise formula on either side, and the jump's sign.
  const BSpline c1 = BSpline::make(2, {0, 1, 2, 3, 4}, {{0, 0}, {1, 1}, {2, -0.5}, {3, 0.5}}, "", {1, -0.2, 1, 1});
  const SplineAnalysis j = analyze(c1);
  ASSERT_FALSE(j.pole);
  ASSERT_EQ(j.joints.size(), 1u);
  const double kl = curvature_at(c1, 2 - 1e-9).kappa, kr = curvature_at(c1, 2 + 1e-9).kappa;
  EXPECT_NEAR(j.joints[0].kappa_left, kl, 1e-6 * std::fabs(kl));
  EXPECT_NEAR(j.joints[0].kappa_right, kr, 1e-6 * std::fabs(kr));
  ASSERT_GT(std::fabs(kr - kl), 1e-3 * std::fabs(kl));
  EXPECT_EQ(j.joints[0].jump, kr > kl ? 1 : -1);
}

TEST(Pole, NegatedWeightsGiveTheSameVerdictsCurvaturesAndRegions) {
  // -w describes the same curve as w (X / W = (-X) / (-W)); neither is all
  // negative, so both are kept as given. Everything analyze states must agree,
  // the certified curvatures to their bound.
  const std::vector<double> w = {1, -1, -1, -1.5, -1, -1.25};
  std::vector<double> minus;
  for (double x : w) minus.push_back(-x);
  for (const std::vector<double>& knots : {std::vector<double>{0, 1, 2, 3, 4, 5, 6, 7},
                                           std::vector<double>{0, 1, 2, 2, 4, 5, 6, 7}}) {
    const BSpline s = BSpline::make(3, knots, kWave, "", w);
    const BSpline t = BSpline::make(3, knots, kWave, "", minus);
    for (int i = 0; i <= 10; ++i) {
      const double u = s.domain_begin() + (s.domain_end() - s.domain_begin()) * i / 10;
      EXPECT_NEAR(evaluate(s, u).x, evaluate(t, u).x, 1e-12);
      EXPECT_NEAR(evaluate(s, u).y, evaluate(t, u).y, 1e-12);
    }
    const SplineAnalysis a = analyze(s), b = analyze(t);
    ASSERT_FALSE(a.pole);
    EXPECT_EQ(a.cmrwi, b.cmrwi);
    EXPECT_EQ(a.cmr, b.cmr);
    EXPECT_EQ(a.cmr_algorithm2, b.cmr_algorithm2);
    for (std::size_t i = 0; i < a.segments.size(); ++i) {
      EXPECT_EQ(a.segments[i].monotonicity.curvature, b.segments[i].monotonicity.curvature);
      EXPECT_EQ(a.segments[i].inflection.inflection, b.segments[i].inflection.inflection);
      EXPECT_EQ(a.shapes[i].kappa_sign, b.shapes[i].kappa_sign);
      EXPECT_EQ(a.shapes[i].inflection, b.shapes[i].inflection);
      // The true curvature sign, against the pointwise formula (W < 0 here).
      const Segment& seg = s.segments()[i];
      EXPECT_EQ(weight_sign(s, seg), -1);
      if (a.shapes[i].inflection == Inflection::none) {
        const double k = curvature_at(s, 0.5 * (seg.a + seg.b)).kappa;
        EXPECT_EQ(a.shapes[i].kappa_sign, k > 0 ? 1 : -1) << "segment " << i;
      }
    }
    for (std::size_t i = 0; i < a.joints.size(); ++i) {
      // Both certified (kKappaRelError): -w > 0 takes the classical form,
      // w the division-free one (end_terms), so they agree to that bound.
      EXPECT_NEAR(a.joints[i].kappa_left, b.joints[i].kappa_left, 2 * kKappaRelError * std::fabs(b.joints[i].kappa_left));
      EXPECT_NEAR(a.joints[i].kappa_right, b.joints[i].kappa_right, 2 * kKappaRelError * std::fabs(b.joints[i].kappa_right));
      EXPECT_EQ(a.joints[i].jump, b.joints[i].jump);
      EXPECT_EQ(a.joints[i].g1, b.joints[i].g1);
      EXPECT_NEAR(a.joints[i].kappa_left, curvature_at(s, a.joints[i].knot - 1e-9).kappa,
                  1e-6 * std::fabs(a.joints[i].kappa_left) + 1e-9);
    }
    // The region engine (segment 1 judged): identical label maps in both
    // modes, and the labels of analyze of the moved spline (W < 0 there).
    int nonzero = 0;
    for (const Mode mode : {Mode::cmrwi, Mode::cmr})
      for (int point = 1; point <= 4; ++point) {
      RegionRequest o;
      o.point = point;
      o.width = o.height = 24;
      o.mode = mode;
      o.segments = SegmentRange{1, 1};
      const RegionResult ra = CpuRegionBackend().render(RegionProblem::make(s, o));
      const RegionResult rb = CpuRegionBackend().render(RegionProblem::make(t, o));
      for (int p = 0; p < o.width * o.height; ++p) {
        ASSERT_EQ(ra.code_at(p), rb.code_at(p)) << "point " << point << " pixel " << p;
        nonzero += ra.code_at(p) != 0;
        if (p % 5 != 0) continue;
        AnalyzeOptions ao;
        ao.segments = o.segments;
        const SplineAnalysis m = analyze(s.with_point(point, pixel_center(ra.view, o.width, o.height, p % o.width, p / o.width)), ao);
        ASSERT_EQ(int(ra.code_at(p)), int(code(mode == Mode::cmr ? m.cmr_algorithm2 : m.cmrwi)))
            << "point " << point << " pixel " << p;
      }
    }
    EXPECT_GT(nonzero, 0);
  }
}

TEST(Pole, RegionPixelsEqualAnalyzeOfTheMovedSpline) {
  // A pole in a judged segment: every position fails (the weights, hence W,
  // do not move). A pole outside the judged segments does not matter.
  const BSpline s = knot_pole_spline();
  struct Case {
    int point;
    std::optional<SegmentRange> segments;
  };
  int nonzero = 0;
  for (const Case& c : {Case{3, {}}, Case{0, {}}, Case{4, SegmentRange{2, 2}}, Case{5, SegmentRange{2, 2}}}) {
    RegionRequest o;
    o.point = c.point;
    o.width = o.height = 20;
    o.segments = c.segments;
    const RegionProblem problem = RegionProblem::make(s, o);
    const RegionResult img = CpuRegionBackend().render(problem);
    for (int j = 0; j < o.height; ++j)
      for (int i = 0; i < o.width; ++i) {
        const Vec2 p = pixel_center(img.view, o.width, o.height, i, j);
        AnalyzeOptions ao;
        ao.segments = c.segments;
        const int want = code(analyze(s.with_point(c.point, p), ao).cmrwi);
        ASSERT_EQ(img.code_at(j * o.width + i), want) << "point " << c.point << " pixel (" << i << ", " << j << ")";
        ASSERT_EQ(int(code(problem.classify(p).label)), want);
        if (!c.segments) {
          ASSERT_EQ(want, 0);
        }
        nonzero += want != 0;
      }
  }
  EXPECT_GT(nonzero, 0);
}

}  // namespace
}  // namespace cmr
