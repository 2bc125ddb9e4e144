#include "bezierize/extract.hpp"

#include <gtest/gtest.h>

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
