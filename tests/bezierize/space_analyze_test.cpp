// analyze_space (bezierize/space_analyze.hpp, issue 25): certified curvature
// and torsion monotonicity of space curves.
#include "bezierize/space_analyze.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "bezierize/analyze.hpp"
#include "numeric/roots.hpp"
#include "bezierize/space_classify.hpp"
#include "bezierize/space_lambda.hpp"
#include "spline/errors.hpp"

namespace cmr {
namespace {

std::vector<Vec3> random_points3(std::mt19937_64& rng, int count, double scale = 2.0) {
  std::uniform_real_distribution<double> u(-scale, scale);
  std::vector<Vec3> p(count);
  for (Vec3& q : p) q = Vec3(u(rng), u(rng), u(rng));
  return p;
}

std::vector<double> open_uniform(int d, int m) {  // polar, clamped, m points
  std::vector<double> k;
  for (int i = 0; i < d - 1; ++i) k.push_back(0);
  for (int i = 0; i <= m - d; ++i) k.push_back(i);
  for (int i = 0; i < d - 1; ++i) k.push_back(m - d);
  return k;
}

glm::dmat3 random_rotation(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1, 1), ang(0, 6.283185307179586);
  const glm::dvec3 axis = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)) + glm::dvec3(1e-3, 0, 0));
  return glm::dmat3(glm::rotate(glm::dmat4(1.0), ang(rng), axis));
}

SpaceSpline transformed(const SpaceSpline& s, const glm::dmat3& M, Vec3 offset, double scale) {
  std::vector<Vec3> pts;
  for (int k = 0; k < s.unique_point_count(); ++k) pts.push_back(scale * (M * s.points()[k]) + offset);
  const std::vector<double> w(s.weights().begin(), s.weights().begin() + (s.is_rational() ? s.unique_point_count() : 0));
  return SpaceSpline::make(s.degree(), s.knots(), pts, "", w);
}

// Direction of kappa on a dense sample: +1 non-decreasing, -1 non-increasing, 0 both ways.
int sampled_direction(const SpaceSpline& s, const Segment& seg, bool torsion) {
  bool up = false, down = false;
  double prev = 0;
  for (int i = 0; i <= 400; ++i) {
    const double t = seg.a + (seg.b - seg.a) * (0.001 + 0.998 * i / 400.0);
    const double v = torsion ? space_torsion(s, t) : space_curvature(s, t);
    if (i > 0) {
      const double tol = 1e-9 * (1 + std::fabs(v));
      up = up || v > prev + tol;
      down = down || v < prev - tol;
    }
    prev = v;
  }
  return up && down ? 0 : (down ? -1 : 1);
}

TEST(SpaceAnalyze, CertifiedSegmentClassesAgreeWithDenseSamplingOfKappaAndTau) {
  std::mt19937_64 rng(2025);
  int checked = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const int d = 2 + trial % 4, m = d + 1 + trial % 3;
    const SpaceSpline s = SpaceSpline::make(d, open_uniform(d, m), random_points3(rng, m));
    SpaceAnalyzeOptions o;
    o.torsion = true;
    const SpaceAnalysis a = analyze_space(s, o);
    for (const Segment& seg : s.segments()) {
      const SpaceSegmentResult& r = a.segments[seg.index];
      if (r.cusp) continue;
      const auto check = [&](Curvature c, bool torsion) {
        const int dir = sampled_direction(s, seg, torsion);
        if (c == Curvature::increasing) {
          EXPECT_EQ(dir, 1) << "trial " << trial << " seg " << seg.index << " torsion " << torsion;
        }
        if (c == Curvature::decreasing) {
          EXPECT_EQ(dir, -1) << "trial " << trial << " seg " << seg.index << " torsion " << torsion;
        }
        ++checked;
      };
      check(r.curvature.curvature, false);
      if (r.zero_curvature.empty() && d >= 3) check(r.torsion->curvature, true);
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(SpaceAnalyze, StraightSegmentIsConstantAndQuadraticHasZeroTorsion) {
  const SpaceAnalysis line = analyze_space(SpaceSpline::bezier({{0, 0, 0}, {1, 1, 1}, {3, 3, 3}, {4, 4, 4}}));
  EXPECT_EQ(line.segments[0].curvature.curvature, Curvature::constant);
  EXPECT_TRUE(line.segments[0].straight);
  EXPECT_TRUE(line.segments[0].zero_curvature.empty());
  EXPECT_EQ(line.curvature, Direction::increasing);  // all constant: Algorithm 1 checks (1) first
  SpaceAnalyzeOptions o;
  o.torsion = true;
  const SpaceAnalysis q = analyze_space(SpaceSpline::bezier({{0, 0, 0}, {1, 2, 3}, {3, 1, -1}}), o);
  EXPECT_EQ(q.segments[0].torsion->curvature, Curvature::constant);
  EXPECT_EQ(q.segments[0].torsion_sign, 0);
}

// Bezier points of the polynomial curve (u, u^3, u^4), u = 2t - 1 in [-1, 1],
// at degree 4 from the blossoms of the monomials: u^p -> e_p(args) / C(4, p).
std::vector<Vec3> twisted_quartic() {
  const auto blossom = [](int p, int k) {  // args: 4-k times -1, k times +1
    double e = 0;
    for (int mask = 0; mask < 16; ++mask) {
      if (__builtin_popcount(mask) != p) continue;
      double prod = 1;
      for (int i = 0; i < 4; ++i)
        if (mask & (1 << i)) prod *= i < 4 - k ? -1.0 : 1.0;
      e += prod;
    }
    const double binom[] = {1, 4, 6, 4, 1};
    return e / binom[p];
  };
  std::vector<Vec3> B;
  for (int k = 0; k <= 4; ++k) B.emplace_back(blossom(1, k), blossom(3, k), blossom(4, k));
  return B;
}

TEST(SpaceAnalyze, ZeroCurvaturePointOfAGenuineSpaceCurveIsFoundExactly) {
  // c = P' x P'' = (12u^4, -12u^2, 6u) (times the chain rule's factor) vanishes at u = 0 only: t = 1/2.
  const SpaceAnalysis a = analyze_space(SpaceSpline::bezier(twisted_quartic()));
  ASSERT_EQ(a.segments[0].zero_curvature.size(), 1u);
  EXPECT_EQ(a.segments[0].zero_curvature[0], 0.5);
  EXPECT_TRUE(a.zero_curvature);
  EXPECT_EQ(a.segments[0].curvature.curvature, Curvature::non_monotone);  // |kappa| has a minimum there
  EXPECT_EQ(a.curvature, Direction::none);
  EXPECT_FALSE(a.segments[0].cusp);
}

// One half of a Bezier curve by de Casteljau at 1/2.
std::vector<Vec3> half(const std::vector<Vec3>& B, bool right) {
  std::vector<std::vector<Vec3>> tri{B};
  for (std::size_t r = 1; r < B.size(); ++r) {
    std::vector<Vec3> row;
    for (std::size_t i = 0; i + 1 < tri.back().size(); ++i) row.push_back(0.5 * (tri.back()[i] + tri.back()[i + 1]));
    tri.push_back(row);
  }
  std::vector<Vec3> out;
  for (std::size_t r = 0; r < B.size(); ++r) out.push_back(right ? tri[B.size() - 1 - r].back() : tri[r].front());
  return out;
}

TEST(SpaceAnalyze, ZeroCurvatureAtTheStartIsNotAViolation) {
  // u in [0, 1/4] of the twisted quartic: kappa grows from 0 at the start.
  const SpaceSpline s = SpaceSpline::bezier(half(half(half(twisted_quartic(), true), false), false));
  const SpaceAnalysis a = analyze_space(s);
  ASSERT_EQ(a.segments[0].zero_curvature, std::vector<double>{0.0});
  EXPECT_EQ(sampled_direction(s, s.segments()[0], false), 1);
  EXPECT_EQ(a.segments[0].curvature.curvature, Curvature::increasing);
  EXPECT_EQ(a.curvature, Direction::increasing);
}

TEST(SpaceAnalyze, CuspIsReported) {
  // x' = 6 (1 - 2t)^2, y' = z' = 3 (1 - 2t + 2t^2) > 0: no cusp.
  const SpaceAnalysis sym = analyze_space(SpaceSpline::bezier({{0, 0, 0}, {2, 1, 1}, {0, 1, 1}, {2, 2, 2}}));
  EXPECT_FALSE(sym.segments[0].cusp);
  EXPECT_FALSE(sym.cusp);
  // P' = 6 (1 - 2t)^2 (1, 1, 1): zero at t = 1/2.
  const SpaceAnalysis real = analyze_space(SpaceSpline::bezier({{0, 0, 0}, {2, 2, 2}, {0, 0, 0}, {2, 2, 2}}));
  EXPECT_TRUE(real.segments[0].cusp);
  EXPECT_TRUE(real.cusp);
}

// A planar spline rotated into space gets the plane's verdicts on |kappa|:
// the plane's CMR direction where kappa > 0, the opposite where kappa < 0,
// and none wherever the plane's is none or has an inflection.
TEST(SpaceAnalyze, PlanarSplineRotatedIntoSpaceGetsThePlanesVerdicts) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-2, 2);
  int compared = 0, monotone = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int d = 2 + trial % 3, m = d + 1 + trial % 2;
    std::vector<Vec2> P(m);
    for (Vec2& p : P) p = Vec2(u(rng), u(rng));
    if (trial % 4 == 0) {  // gentle arcs, often monotone
      for (int i = 0; i < m; ++i) P[i] = Vec2(i, 0.3 * i * i + 0.1 * u(rng));
    }
    const BSpline plane = BSpline::make(d, open_uniform(d, m), P);
    AnalyzeOptions o2;
    o2.classify.max_depth = 12;
    const SplineAnalysis a2 = analyze(plane, o2);
    const glm::dmat3 M = random_rotation(rng);
    const SpaceSpline space = transformed(SpaceSpline::embed(plane), M, Vec3(u(rng), u(rng), u(rng)), 1.0);
    SpaceAnalyzeOptions o3;
    o3.max_depth = 12;
    const SpaceAnalysis a3 = analyze_space(space, o3);
    if (a2.cusp || a2.cmrwi == Direction::undecided || a2.cmr == Direction::undecided ||
        a3.curvature == Direction::undecided)
      continue;
    Direction want = Direction::none;
    if (a2.cmr != Direction::none) {
      int sign = 0;
      for (const SegmentShape& sh : a2.shapes) sign = sign != 0 ? sign : sh.kappa_sign;
      want = sign >= 0 ? a2.cmr : (a2.cmr == Direction::increasing ? Direction::decreasing : Direction::increasing);
      ++monotone;
    }
    EXPECT_EQ(to_string(a3.curvature), std::string(to_string(want))) << "trial " << trial;
    ++compared;
  }
  EXPECT_GT(compared, 150);
  EXPECT_GT(monotone, 20);
}

TEST(SpaceAnalyze, VerdictsAreInvariantUnderRotationTranslationAndUniformScaling) {
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> u(-5, 5), sc(0.1, 10);
  int compared = 0;
  for (int trial = 0; trial < 80; ++trial) {
    const int d = 2 + trial % 4, m = d + 1 + trial % 4;
    const SpaceSpline s = SpaceSpline::make(d, open_uniform(d, m), random_points3(rng, m));
    SpaceAnalyzeOptions o;
    o.torsion = true;
    const SpaceAnalysis a = analyze_space(s, o);
    const SpaceSpline t = transformed(s, random_rotation(rng), Vec3(u(rng), u(rng), u(rng)), sc(rng));
    const SpaceAnalysis b = analyze_space(t, o);
    ASSERT_EQ(a.segments.size(), b.segments.size());
    for (std::size_t i = 0; i < a.segments.size(); ++i) {
      EXPECT_EQ(a.segments[i].curvature.curvature, b.segments[i].curvature.curvature) << "trial " << trial << " seg " << i;
      EXPECT_EQ(a.segments[i].torsion->curvature, b.segments[i].torsion->curvature) << "trial " << trial << " seg " << i;
      EXPECT_EQ(a.segments[i].zero_curvature.size(), b.segments[i].zero_curvature.size()) << "trial " << trial;
    }
    for (std::size_t i = 0; i < a.joints.size(); ++i) EXPECT_EQ(a.joints[i].jump, b.joints[i].jump) << "trial " << trial;
    EXPECT_EQ(a.curvature, b.curvature) << "trial " << trial;
    EXPECT_EQ(*a.torsion, *b.torsion) << "trial " << trial;
    ++compared;
  }
  EXPECT_EQ(compared, 80);
}

TEST(SpaceAnalyze, JointsMeasureKappaTauAndG1G2) {
  // C1 joint (double knot, cubic): tangents agree, curvature generally jumps.
  const SpaceSpline s = SpaceSpline::make(3, {0, 0, 0, 1, 1, 2, 2, 2},
                                          {{0, 0, 0}, {1, 1, 0.5}, {2, 1, 1}, {3, 1.5, 1.2}, {4, 3, 1}, {5, 3, 3}});
  const SpaceAnalysis a = analyze_space(s);
  ASSERT_EQ(a.joints.size(), 1u);
  const SpaceJoint& j = a.joints[0];
  EXPECT_EQ(j.continuity, 1);
  EXPECT_EQ(j.angle_deg, 0.0);
  EXPECT_TRUE(j.g1);
  EXPECT_NEAR(j.kappa_left, space_curvature(s, std::nextafter(1.0, 0.0)), 1e-9);
  EXPECT_NEAR(j.kappa_right, space_curvature(s, 1.0), 1e-9);
  EXPECT_NEAR(j.tau_right, space_torsion(s, 1.0), 1e-9 * (1 + std::fabs(j.tau_right)));
  EXPECT_NEAR(j.tau_left, space_torsion(s, std::nextafter(1.0, 0.0)), 1e-6 * (1 + std::fabs(j.tau_left)));
  EXPECT_EQ(j.jump, j.kappa_right > j.kappa_left ? 1 : -1);
  EXPECT_FALSE(j.g2);
  // C2 (uniform cubic): G2, no jump.
  std::mt19937_64 rng5(5);
  const SpaceSpline u = SpaceSpline::make(3, {0, 1, 2, 3, 4, 5, 6}, random_points3(rng5, 5));
  for (const SpaceJoint& k : analyze_space(u).joints) {
    EXPECT_TRUE(k.g2);
    EXPECT_EQ(k.jump, 0);
    EXPECT_EQ(k.normal_angle_deg, 0.0);
  }
}

TEST(SpaceAnalyze, ClosedSplineJudgesTheSeam) {
  const SpaceSpline s = SpaceSpline::make_closed(3, {0, 1, 2, 3, 4}, {{1, 0, 0}, {0, 1, 1}, {-1, 0, 0}, {0, -1, -1}});
  const SpaceAnalysis a = analyze_space(s);
  ASSERT_TRUE(a.seam.has_value());
  EXPECT_EQ(a.seam->index, 4);
  EXPECT_TRUE(a.seam->g2);
  EXPECT_EQ(a.curvature, Direction::none);  // a closed smooth loop cannot have monotone curvature unless constant
}

TEST(SpaceAnalyze, CurvatureExtremaAreWhereSampledKappaTurns) {
  std::mt19937_64 rng(31);
  int found = 0;
  for (int trial = 0; trial < 30; ++trial) {
    const SpaceSpline s = SpaceSpline::bezier(random_points3(rng, 4));
    const Segment& seg = s.segments()[0];
    for (const SpaceExtremum& e : space_curvature_extrema(s, seg)) {
      const double h = 1e-4, k = space_curvature(s, e.t), l = space_curvature(s, e.t - h), r = space_curvature(s, e.t + h);
      if (e.maximum) {
        EXPECT_GE(k, std::max(l, r)) << "trial " << trial << " t " << e.t;
      } else {
        EXPECT_LE(k, std::min(l, r)) << "trial " << trial << " t " << e.t;
      }
      ++found;
    }
    if (analyze_space(s).segments[0].curvature.curvature == Curvature::increasing) {
      EXPECT_TRUE(space_curvature_extrema(s, seg).empty()) << "trial " << trial;
    }
  }
  EXPECT_GT(found, 10);
}

TEST(SpaceAnalyze, TorsionSignChangesAreWhereSampledTorsionChangesSign) {
  std::mt19937_64 rng(57);
  SpaceAnalyzeOptions o;
  o.torsion = true;
  int changes = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const SpaceSpline s = SpaceSpline::bezier(random_points3(rng, 5));  // quartic: N of degree 3
    const SpaceSegmentResult r = analyze_space(s, o).segments[0];
    if (!r.zero_curvature.empty()) continue;
    int sampled = 0;
    double prev = space_torsion(s, 1e-6);
    for (int i = 1; i <= 2000; ++i) {
      const double v = space_torsion(s, std::min(1.0 - 1e-6, i / 2000.0));
      sampled += (v > 0) != (prev > 0);
      prev = v;
    }
    EXPECT_EQ(static_cast<int>(r.torsion_sign_changes.size()), sampled) << "trial " << trial;
    if (r.torsion_sign != 0) {
      EXPECT_TRUE(r.torsion_sign_changes.empty()) << "trial " << trial;
    }
    for (double t : r.torsion_sign_changes) {
      EXPECT_LT(space_torsion(s, t - 1e-5) * space_torsion(s, t + 1e-5), 0) << "trial " << trial << " t " << t;
    }
    changes += static_cast<int>(r.torsion_sign_changes.size());
  }
  EXPECT_GT(changes, 5);
}

// torsion_sign follows the exact root isolation: a segment whose torsion
// numerator N has no root on the closed span has one strict sign there, even
// where N's Bernstein coefficients change sign (about 1 in 70 random quartic
// segments). The reference: isolate_roots on the exact N, and the sign of N
// in the middle of the span.
TEST(SpaceAnalyze, TorsionSignIsStrictWhereTheNumeratorHasNoRootOnTheSpan) {
  std::mt19937_64 rng(91);
  SpaceAnalyzeOptions o;
  o.torsion = true;
  int mixed_without_roots = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const SpaceSpline s = SpaceSpline::bezier(random_points3(rng, 5));
    const SpaceWindow w = space_window(s, s.segments()[0]);
    const Bernstein<Rational> N =
        torsion_numerator_bernstein<Rational>(space_window_bezier<Rational>(w, space_window_points<Rational>(s, w)));
    if (is_zero(N) || !isolate_roots(N).empty()) continue;
    const int want = sgn(bernstein_eval(N, Rational(1, 2)));
    mixed_without_roots += strict_sign(N) == 0;
    EXPECT_EQ(analyze_space(s, o).segments[0].torsion_sign, want) << "trial " << trial;
  }
  EXPECT_GE(mixed_without_roots, 1);
}

TEST(SpaceAnalyze, BadOptionsAreInputErrors) {
  SpaceAnalyzeOptions o;
  o.max_depth = 99;
  EXPECT_THROW(analyze_space(SpaceSpline::bezier({{0, 0, 0}, {1, 1, 1}, {2, 0, 0}}), o), InputError);
}

// ---- rational space curves ----

std::vector<double> random_weights(std::mt19937_64& rng, int count) {
  std::uniform_real_distribution<double> u(0.25, 4);
  std::vector<double> w(count);
  for (double& x : w) x = u(rng);
  return w;
}

TEST(RationalSpaceAnalyze, CertifiedSegmentClassesAgreeWithDenseSamplingOfKappaAndTau) {
  std::mt19937_64 rng(2026);
  int checked = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const int d = 2 + trial % 4, m = d + 1 + trial % 3;
    const SpaceSpline s = SpaceSpline::make(d, open_uniform(d, m), random_points3(rng, m), "", random_weights(rng, m));
    ASSERT_TRUE(s.is_rational());
    SpaceAnalyzeOptions o;
    o.torsion = true;
    const SpaceAnalysis a = analyze_space(s, o);
    for (const Segment& seg : s.segments()) {
      const SpaceSegmentResult& r = a.segments[seg.index];
      if (r.cusp) continue;
      const auto check = [&](Curvature c, bool torsion) {
        const int dir = sampled_direction(s, seg, torsion);
        if (c == Curvature::increasing) {
          EXPECT_EQ(dir, 1) << "trial " << trial << " seg " << seg.index << " torsion " << torsion;
        }
        if (c == Curvature::decreasing) {
          EXPECT_EQ(dir, -1) << "trial " << trial << " seg " << seg.index << " torsion " << torsion;
        }
        ++checked;
      };
      check(r.curvature.curvature, false);
      if (r.zero_curvature.empty() && d >= 3) check(r.torsion->curvature, true);
      // The sign of Nr is the sign of tau.
      if (d >= 3 && r.torsion_sign != 0) {
        const double tau = space_torsion(s, 0.5 * (seg.a + seg.b));
        EXPECT_EQ(tau > 0 ? 1 : -1, r.torsion_sign) << "trial " << trial << " seg " << seg.index;
      }
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(RationalSpaceAnalyze, PlanarRationalSplineRotatedIntoSpaceGetsThePlanesVerdicts) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-2, 2), uw(0.25, 4);
  int compared = 0, monotone = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int d = 2 + trial % 3, m = d + 1 + trial % 2;
    std::vector<Vec2> P(m);
    std::vector<double> w(m);
    for (Vec2& p : P) p = Vec2(u(rng), u(rng));
    for (double& x : w) x = uw(rng);
    if (trial % 2 == 0) {  // gentle arcs with near-equal weights, often monotone
      for (int i = 0; i < m; ++i) P[i] = Vec2(i, 0.3 * i * i + 0.1 * u(rng));
      for (double& x : w) x = 1 + 0.02 * u(rng);
    }
    const BSpline plane = BSpline::make(d, open_uniform(d, m), P, "", w);
    ASSERT_TRUE(plane.is_rational());
    AnalyzeOptions o2;
    o2.classify.max_depth = 12;
    const SplineAnalysis a2 = analyze(plane, o2);
    const SpaceSpline embedded = SpaceSpline::embed(plane);
    ASSERT_TRUE(embedded.is_rational());
    const SpaceSpline space = transformed(embedded, random_rotation(rng), Vec3(u(rng), u(rng), u(rng)), 1.0);
    SpaceAnalyzeOptions o3;
    o3.max_depth = 12;
    const SpaceAnalysis a3 = analyze_space(space, o3);
    // The unrotated embedding gets the same verdict too (exact data, no rounding).
    EXPECT_EQ(analyze_space(embedded, o3).curvature, a3.curvature) << "trial " << trial;
    if (a2.cusp || a2.cmrwi == Direction::undecided || a2.cmr == Direction::undecided ||
        a3.curvature == Direction::undecided)
      continue;
    Direction want = Direction::none;
    if (a2.cmr != Direction::none) {
      int sign = 0;
      for (const SegmentShape& sh : a2.shapes) sign = sign != 0 ? sign : sh.kappa_sign;
      want = sign >= 0 ? a2.cmr : (a2.cmr == Direction::increasing ? Direction::decreasing : Direction::increasing);
      ++monotone;
    }
    EXPECT_EQ(to_string(a3.curvature), std::string(to_string(want))) << "trial " << trial;
    ++compared;
  }
  EXPECT_GT(compared, 150);
  EXPECT_GT(monotone, 20);
}

void expect_same_verdicts(const SpaceAnalysis& a, const SpaceAnalysis& b, const std::string& what) {
  ASSERT_EQ(a.segments.size(), b.segments.size()) << what;
  for (std::size_t i = 0; i < a.segments.size(); ++i) {
    EXPECT_EQ(a.segments[i].curvature.curvature, b.segments[i].curvature.curvature) << what << " seg " << i;
    EXPECT_EQ(a.segments[i].torsion->curvature, b.segments[i].torsion->curvature) << what << " seg " << i;
    EXPECT_EQ(a.segments[i].torsion_sign, b.segments[i].torsion_sign) << what << " seg " << i;
    EXPECT_EQ(a.segments[i].zero_curvature.size(), b.segments[i].zero_curvature.size()) << what << " seg " << i;
  }
  for (std::size_t i = 0; i < a.joints.size(); ++i) EXPECT_EQ(a.joints[i].jump, b.joints[i].jump) << what << " joint " << i;
  EXPECT_EQ(a.curvature, b.curvature) << what;
  EXPECT_EQ(*a.torsion, *b.torsion) << what;
}

TEST(RationalSpaceAnalyze, VerdictsAreInvariantUnderRotationTranslationScalingAndWeightScaling) {
  std::mt19937_64 rng(98);
  std::uniform_real_distribution<double> u(-5, 5), sc(0.1, 10);
  for (int trial = 0; trial < 60; ++trial) {
    const int d = 2 + trial % 4, m = d + 1 + trial % 4;
    const std::vector<double> w = random_weights(rng, m);
    const SpaceSpline s = SpaceSpline::make(d, open_uniform(d, m), random_points3(rng, m), "", w);
    SpaceAnalyzeOptions o;
    o.torsion = true;
    const SpaceAnalysis a = analyze_space(s, o);
    const std::string at = "trial " + std::to_string(trial);
    expect_same_verdicts(a, analyze_space(transformed(s, random_rotation(rng), Vec3(u(rng), u(rng), u(rng)), sc(rng)), o),
                         at + " rigid+scale");
    for (const double f : {0.5, 3.0}) {  // every weight times f: the same curve
      std::vector<double> wf = w;
      for (double& x : wf) x *= f;
      expect_same_verdicts(a, analyze_space(SpaceSpline::make(d, open_uniform(d, m), s.points(), "", wf), o),
                           at + " weights*" + std::to_string(f));
    }
  }
}

// A rational Bezier curve with weights w_i rho^i (rho > 0) is the same curve
// under the Moebius reparametrisation s(t) = rho t / ((1 - t) + rho t) of [0, 1]
// onto itself, which keeps the orientation: the same verdicts.
TEST(RationalSpaceAnalyze, VerdictsAreInvariantUnderMoebiusReparametrisation) {
  std::mt19937_64 rng(97);
  for (int trial = 0; trial < 60; ++trial) {
    const int d = 2 + trial % 6;
    const std::vector<Vec3> P = random_points3(rng, d + 1);
    const std::vector<double> w = random_weights(rng, d + 1);
    const SpaceSpline s = SpaceSpline::bezier(P, "", w);
    SpaceAnalyzeOptions o;
    o.torsion = true;
    const SpaceAnalysis a = analyze_space(s, o);
    for (const double rho : {0.5, 2.0, 3.0}) {
      std::vector<double> wr = w;
      double f = 1;
      for (double& x : wr) {
        x *= f;
        f *= rho;
      }
      const SpaceSpline r = SpaceSpline::bezier(P, "", wr);
      // The same point set: C_r(t) = C(s(t)) with s(t) = rho t / ((1 - t) + rho t).
      for (const double t : {0.25, 0.5, 0.75}) {
        const double st = rho * t / ((1 - t) + rho * t);
        EXPECT_LT(glm::length(evaluate(r, t) - evaluate(s, st)), 1e-9) << "trial " << trial << " rho " << rho;
      }
      expect_same_verdicts(a, analyze_space(r, o), "trial " + std::to_string(trial) + " rho " + std::to_string(rho));
    }
  }
}

TEST(RationalSpaceAnalyze, JointsMeasureKappaAndTauOfTheRationalCurve) {
  std::mt19937_64 rng(96);
  for (int trial = 0; trial < 20; ++trial) {
    const int d = 3 + trial % 3, m = d + 3;
    const SpaceSpline s = SpaceSpline::make(d, open_uniform(d, m), random_points3(rng, m), "", random_weights(rng, m));
    const SpaceAnalysis a = analyze_space(s);
    for (const SpaceJoint& j : a.joints) {
      const std::string at = "trial " + std::to_string(trial) + " joint " + std::to_string(j.index);
      const double kl = space_curvature(s, std::nextafter(j.knot, -1e300)), kr = space_curvature(s, j.knot);
      EXPECT_NEAR(j.kappa_left, kl, 1e-7 * (1 + kl)) << at;
      EXPECT_NEAR(j.kappa_right, kr, 1e-7 * (1 + kr)) << at;
      const double tl = space_torsion(s, std::nextafter(j.knot, -1e300)), tr = space_torsion(s, j.knot);
      EXPECT_NEAR(j.tau_left, tl, 1e-6 * (1 + std::fabs(tl))) << at;
      EXPECT_NEAR(j.tau_right, tr, 1e-6 * (1 + std::fabs(tr))) << at;
    }
  }
  // A C1 joint (double knot) of a rational cubic: the exact jump sign is that of the sampled kappas.
  const SpaceSpline c = SpaceSpline::make(3, {0, 0, 0, 1, 1, 2, 2, 2},
                                          {{0, 0, 0}, {1, 1, 0.5}, {2, 1, 1}, {3, 1.5, 1.2}, {4, 3, 1}, {5, 3, 3}}, "",
                                          {1, 2, 0.5, 1.5, 3, 1});
  const SpaceAnalysis ac = analyze_space(c);
  ASSERT_EQ(ac.joints.size(), 1u);
  const double kl = space_curvature(c, std::nextafter(1.0, 0.0)), kr = space_curvature(c, 1.0);
  EXPECT_EQ(ac.joints[0].jump, kr > kl ? 1 : -1) << kl << " " << kr;
  EXPECT_NEAR(ac.joints[0].kappa_left, kl, 1e-9);
  EXPECT_NEAR(ac.joints[0].kappa_right, kr, 1e-9);
}

}  // namespace
}  // namespace cmr
