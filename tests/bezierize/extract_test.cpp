#include "bezierize/extract.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "numeric/bernstein.hpp"
#include "tests/test_util.hpp"

namespace cmr {
namespace {

Vec2 bezier_eval(const std::vector<Vec2>& P, double t) {
  std::vector<Vec2> w = P;
  for (std::size_t r = 1; r < w.size(); ++r)
    for (std::size_t i = 0; i + r < w.size(); ++i) w[i] = (1 - t) * w[i] + t * w[i + 1];
  return w[0];
}

struct Family {
  const char* name;
  int degree;
  std::vector<double> knots;
};

const std::vector<Family> kFamilies = {
    {"uniform", 3, {0, 1, 2, 3, 4, 5, 6, 7}},
    {"clamped", 3, {0, 0, 0, 1, 2, 3, 3, 3}},
    {"nonuniform", 3, {0, 0.1, 0.5, 1.7, 1.8, 4.0, 6, 9.5}},
    {"negative", 3, {-7, -5, -4.5, -1, -0.25, 0, 2, 3}},
    {"repeated", 3, {0, 1, 2, 2, 4, 4, 6, 7}},
    {"quadratic", 2, {0, 1, 2, 2, 3, 4, 5}},
    {"quintic", 5, {0, 1, 2, 3, 4, 5, 5, 7, 8, 9, 10, 11}},
    {"empty_span", 3, {0, 0, 0, 1, 1, 3, 3, 3}},
};

TEST(Extract, BothRoutesMatchCoxDeBoorOnEveryFamily) {
  std::mt19937_64 rng(31);
  for (const Family& f : kFamilies) {
    const int m = static_cast<int>(f.knots.size()) - f.degree + 1;
    const BSpline s = BSpline::make(f.degree, f.knots, test::random_points(rng, m));
    const auto blossomed = bezier_segments(s);
    const auto inserted = bezier_segments_by_insertion(s);
    ASSERT_EQ(blossomed.size(), inserted.size()) << f.name;
    for (std::size_t j = 0; j < blossomed.size(); ++j) {
      const Segment& seg = blossomed[j].segment;
      for (std::size_t k = 0; k < blossomed[j].points.size(); ++k) {
        EXPECT_NEAR(blossomed[j].points[k].x, inserted[j].points[k].x, 1e-12) << f.name << " seg " << j << " pt " << k;
        EXPECT_NEAR(blossomed[j].points[k].y, inserted[j].points[k].y, 1e-12) << f.name << " seg " << j << " pt " << k;
      }
      for (double u : {0.0, 0.2, 0.5, 0.81, 1.0}) {
        const double t = seg.a + u * (seg.b - seg.a);
        const Vec2 a = bezier_eval(blossomed[j].points, u), b = test::cox_de_boor(s, t);
        EXPECT_NEAR(a.x, b.x, 1e-12) << f.name << " seg " << j << " t=" << t;
        EXPECT_NEAR(a.y, b.y, 1e-12) << f.name << " seg " << j << " t=" << t;
      }
    }
  }
}

TEST(Extract, HundredThousandPointSplineMatchesCoxDeBoor) {
  std::mt19937_64 rng(32);
  const int m = 100000, d = 3;
  std::vector<double> knots(m + d - 1);
  std::uniform_real_distribution<double> gap(0.1, 2.0);
  knots[0] = -1000;
  for (std::size_t i = 1; i < knots.size(); ++i) knots[i] = knots[i - 1] + gap(rng);
  const BSpline s = BSpline::make(d, knots, test::random_points(rng, m, 100));
  const auto segs = bezier_segments(s);
  ASSERT_EQ(segs.size(), static_cast<std::size_t>(m - d));
  for (std::size_t j = 0; j < segs.size(); j += 997) {
    const Segment& seg = segs[j].segment;
    for (double u : {0.0, 0.37, 1.0}) {
      const Vec2 a = bezier_eval(segs[j].points, u), b = test::cox_de_boor(s, seg.a + u * (seg.b - seg.a));
      ASSERT_NEAR(a.x, b.x, 1e-7) << "seg " << j << " u=" << u;
      ASSERT_NEAR(a.y, b.y, 1e-7) << "seg " << j << " u=" << u;
    }
  }
}

TEST(Extract, KnotInsertionLeavesTheCurveUnchanged) {
  std::mt19937_64 rng(33);
  for (const Family& f : kFamilies) {
    const int m = static_cast<int>(f.knots.size()) - f.degree + 1;
    const BSpline s = BSpline::make(f.degree, f.knots, test::random_points(rng, m));
    std::uniform_real_distribution<double> u(s.domain_begin(), s.domain_end());
    BSpline r = s;
    for (int k = 0; k < 5; ++k) r = insert_knot(r, u(rng));
    EXPECT_EQ(r.point_count(), s.point_count() + 5);
    for (int i = 0; i <= 100; ++i) {
      const double t = s.domain_begin() + (s.domain_end() - s.domain_begin()) * i / 100.0;
      const Vec2 a = evaluate(s, t), b = evaluate(r, t);
      EXPECT_NEAR(a.x, b.x, 1e-12) << f.name << " t=" << t;
      EXPECT_NEAR(a.y, b.y, 1e-12) << f.name << " t=" << t;
    }
  }
}

TEST(Extract, InfluenceWeightsPredictTheMovedBezierPoints) {
  std::mt19937_64 rng(34);
  const BSpline s = BSpline::make(3, {0, 0, 0, 1, 2, 3, 3, 3}, test::random_points(rng, 6));
  const Vec2 delta(0.3, -0.7);
  for (int k = 0; k < 6; ++k) {
    const auto infl = influence(s, {k});
    const auto before = bezier_segments(s);
    const auto after = bezier_segments(s.with_point(k, s.points()[k] + delta));
    std::vector<bool> touched(3, false);
    for (const SegmentInfluence& si : infl) {
      touched[si.segment] = true;
      for (int i = 0; i <= 3; ++i) {
        const Vec2 predicted = before[si.segment].points[i] + si.w[i] * delta;
        EXPECT_NEAR(predicted.x, after[si.segment].points[i].x, 1e-14) << "k=" << k << " seg " << si.segment;
        EXPECT_NEAR(predicted.y, after[si.segment].points[i].y, 1e-14) << "k=" << k << " seg " << si.segment;
      }
    }
    for (int j = 0; j < 3; ++j)
      if (!touched[j]) {
        EXPECT_EQ(before[j].points, after[j].points) << "k=" << k << " moved untouched seg " << j;
      }
  }
  // A rigid group adds its members' weights.
  const auto g = influence(s, {2, 3});
  const auto after = bezier_segments(s.with_point(2, s.points()[2] + delta).with_point(3, s.points()[3] + delta));
  const auto before = bezier_segments(s);
  for (const SegmentInfluence& si : g)
    for (int i = 0; i <= 3; ++i)
      EXPECT_NEAR((before[si.segment].points[i] + si.w[i] * delta).x, after[si.segment].points[i].x, 1e-14);
}

}  // namespace
}  // namespace cmr

namespace cmr {
namespace {

/// The blossom's Bezier points, always evaluated (bezier_points without its
/// shortcut), for comparing bit for bit. B_k = f(a^{d-k}, b^k) with the a's
/// first (bezier_points' order), or with `b_first` the b's first (the order
/// analyze's end curvature reads a segment from its end b).
template <class S, class P>
std::vector<P> blossomed(const std::vector<S>& knots, const std::vector<P>& points, int d, int j, const S& a,
                         const S& b, bool b_first = false) {
  std::vector<P> out;
  std::vector<S> args(d);
  for (int k = 0; k <= d; ++k) {
    for (int i = 0; i < d; ++i) args[i] = b_first ? (i < k ? b : a) : (i < d - k ? a : b);
    out.push_back(blossom_span(knots, points, d, j, args.data()));
  }
  return out;
}

bool same_bits(double x, double y) { return std::memcmp(&x, &y, sizeof x) == 0; }

/// Bezier spans (knots a^d b^d around span d-1) of random control points:
/// integer coordinates (a font's), halves, tiny, -0.0 and 0, with integer,
/// dyadic and non-dyadic knot pairs. Wherever the shortcut answers it must
/// be the blossom's answer bit for bit (double), value and bound (Tracked),
/// exactly (Rational); and it must answer for integer data.
TEST(BezierSpanPoints, EqualTheBlossomBitForBitWhereTheyAnswer) {
  std::mt19937 rng(20261203);
  const std::vector<std::pair<double, double>> spans = {{0, 1}, {3, 4}, {-2, 5}, {0.5, 0.75}, {0.1, 0.3}, {1e-280, 1}};
  const std::vector<double> specials = {0.0, -0.0, 1e-300, -3e-290, 0.5, 1e300};
  int answered = 0, integer_answered = 0, integer_cases = 0;
  for (int d = 1; d <= 9; ++d)
    for (const auto& [a, b] : spans)
      for (int trial = 0; trial < 60; ++trial) {
        std::vector<double> knots(d, a);
        knots.insert(knots.end(), d, b);
        std::vector<Vec2> pts;
        const bool integer = trial % 3 == 0;
        for (int i = 0; i <= d; ++i) {
          auto coord = [&]() -> double {
            if (integer) return static_cast<double>(static_cast<int>(rng() % 2001) - 1000);
            if (rng() % 4 == 0) return specials[rng() % specials.size()];
            return std::ldexp(static_cast<double>(static_cast<int>(rng() % 20001) - 10000), -static_cast<int>(rng() % 8));
          };
          const double x = coord();
          pts.push_back({x, coord()});
        }
        const int j = d - 1;
        // double
        if (auto fast = bezier_span_points(knots, pts, d, j, a, b)) {
          ++answered;
          const std::vector<Vec2> slow = blossomed(knots, pts, d, j, a, b);
          for (int k = 0; k <= d; ++k) {
            EXPECT_TRUE(same_bits((*fast)[k].x, slow[k].x) && same_bits((*fast)[k].y, slow[k].y))
                << "double, degree " << d << ", span [" << a << ", " << b << "], point " << k;
          }
        }
        // Tracked: values and bounds
        std::vector<Tracked> tk(knots.begin(), knots.end());
        std::vector<Point<Tracked>> tp;
        for (const Vec2& p : pts) tp.push_back(to_point<Tracked>(p));
        const bool integer_knots = a == std::floor(a) && b == std::floor(b);
        if (integer && integer_knots) ++integer_cases;
        if (auto fast = bezier_span_points(tk, tp, d, j, Tracked(a), Tracked(b))) {
          ++answered;
          if (integer && integer_knots) ++integer_answered;
          for (const bool b_first : {false, true}) {
            const std::vector<Point<Tracked>> slow = blossomed(tk, tp, d, j, Tracked(a), Tracked(b), b_first);
            for (int k = 0; k <= d; ++k) {
              const Point<Tracked>& f = (*fast)[k];
              const Point<Tracked>& s = slow[k];
              EXPECT_TRUE(same_bits(f.x.v, s.x.v) && same_bits(f.y.v, s.y.v) && same_bits(f.x.e, s.x.e) &&
                          same_bits(f.y.e, s.y.e))
                  << "Tracked, degree " << d << ", span [" << a << ", " << b << "], point " << k
                  << (b_first ? " (b first)" : "") << ": " << f.x.v << "+-" << f.x.e << " vs " << s.x.v << "+-" << s.x.e;
            }
          }
        }
        // Rational: exactly
        std::vector<Rational> rk(knots.begin(), knots.end());
        std::vector<Point<Rational>> rp;
        for (const Vec2& p : pts) rp.push_back(to_point<Rational>(p));
        if (auto fast = bezier_span_points(rk, rp, d, j, Rational(a), Rational(b))) {
          ++answered;
          const std::vector<Point<Rational>> slow = blossomed(rk, rp, d, j, Rational(a), Rational(b));
          for (int k = 0; k <= d; ++k) EXPECT_TRUE((*fast)[k].x == slow[k].x && (*fast)[k].y == slow[k].y);
        }
      }
  EXPECT_GT(answered, 1000);
  EXPECT_EQ(integer_answered, integer_cases);  // a font's data always takes the shortcut
  EXPECT_GT(integer_cases, 0);
}

/// Not a Bezier span (a uniform cubic's inner span): no shortcut.
TEST(BezierSpanPoints, LeaveOtherSpansToTheBlossom) {
  const std::vector<double> knots = {0, 1, 2, 3, 4, 5, 6, 7};
  const std::vector<Vec2> pts = {{0, 0}, {1, 2}, {3, 3}, {4, 0}, {6, 1}, {7, 3}};
  for (int j = 2; j <= 4; ++j) EXPECT_FALSE(bezier_span_points(knots, pts, 3, j, knots[j], knots[j + 1]));
  const std::vector<double> clamped = {0, 0, 0, 1, 1, 1, 2, 2};  // span 2 = [0, 1] is Bezier, span 3 is empty
  EXPECT_TRUE(bezier_span_points(clamped, pts, 3, 2, 0.0, 1.0));
}

}  // namespace
}  // namespace cmr
