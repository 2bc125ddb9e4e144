// Closed (periodic) splines: the unrolled form against closed forms of the
// uniform case, periodicity and smoothness across the seam, rotation of the
// start, twins, reversal and the JSON form.
#include <gtest/gtest.h>

#include <random>

#include <nlohmann/json.hpp>

#include "spline/bspline.hpp"
#include "spline/errors.hpp"
#include "spline/spline_json.hpp"

namespace cmr {
namespace {

std::vector<Vec2> ring(std::mt19937_64& rng, int m) {
  std::uniform_real_distribution<double> jitter(-0.2, 0.2);
  std::vector<Vec2> p;
  for (int i = 0; i < m; ++i) {
    const double a = 6.283185307179586 * i / m;
    p.push_back({std::cos(a) + jitter(rng), std::sin(a) + jitter(rng)});
  }
  return p;
}

std::vector<double> knots_of(std::mt19937_64& rng, int m) {
  std::uniform_real_distribution<double> step(0.5, 2.0);
  std::vector<double> u{0.25};
  for (int i = 0; i < m; ++i) u.push_back(u.back() + step(rng));
  return u;
}

double dist(Vec2 a, Vec2 b) { return std::sqrt(dot(a - b, a - b)); }

// Uniform closed cubic: segment i starts at (P_i + 4 P_{i+1} + P_{i+2}) / 6
// (indices mod m), the textbook value of the uniform cubic basis at a knot.
TEST(ClosedSpline, UniformCubicMatchesTextbookKnotValues) {
  std::mt19937_64 rng(7);
  const int m = 7;
  const auto P = ring(rng, m);
  std::vector<double> u;
  for (int i = 0; i <= m; ++i) u.push_back(i);
  const BSpline s = BSpline::make_closed(3, u, P);
  ASSERT_EQ(s.segment_count(), m);
  ASSERT_TRUE(s.closed());
  EXPECT_EQ(s.unique_point_count(), m);
  for (int i = 0; i < m; ++i) {
    const Vec2 want = (P[i] + 4.0 * P[(i + 1) % m] + P[(i + 2) % m]) / 6.0;
    EXPECT_LT(dist(evaluate(s, s.segments()[i].a), want), 1e-14) << "segment " << i;
  }
  EXPECT_LT(dist(evaluate(s, s.domain_end()), evaluate(s, s.domain_begin())), 1e-14);
}

// With simple knots the curve is C^{d-1} across the seam like at every other
// joint: the end of the last segment meets the start of segment 0 in every
// derivative below the degree.
TEST(ClosedSpline, SeamIsSmoothLikeEveryJoint) {
  std::mt19937_64 rng(11);
  for (int d = 2; d <= 5; ++d) {
    const int m = d + 3;
    const BSpline s = BSpline::make_closed(d, knots_of(rng, m), ring(rng, m));
    ASSERT_EQ(s.segment_count(), m) << "degree " << d;
    const Segment& last = s.segments().back();
    const Segment& first = s.segments().front();
    for (int r = 0; r < d; ++r) {
      // derivative() takes the segment containing t: the domain end is in the last.
      const Vec2 left = derivative(s, last.b, r);
      const Vec2 right = derivative(s, first.a, r);
      EXPECT_LT(dist(left, right), 1e-9 * (1 + std::sqrt(dot(left, left)))) << "degree " << d << " order " << r;
    }
  }
}

// Starting the period one knot later is the same closed curve, shifted in t.
TEST(ClosedSpline, RotatingTheStartKeepsTheCurve) {
  std::mt19937_64 rng(3);
  for (int d = 2; d <= 4; ++d) {
    const int m = d + 4;
    const auto P = ring(rng, m);
    const auto u = knots_of(rng, m);
    const BSpline s = BSpline::make_closed(d, u, P);
    std::vector<Vec2> P2(P.begin() + 1, P.end());
    P2.push_back(P[0]);
    std::vector<double> u2(u.begin() + 1, u.end());
    u2.push_back(u[m] + (u[1] - u[0]));
    const BSpline s2 = BSpline::make_closed(d, u2, P2);
    for (int k = 0; k <= 200; ++k) {
      const double t = u[1] + (u[m] - u[0]) * k / 200.0 * 0.999;
      const double t_in_s = t <= u[m] ? t : t - (u[m] - u[0]);
      EXPECT_LT(dist(evaluate(s2, t), evaluate(s, t_in_s)), 1e-12) << "degree " << d << " t " << t;
    }
  }
}

TEST(ClosedSpline, TwinsMoveTogetherAndReversalStaysClosed) {
  std::mt19937_64 rng(5);
  const int d = 3, m = 6;
  const BSpline s = BSpline::make_closed(d, knots_of(rng, m), ring(rng, m));
  for (int k = 0; k < d; ++k) {
    EXPECT_EQ(s.twin(k), k + m);
    EXPECT_EQ(s.twin(k + m), k);
    const BSpline moved = s.with_point(k, {5, 5});
    EXPECT_EQ(moved.points()[k + m], Vec2(5, 5));
  }
  EXPECT_EQ(s.twin(d), -1);
  const BSpline r = s.reversed();
  ASSERT_TRUE(r.closed());
  for (int k = 0; k < d; ++k) EXPECT_EQ(r.points()[k], r.points()[k + m]) << "twin " << k;
  for (int k = 0; k <= 50; ++k) {
    const double t = s.domain_begin() + (s.domain_end() - s.domain_begin()) * k / 50.0;
    EXPECT_LT(dist(evaluate(r, -t), evaluate(s, t)), 1e-12) << "t " << t;
  }
}

TEST(ClosedSpline, JsonRoundTripAndDefaults) {
  std::mt19937_64 rng(9);
  const BSpline s = BSpline::make_closed(2, knots_of(rng, 5), ring(rng, 5), "ring");
  const nlohmann::json j = spline_to_json(s);
  EXPECT_TRUE(j["closed"].get<bool>());
  EXPECT_EQ(j["points"].size(), 5u);
  EXPECT_EQ(j["knots"].size(), 6u);
  const BSpline back = spline_from_json(j);
  EXPECT_TRUE(back.closed());
  EXPECT_EQ(back.knots(), s.knots());
  EXPECT_EQ(back.points(), s.points());
  // Without knots: uniform 0..m.
  nlohmann::json u = {{"degree", 2}, {"closed", true}, {"points", {{0, 0}, {1, 0}, {1, 1}, {0, 1}}}};
  EXPECT_EQ(spline_from_json(u).period_knots(), (std::vector<double>{0, 1, 2, 3, 4}));
  u["point_names"] = {"a", "b", "c", "d"};
  EXPECT_NO_THROW(spline_from_json(u));
}

TEST(ClosedSpline, BadInputNamesTheProblem) {
  auto message = [](auto f) {
    try {
      f();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::vector<Vec2> P{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  EXPECT_NE(message([&] { (void)BSpline::make_closed(2, {0, 1, 2}, P); }).find("points + 1 = 5 knots"),
            std::string::npos);
  // Seam: knots[0] == knots[1] and knots[3] == knots[4]: multiplicity 3 > 2.
  EXPECT_NE(message([&] { (void)BSpline::make_closed(2, {0, 0, 1, 2, 2}, P); }).find("the seam"), std::string::npos);
  EXPECT_NE(message([&] { (void)BSpline::make_closed(2, {0, 0, 0, 0, 0}, P); }).find("period"), std::string::npos);
  nlohmann::json j = {{"degree", 2}, {"closed", "yes"}, {"points", {{0, 0}, {1, 0}, {1, 1}}}};
  EXPECT_NE(message([&] { (void)spline_from_json(j); }).find("closed: not true or false"), std::string::npos);
  j["closed"] = true;
  j["point_names"] = {"a"};
  EXPECT_NE(message([&] { (void)spline_from_json(j); }).find("point_names"), std::string::npos);
}

}  // namespace
}  // namespace cmr
