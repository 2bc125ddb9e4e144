#include "spline/bspline.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "spline/errors.hpp"
#include "tests/test_util.hpp"

namespace cmr {
namespace {

const std::vector<Vec2> kSix = {{0, 0}, {1, 2}, {3, 3}, {5, 2.5}, {6.5, 1}, {7, -1}};

TEST(BSpline, PaperUniformKnotsHaveSpans23_34_45) {
  const BSpline s = BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7}, kSix);
  ASSERT_EQ(s.segment_count(), 3);
  EXPECT_EQ(s.segments()[0].a, 2);
  EXPECT_EQ(s.segments()[0].b, 3);
  EXPECT_EQ(s.segments()[2].a, 4);
  EXPECT_EQ(s.segments()[2].b, 5);
}

TEST(BSpline, PaperClampedKnotsHaveSpans01_12_23AndInterpolateEnds) {
  const BSpline s = BSpline::make(3, {0, 0, 0, 1, 2, 3, 3, 3}, kSix);
  ASSERT_EQ(s.segment_count(), 3);
  EXPECT_EQ(s.segments()[0].a, 0);
  EXPECT_EQ(s.segments()[2].b, 3);
  const Vec2 a = evaluate(s, 0.0), b = evaluate(s, 3.0);
  EXPECT_NEAR(a.x, 0, 1e-15);
  EXPECT_NEAR(a.y, 0, 1e-15);
  EXPECT_NEAR(b.x, 7, 1e-14);
  EXPECT_NEAR(b.y, -1, 1e-14);
}

TEST(BSpline, EmptySpansAreSkipped) {
  const BSpline s = BSpline::make(3, {0, 0, 0, 1, 1, 3, 3, 3}, kSix);
  ASSERT_EQ(s.segment_count(), 2);
  EXPECT_EQ(s.segments()[1].a, 1);
  EXPECT_EQ(s.segments()[1].b, 3);
  EXPECT_EQ(s.segments()[1].index, 1);
}

struct BadCase {
  const char* name;
  int degree;
  std::vector<double> knots;
  std::vector<Vec2> points;
  const char* message_part;
};

// Printed by its name, so the test's name (ctest lists GetParam()) is stable
// and readable, not the struct's bytes.
void PrintTo(const BadCase& c, std::ostream* os) { *os << c.name; }

class BSplineRejects : public ::testing::TestWithParam<BadCase> {};

TEST_P(BSplineRejects, WithAMessageNamingTheProblem) {
  const BadCase& c = GetParam();
  try {
    (void)BSpline::make(c.degree, c.knots, c.points);
    FAIL() << c.name << " was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(c.message_part), std::string::npos) << e.what();
  }
}

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

INSTANTIATE_TEST_SUITE_P(
    Table, BSplineRejects,
    ::testing::Values(BadCase{"degree1", 1, {0, 1}, {{0, 0}, {1, 0}}, "degree"},
                      BadCase{"too_few_points", 3, {0, 0, 1, 1}, {{0, 0}, {1, 0}, {2, 1}}, "at least 4"},
                      BadCase{"wrong_knot_count", 3, {0, 1, 2, 3, 4, 5, 6}, kSix, "8 knots (got 7)"},
                      BadCase{"decreasing", 3, {0, 1, 2, 3, 2.5, 5, 6, 7}, kSix, "knots[4] (2.5) is smaller"},
                      BadCase{"nan_knot", 3, {0, 1, 2, kNaN, 4, 5, 6, 7}, kSix, "knots[3] is not a finite"},
                      BadCase{"inf_knot", 3, {0, 1, 2, 3, 4, 5, 6, kInf}, kSix, "knots[7]"},
                      BadCase{"nan_point", 3, {0, 1, 2, 3, 4, 5, 6, 7},
                              {{0, 0}, {1, 2}, {3, kNaN}, {5, 2.5}, {6.5, 1}, {7, -1}}, "points[2][1]"},
                      BadCase{"multiplicity", 3, {0, 0, 0, 1, 1, 1, 1, 3}, kSix, "multiplicity"},
                      BadCase{"all_empty", 3, {0, 1, 2, 2, 3, 4}, {{0, 0}, {1, 1}, {2, 0}, {3, 1}}, "empty"}),
    [](const auto& p) { return std::string(p.param.name); });

TEST(BSpline, EvaluationMatchesCoxDeBoorOnKnotFamilies) {
  std::mt19937_64 rng(7);
  const std::vector<std::pair<int, std::vector<double>>> families = {
      {3, {0, 1, 2, 3, 4, 5, 6, 7}},                // uniform
      {3, {0, 0, 0, 1, 2, 3, 3, 3}},                // clamped
      {3, {0, 0.1, 0.5, 1.7, 1.8, 4.0, 6, 9.5}},    // non-uniform
      {3, {-7, -5, -4.5, -1, -0.25, 0, 2, 3}},      // negative
      {3, {0, 1, 2, 2, 4, 4, 6, 7}},                // repeated (C1 joints)
      {2, {0, 1, 2, 2, 3, 4, 5}},                   // quadratic, repeated
      {5, {0, 1, 2, 3, 4, 5, 5, 7, 8, 9, 10, 11}},  // quintic, repeated
  };
  for (const auto& [d, knots] : families) {
    const int m = static_cast<int>(knots.size()) - d + 1;
    const BSpline s = BSpline::make(d, knots, test::random_points(rng, m));
    for (int i = 0; i <= 200; ++i) {
      const double t = s.domain_begin() + (s.domain_end() - s.domain_begin()) * i / 200.0;
      const Vec2 a = evaluate(s, t), b = test::cox_de_boor(s, t);
      ASSERT_NEAR(a.x, b.x, 1e-13) << "degree " << d << " knots[0]=" << knots[0] << " t=" << t;
      ASSERT_NEAR(a.y, b.y, 1e-13) << "degree " << d << " knots[0]=" << knots[0] << " t=" << t;
    }
  }
}

TEST(BSpline, HundredThousandPointsEvaluateLikeCoxDeBoor) {
  std::mt19937_64 rng(11);
  const int m = 100000, d = 3;
  std::vector<double> knots(m + d - 1);
  for (std::size_t i = 0; i < knots.size(); ++i) knots[i] = static_cast<double>(i);
  const BSpline s = BSpline::make(d, knots, test::random_points(rng, m));
  EXPECT_EQ(s.segment_count(), m - d);
  std::uniform_real_distribution<double> u(s.domain_begin(), s.domain_end());
  for (int i = 0; i < 2000; ++i) {
    const double t = u(rng);
    const Vec2 a = evaluate(s, t), b = test::cox_de_boor(s, t);
    ASSERT_NEAR(a.x, b.x, 1e-12) << "t=" << t;
    ASSERT_NEAR(a.y, b.y, 1e-12) << "t=" << t;
  }
}

TEST(BSpline, DerivativesMatchFiniteDifferences) {
  std::mt19937_64 rng(3);
  const BSpline s = BSpline::make(4, {0, 0, 0.5, 1.5, 2, 3.5, 4, 4, 5}, test::random_points(rng, 6));
  const double h = 1e-5 * (s.domain_end() - s.domain_begin());
  for (const Segment& seg : s.segments()) {
    for (double f : {0.2, 0.5, 0.8}) {
      const double t = seg.a + f * (seg.b - seg.a);
      for (int r = 1; r <= 3; ++r) {
        const Vec2 fd = (derivative(s, t + h, r - 1) - derivative(s, t - h, r - 1)) / (2 * h);
        const Vec2 d = derivative(s, t, r);
        const double tol = 1e-6 * (1 + std::abs(d.x) + std::abs(d.y));
        EXPECT_NEAR(d.x, fd.x, tol) << "r=" << r << " t=" << t;
        EXPECT_NEAR(d.y, fd.y, tol) << "r=" << r << " t=" << t;
      }
    }
  }
}

TEST(BSpline, BezierIsTheBSplineWithKnots0n1n) {
  const std::vector<Vec2> P = {{0, 0}, {1, 3}, {4, 3}, {5, 0}};
  const BSpline s = BSpline::bezier(P);
  EXPECT_EQ(s.knots(), (std::vector<double>{0, 0, 0, 1, 1, 1}));
  for (double t : {0.0, 0.25, 0.5, 0.9, 1.0}) {
    const double s0 = 1 - t;
    const Vec2 ref = s0 * s0 * s0 * P[0] + 3 * s0 * s0 * t * P[1] + 3 * s0 * t * t * P[2] + t * t * t * P[3];
    const Vec2 v = evaluate(s, t);
    EXPECT_NEAR(v.x, ref.x, 1e-14) << "t=" << t;
    EXPECT_NEAR(v.y, ref.y, 1e-14) << "t=" << t;
  }
}

TEST(BSpline, ReversedTracesTheSameCurveBackwards) {
  std::mt19937_64 rng(5);
  const BSpline s = BSpline::make(3, {0, 0.5, 1, 3, 4, 4, 6, 7}, test::random_points(rng, 6));
  const BSpline r = s.reversed();
  for (int i = 0; i <= 50; ++i) {
    const double t = s.domain_begin() + (s.domain_end() - s.domain_begin()) * i / 50.0;
    const Vec2 a = evaluate(s, t), b = evaluate(r, -t);
    EXPECT_NEAR(a.x, b.x, 1e-13) << "t=" << t;
    EXPECT_NEAR(a.y, b.y, 1e-13) << "t=" << t;
  }
}

TEST(BSpline, WithPointRejectsOutOfRangeIndex) {
  const BSpline s = BSpline::bezier({{0, 0}, {1, 1}, {2, 0}});
  EXPECT_THROW((void)s.with_point(3, {0, 0}), InputError);
  EXPECT_THROW((void)s.with_point(-1, {0, 0}), InputError);
  EXPECT_EQ(s.with_point(1, {5, 5}).points()[1], Vec2(5, 5));
}

// with_points: every distinct point at once, the same spline as a
// with_point per point (closed: the twins follow; rational: the weights
// stay with their points), and the same refusals.
TEST(BSpline, WithPointsIsAWithPointPerPoint) {
  const std::vector<Vec2> ring = {{0, 0}, {4, 0}, {5, 3}, {2, 5}, {-1, 3}};
  const std::vector<Vec2> moved = {{1, 0}, {4, -1}, {6, 3}, {2, 7}, {-2, 2}};
  for (const BSpline& s : {BSpline::make_closed(3, {0, 1, 2, 3, 4, 5}, ring),
                           BSpline::make(2, {0, 0, 1, 2, 3, 3}, ring, "", {1, 2, 1, 3, 1}),
                           BSpline::bezier(ring)}) {
    BSpline each = s;
    for (int k = 0; k < s.unique_point_count(); ++k) each = each.with_point(k, moved[static_cast<std::size_t>(k)]);
    const BSpline all = s.with_points({moved.begin(), moved.begin() + s.unique_point_count()});
    EXPECT_EQ(all.points(), each.points());
    EXPECT_EQ(all.homogeneous_points(), each.homogeneous_points());
    EXPECT_THROW((void)s.with_points({moved.begin(), moved.begin() + 2}), InputError);
    std::vector<Vec2> bad(moved.begin(), moved.begin() + s.unique_point_count());
    bad[1].x = std::nan("");
    EXPECT_THROW((void)s.with_points(bad), InputError);
  }
}

TEST(BSpline, WeightsAreValidatedNamingTheIndex) {
  const std::vector<Vec2> P = {{0, 0}, {1, 1}, {2, 0}};
  const auto message = [&](std::vector<double> w) {
    try {
      (void)BSpline::bezier(P, "", std::move(w));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message({1, 2}), "weights: one weight per control point is needed: 3 points, 2 weights");
  // Any finite weights, not all 0: zero and negative ones are accepted (poles, analyze.hpp).
  EXPECT_EQ(message({1, 0, 1}), "accepted");
  EXPECT_EQ(message({1, 1, -2}), "accepted");
  EXPECT_EQ(message({0, 0, 0}), "weights: every weight is 0; at least one must be non-zero");
  EXPECT_EQ(message({-0.0, 0, 0}), "weights: every weight is 0; at least one must be non-zero");
  EXPECT_EQ(message({1, std::numeric_limits<double>::infinity(), 1}), "weights[1] is not a finite number");
  EXPECT_EQ(message({1, std::numeric_limits<double>::quiet_NaN(), 1}), "weights[1] is not a finite number");
  EXPECT_EQ(message({-std::numeric_limits<double>::infinity(), 1, 1}), "weights[0] is not a finite number");
  EXPECT_EQ(message({1, 2, 1}), "accepted");
  EXPECT_FALSE(BSpline::bezier(P, "", {3, 3, 3}).is_rational());  // equal weights cancel
  EXPECT_FALSE(BSpline::bezier(P, "", {-3, -3, -3}).is_rational());
  // Mixed signs are kept as given.
  EXPECT_EQ(BSpline::bezier(P, "", {1, -1, 2}).weights(), (std::vector<double>{1, -1, 2}));
}

TEST(BSpline, AllNegativeWeightsAreNegatedAndGiveTheSameCurve) {
  // X / W = (-X) / (-W): the curve of -w is the curve of w. Checked against
  // an independent route: direct sums of the cubic
  // Bernstein basis with the weights as given (negative), then divided.
  const std::vector<Vec2> P = {{0, 0}, {1, 2}, {3, 2}, {4, 0}};
  const std::vector<double> neg = {-1, -0.5, -2, -1.5};
  const BSpline s = BSpline::bezier(P, "", neg);
  EXPECT_EQ(s.weights(), (std::vector<double>{1, 0.5, 2, 1.5}));
  const BSpline pos = BSpline::bezier(P, "", {1, 0.5, 2, 1.5});
  for (int i = 0; i <= 20; ++i) {
    const double t = i / 20.0;
    const double B[4] = {(1 - t) * (1 - t) * (1 - t), 3 * t * (1 - t) * (1 - t), 3 * t * t * (1 - t), t * t * t};
    Vec2 X(0.0);
    double W = 0;
    for (int k = 0; k < 4; ++k) {
      X += B[k] * neg[k] * P[k];
      W += B[k] * neg[k];
    }
    const Vec2 c = evaluate(s, t), ref = X / W;
    EXPECT_NEAR(c.x, ref.x, 1e-14);
    EXPECT_NEAR(c.y, ref.y, 1e-14);
    EXPECT_EQ(c, evaluate(pos, t));
  }
}

TEST(BSpline, RationalEvaluationMatchesCoxDeBoorOfTheHomogeneousCurve) {
  // Independent route: Cox-de Boor on (w x, w y) and on (w, 0), then divide.
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> weight(0.2, 5);
  for (const auto& knots : {std::vector<double>{0, 1, 2, 3, 4, 5, 6, 7}, std::vector<double>{0, 0, 0, 1, 2, 3, 3, 3},
                            std::vector<double>{0, 0, 0, 1, 1, 1, 2, 2}}) {
    const auto P = test::random_points(rng, 6);
    std::vector<double> w;
    for (int i = 0; i < 6; ++i) w.push_back(weight(rng));
    const BSpline s = BSpline::make(3, knots, P, "", w);
    std::vector<Vec2> wp, ww;
    for (int i = 0; i < 6; ++i) {
      wp.push_back(w[i] * P[i]);
      ww.push_back(Vec2(w[i], 0));
    }
    const BSpline X = BSpline::make(3, knots, wp), W = BSpline::make(3, knots, ww);
    for (double t = s.domain_begin(); t <= s.domain_end(); t += 0.0625) {
      const Vec2 want = test::cox_de_boor(X, t) / test::cox_de_boor(W, t).x;
      const Vec2 got = evaluate(s, t);
      EXPECT_NEAR(got.x, want.x, 1e-12 * (1 + std::abs(want.x))) << "t=" << t;
      EXPECT_NEAR(got.y, want.y, 1e-12 * (1 + std::abs(want.y))) << "t=" << t;
      // Derivatives (Leibniz on the homogeneous blossom) against central differences.
      const double h = 1e-6;
      const Vec2 fd = (evaluate(s, t + h) - evaluate(s, t - h)) / (2 * h);
      if (t - h > s.domain_begin() && t + h < s.domain_end() && s.multiplicity(t) == 0) {
        const Vec2 d1 = derivative(s, t, 1);
        EXPECT_NEAR(d1.x, fd.x, 1e-6 * (1 + std::abs(fd.x))) << "t=" << t;
        EXPECT_NEAR(d1.y, fd.y, 1e-6 * (1 + std::abs(fd.y))) << "t=" << t;
      }
    }
    // Reversal and with_point keep the weights with their points.
    const BSpline r = s.reversed();
    for (double t = s.domain_begin(); t <= s.domain_end(); t += 0.25) {
      const Vec2 a = evaluate(s, t), b = evaluate(r, -t);
      EXPECT_NEAR(a.x, b.x, 1e-12 * (1 + std::abs(a.x)));
      EXPECT_NEAR(a.y, b.y, 1e-12 * (1 + std::abs(a.y)));
    }
    EXPECT_EQ(s.with_point(2, Vec2(9, 9)).homogeneous_points()[2], glm::dvec3(9 * w[2], 9 * w[2], w[2]));
  }
}

}  // namespace
}  // namespace cmr
