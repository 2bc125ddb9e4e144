// The exact shortcut of a Bezier window (bezierize/extract.hpp: knots a^d b^d,
// so the control points are the Bezier points): segment_bezier_points<Rational>
// and the exact end curvature (analyze.cpp's end_curvature<Rational>) must be
// what rational blossoming gives, bit for bit, on Bezier chains (fonts' and
// SVG's form, coordinates at thirds as a CFF line has them) and on splines
// whose windows are not Bezier windows.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "bezierize/analyze.hpp"
#include "bezierize/decide.hpp"
#include "numeric/exact.hpp"
#include "bezierize/extract.hpp"
#include "numeric/fast_path.hpp"

namespace cmr {
namespace {

// n pieces of degree d in a row: knots 0^d 1^d ... n^d, random points.
BSpline chain(std::mt19937_64& rng, int d, int n, int trial) {
  std::uniform_int_distribution<int> small(-600, 600);
  std::vector<Vec2> P;
  for (int i = 0; i <= n * d; ++i) P.push_back(Vec2(small(rng), small(rng)));
  for (int i = 0; i + d < static_cast<int>(P.size()); i += d)  // a line as CFF import writes it: points at thirds
    if (trial % 2 == 0 && i % (2 * d) == 0)
      for (int k = 1; k < d; ++k) P[i + k] = P[i] + (static_cast<double>(k) / d) * (P[i + d] - P[i]);
  std::vector<double> knots;
  for (int j = 0; j <= n; ++j)
    for (int k = 0; k < d; ++k) knots.push_back(j * (trial % 3 == 0 ? 0.75 : 1.0));
  return BSpline::make(d, knots, P, "chain " + std::to_string(trial));
}

// Simple interior knots: no window is a Bezier window but the ends'.
BSpline uniform(std::mt19937_64& rng, int d, int m) {
  std::uniform_real_distribution<double> real(-10, 10);
  std::vector<Vec2> P;
  for (int i = 0; i < m; ++i) P.push_back(Vec2(real(rng), real(rng)));
  std::vector<double> knots(d, 0.0);
  for (int j = 1; j < m - d; ++j) knots.push_back(j / 3.0);
  for (int k = 0; k < d; ++k) knots.push_back((m - d) / 3.0);
  return BSpline::make(d, knots, P, "uniform");
}

std::vector<Point<Rational>> blossomed(const BSpline& s, const Segment& seg) {
  const SegmentWindow<Rational> w = segment_window<Rational>(s, seg);
  return bezier_points(w.knots, w.points, s.degree(), w.span, Rational(seg.a), Rational(seg.b));
}

// kappa at an end from the blossomed Bezier points, as certified_end_curvature's exact path computes it.
double blossomed_end_kappa(const BSpline& s, const Segment& seg, int side) {
  const std::vector<Point<Rational>> B = blossomed(s, seg);
  const int d = s.degree();
  EndTerms<Rational> t = side == 0 ? end_terms<Rational>(B[0], B[1], B[2]) : end_terms<Rational>(B[d], B[d - 1], B[d - 2]);
  if (side == 1) t.A = -t.A;
  if (sgn(t.G) == 0) return std::nan("");
  const double c = (d - 1.0) / d, A = t.A.get_d(), G = t.G.get_d();
  return c * A / G / std::sqrt(G);
}

void expect_blossom_results(const BSpline& s, bool all_windows_bezier) {
  const ExactOnlyScope exact_only;  // the curvatures from the exact end terms
  for (const Segment& seg : s.segments()) {
    const std::string ctx = s.name() + ", segment " + std::to_string(seg.index);
    if (all_windows_bezier) {
      EXPECT_TRUE(bezier_window(s, seg)) << ctx;
    }
    const std::vector<Point<Rational>> fast = segment_bezier_points<Rational>(s, seg), slow = blossomed(s, seg);
    ASSERT_EQ(fast.size(), slow.size()) << ctx;
    for (std::size_t k = 0; k < fast.size(); ++k) {
      EXPECT_EQ(fast[k].x, slow[k].x) << ctx << ", point " << k;
      EXPECT_EQ(fast[k].y, slow[k].y) << ctx << ", point " << k;
    }
    for (int side : {0, 1}) {
      const double got = certified_end_curvature(s, seg, side), want = blossomed_end_kappa(s, seg, side);
      if (std::isnan(want)) EXPECT_TRUE(std::isnan(got)) << ctx << ", side " << side;
      else EXPECT_EQ(got, want) << ctx << ", side " << side;
    }
  }
}

TEST(BezierWindow, ChainsGetTheBlossomsPointsAndEndCurvatures) {
  std::mt19937_64 rng(1124);
  for (int trial = 0; trial < 60; ++trial) {
    const BSpline s = chain(rng, 2 + trial % 4, 1 + trial % 5, trial);
    expect_blossom_results(s, true);
    if (::testing::Test::HasFailure()) return;
  }
}

TEST(BezierWindow, OtherKnotsAreBlossomed) {
  std::mt19937_64 rng(7);
  for (int d = 2; d <= 5; ++d) {
    const BSpline s = uniform(rng, d, d + 6);
    int bezier = 0;
    for (const Segment& seg : s.segments()) bezier += bezier_window(s, seg);
    EXPECT_EQ(bezier, 0) << "degree " << d;  // every window has a simple knot
    expect_blossom_results(s, false);
  }
}

}  // namespace
}  // namespace cmr
