// bezierize/kcurve: the defining properties of κ-curves, certified. Every
// curvature maximum (root of lambda, isolated exactly by bezierize/roots)
// lies at an input point, joints are G2 except at inflections, the cubic
// chain of CAD&A 2024 §5.2 keeps P_{k-1}, P_k, P_{k+1} collinear, a regular
// polygon matches its closed form, and degenerate input gives a clear error
// or a finite curve.
#include "design/kcurve.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bezierize/extract.hpp"
#include "bezierize/lambda.hpp"
#include "numeric/roots.hpp"
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "spline/errors.hpp"

namespace cmr {
namespace {

/// Tolerances of the checks, relative to the points' extent (or to the
/// largest |κ| for curvature), well above the iteration's 1e-12 residual.
constexpr double kPointTolerance = 1e-7;
constexpr double kCurvatureTolerance = 1e-6;

/// "open (x,y)(x,y)..." for traces.
std::string str(const std::vector<Vec2>& pts, bool closed = false) {
  std::ostringstream s;
  s << (closed ? "closed " : "open ");
  for (const Vec2& p : pts) s << '(' << p.x << ',' << p.y << ')';
  return s.str();
}

double extent(const std::vector<Vec2>& pts) {
  Vec2 lo = pts[0], hi = pts[0];
  for (const Vec2& p : pts) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return glm::length(hi - lo);
}

/// de Casteljau in double (independent of the code under test).
Vec2 bezier_at(std::vector<Vec2> b, double t) {
  for (std::size_t r = 1; r < b.size(); ++r)
    for (std::size_t i = 0; i + r < b.size(); ++i) b[i] = (1 - t) * b[i] + t * b[i + 1];
  return b[0];
}

/// Parameters (enclosure midpoints) where lambda of the Bézier piece changes
/// sign in [0, 1]: its curvature extrema, certified by exact isolation.
std::vector<double> extrema(const std::vector<Vec2>& piece) {
  std::vector<Point<Rational>> exact;
  for (const Vec2& p : piece) exact.push_back(to_point<Rational>(p));
  std::vector<double> out;
  for (const RootInterval& r : isolate_roots(lambda_bernstein<Rational>(exact), {1e-13}))
    if (r.sign_change()) out.push_back(nearest_double(Rational((r.lo + r.hi) / 2)));
  return out;
}

/// Signed curvature of a quadratic at t = 0 or 1.
double quadratic_kappa(const std::array<Vec2, 3>& q, double t) {
  const Vec2 d1 = 2.0 * ((1 - t) * (q[1] - q[0]) + t * (q[2] - q[1])), d2 = 2.0 * (q[0] - 2.0 * q[1] + q[2]);
  return det(d1, d2) / std::pow(glm::length(d1), 3);
}

/// The interpolated points in quadratic order.
std::vector<Vec2> interpolated(const std::vector<Vec2>& pts, bool closed) {
  return closed ? pts : std::vector<Vec2>(pts.begin() + 1, pts.end() - 1);
}

void expect_quadratic_properties(const KCurve& k, const std::vector<Vec2>& pts, bool closed) {
  const std::vector<Vec2> p = interpolated(pts, closed);
  const double e = extent(pts);
  ASSERT_EQ(k.quadratics.size(), p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto& q = k.quadratics[i];
    for (const Vec2& c : q) ASSERT_TRUE(std::isfinite(c.x) && std::isfinite(c.y)) << "quadratic " << i;
    // At most one extremum (the quadratic's |κ| is unimodal). Where the
    // iteration settles with p_i on a joint, the maximum is that end (t_max
    // 0 or 1) and lambda has no root inside; κ-curves guarantee that maxima
    // lie only at the points, not that every point is a maximum.
    const std::vector<double> roots = extrema({q.begin(), q.end()});
    ASSERT_LE(roots.size(), 1u) << "quadratic " << i << " has " << roots.size() << " curvature extrema";
    const std::vector<double> t = roots.empty() ? std::vector<double>{k.t_max[i]} : roots;
    if (roots.empty()) {
      EXPECT_TRUE(t[0] == 0 || t[0] == 1) << "quadratic " << i << ": t_max " << t[0];
    }
    const Vec2 at = bezier_at({q.begin(), q.end()}, t[0]);
    const bool off_point = std::count(k.off_point_maxima.begin(), k.off_point_maxima.end(), static_cast<int>(i)) > 0;
    // Flagged exactly where the maximum is not at the point (the published
    // fixed point with the point on a joint; kcurve.hpp).
    EXPECT_EQ(off_point, glm::length(at - p[i]) > kPointTolerance * e) << "quadratic " << i;
    if (off_point) continue;
    EXPECT_LE(glm::length(at - p[i]), kPointTolerance * e)
        << "quadratic " << i << ": maximum at t = " << t[0] << " is (" << at.x << "," << at.y << "), point ("
        << p[i].x << "," << p[i].y << ")";
    EXPECT_NEAR(k.t_max[i], t[0], 1e-9) << "quadratic " << i << ": Eq. 7 against the root of lambda";
  }
  const std::size_t joints = closed ? p.size() : p.size() - 1;
  for (std::size_t i = 0; i < joints; ++i) {
    const auto& l = k.quadratics[i];
    const auto& r = k.quadratics[(i + 1) % p.size()];
    EXPECT_EQ(l[2], r[0]) << "joint " << i;
    EXPECT_LE(std::abs(det(l[2] - l[1], r[1] - r[0])), 1e-12 * e * e) << "joint " << i << " is not G1";
    const double kl = quadratic_kappa(l, 1), kr = quadratic_kappa(r, 0);
    const double scale = std::max(std::abs(kl), std::abs(kr));
    if (kl * kr > 0)  // no inflection at the joint: G2
      EXPECT_LE(std::abs(kl - kr), kCurvatureTolerance * scale) << "joint " << i << ": kappa " << kl << " vs " << kr;
    else  // an inflection: the magnitudes still agree
      EXPECT_LE(std::abs(std::abs(kl) - std::abs(kr)), kCurvatureTolerance * scale) << "joint " << i;
  }
}

void expect_cubic_chain_properties(const KCurve& k, const std::vector<Vec2>& pts, bool closed) {
  const BSpline chain = kcurve_cubic_chain(k);
  const std::vector<int> maxima = kcurve_cubic_maxima(k);
  const std::vector<Vec2> p = interpolated(pts, closed);
  const double e = extent(pts);
  ASSERT_EQ(maxima.size(), p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const int m = maxima[i];
    if (m < 0) {  // the maximum is at the quadratic's end (see above): no handle pair
      EXPECT_TRUE(k.t_max[i] == 0 || k.t_max[i] == 1) << "point " << i;
      continue;
    }
    const auto& c = chain.points();
    if (std::count(k.off_point_maxima.begin(), k.off_point_maxima.end(), static_cast<int>(i)) == 0) {
      EXPECT_LE(glm::length(c[m] - p[i]), kPointTolerance * e) << "P_k of point " << i;
    }
    EXPECT_LE(std::abs(det(c[m] - c[m - 1], c[m + 1] - c[m])), 1e-12 * e * e) << "handles of point " << i;
  }
  for (const BezierSegment& b : bezier_segments(chain))
    for (double t : extrema(b.points)) {
      const Vec2 at = bezier_at(b.points, t);
      double nearest = std::numeric_limits<double>::infinity();
      for (const Vec2& q : p) nearest = std::min(nearest, glm::length(at - q));
      for (int m : maxima)  // an off-point maximum is a joint of the chain
        if (m >= 0) nearest = std::min(nearest, glm::length(at - chain.points()[m]));
      EXPECT_LE(nearest, kPointTolerance * e) << "cubic piece " << b.segment.index << ": extremum at t = " << t;
    }
}

/// Checks every property of a converged κ-curve through pts; returns false
/// (after checking that the result is finite) when it did not converge and
/// `may_stall` allows that.
bool expect_kcurve(const std::vector<Vec2>& pts, bool closed, bool may_stall = false) {
  SCOPED_TRACE(str(pts, closed));
  const KCurve k = kcurve(pts, {.closed = closed});
  EXPECT_TRUE(std::isfinite(k.residual));
  if (may_stall && !k.converged()) return false;
  EXPECT_TRUE(k.converged()) << "residual " << k.residual << " after " << k.iterations << " iterations";
  expect_quadratic_properties(k, pts, closed);
  expect_cubic_chain_properties(k, pts, closed);
  const BSpline q = kcurve_quadratic_spline(k);
  EXPECT_EQ(q.segment_count(), static_cast<int>(k.quadratics.size()));
  EXPECT_EQ(q.points().front(), k.quadratics[0][0]);
  if (closed) {
    EXPECT_EQ(q.points().front(), q.points().back());
  } else {
    EXPECT_EQ(q.points().front(), pts.front());
    EXPECT_EQ(q.points().back(), pts.back());
  }
  return true;
}

TEST(KCurve, OpenHandCases) {
  expect_kcurve({{0, 0}, {1, 1}, {2, 0}}, false);
  expect_kcurve({{0, 0}, {1, 2}, {3, 2.5}, {4, 0.5}, {6, 1}}, false);
  expect_kcurve({{0, 0}, {1, 1}, {2, -1}, {3, 1}, {4, -1}, {5, 0}}, false);  // zigzag: inflections at joints
}

TEST(KCurve, ClosedHandCases) {
  expect_kcurve({{0, 0}, {2, 0}, {1, 1.5}}, true);  // three points
  expect_kcurve({{0, 0}, {3, 0}, {3, 2}, {0, 2}}, true);
  expect_kcurve({{0, 0}, {2, -1}, {4, 0}, {3, 1}, {4, 3}, {1, 2}}, true);  // non-convex
}

TEST(KCurve, RegularPolygonMatchesClosedForm) {
  // By symmetry t_i = 1/2 and λ_i = 1/2, so p_i = c_{i-1,1}/8 + 3 c_{i,1}/4 + c_{i+1,1}/8;
  // with c_{i,1} = s p_i (rotations by 2π/n) s = 4 / (3 + cos(2π/n)).
  for (int n : {3, 5, 8}) {
    std::vector<Vec2> pts;
    for (int i = 0; i < n; ++i)
      pts.push_back({std::cos(2 * std::numbers::pi * i / n), std::sin(2 * std::numbers::pi * i / n)});
    const KCurve k = kcurve(pts, {.closed = true});
    const double s = 4 / (3 + std::cos(2 * std::numbers::pi / n));
    for (int i = 0; i < n; ++i) {
      EXPECT_NEAR(k.quadratics[i][1].x, s * pts[i].x, 1e-10) << "n = " << n << ", i = " << i;
      EXPECT_NEAR(k.quadratics[i][1].y, s * pts[i].y, 1e-10) << "n = " << n << ", i = " << i;
      EXPECT_NEAR(k.t_max[i], 0.5, 1e-10) << "n = " << n << ", i = " << i;
    }
  }
}

/// A random walk: steps of 0.3..1, turning by up to 2 rad (115 degrees) at
/// each point (much sharper turns may not converge; see kcurve.hpp).
std::vector<Vec2> random_points(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> step(0.3, 1), turn(-2, 2), start(-1, 1);
  std::vector<Vec2> pts{{start(rng), start(rng)}};
  double heading = std::numbers::pi * start(rng);
  while (static_cast<int>(pts.size()) < n) {
    pts.push_back(pts.back() + step(rng) * Vec2{std::cos(heading), std::sin(heading)});
    heading += turn(rng);
  }
  return pts;
}

// Random walks: every converged curve has all the properties; the iteration
// may stall (slowly approaching a state with a point on a joint) in a few.
constexpr int kRandomCases = 60;
constexpr int kMaxStalled = kRandomCases / 10;

TEST(KCurve, RandomOpenCurves) {
  std::mt19937 rng(20171);
  int stalled = 0;
  for (int c = 0; c < kRandomCases; ++c) stalled += !expect_kcurve(random_points(rng, 3 + c % 8), false, true);
  EXPECT_LE(stalled, kMaxStalled) << stalled << " of " << kRandomCases << " did not converge";
}

TEST(KCurve, RandomClosedCurves) {
  std::mt19937 rng(20172);
  int stalled = 0;
  for (int c = 0; c < kRandomCases; ++c) {
    const std::vector<Vec2> pts = random_points(rng, 3 + c % 8);
    if (glm::length(pts.front() - pts.back()) <= 0.2) continue;  // too close to close the curve
    stalled += !expect_kcurve(pts, true, true);
  }
  EXPECT_LE(stalled, kMaxStalled) << stalled << " of " << kRandomCases << " did not converge";
}

TEST(KCurveParameter, TheCubicHasOneRootInTheUnitInterval) {
  // f in Bernstein form (-|A|^2, -A.B/3, A.B/3, |B|^2), isolated exactly; the
  // root must be unique and the bisection must land in its enclosure.
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0, 1);
  for (int c = 0; c < 500; ++c) {
    const Vec2 p{g(rng), g(rng)}, c0 = p + Vec2{g(rng), g(rng)}, c2 = p + 3.0 * Vec2{g(rng), g(rng)};
    const Vec2 A = c0 - p, B = c2 - p;
    const Rational aa = dot(to_point<Rational>(A), to_point<Rational>(A));
    const Rational bb = dot(to_point<Rational>(B), to_point<Rational>(B));
    const Rational ab = dot(to_point<Rational>(A), to_point<Rational>(B));
    const Bernstein<Rational> f{Rational(-aa), Rational(-ab / 3), Rational(ab / 3), bb};
    const std::vector<RootInterval> roots = isolate_roots(f, {1e-14});
    ASSERT_EQ(roots.size(), 1u) << "case " << c;
    const double t = kcurve_parameter(c0, p, c2);
    EXPECT_GE(t, double_below(roots[0].lo) - 1e-15) << "case " << c;
    EXPECT_LE(t, double_above(roots[0].hi) + 1e-15) << "case " << c;
  }
}

TEST(KCurveParameter, VanishingLeadingCoefficient) {
  // c0 == c2: the cubic's monomial leading coefficient |c2 - c0|^2 is zero;
  // f = |A|^2 (2t - 1), so t = 1/2.
  EXPECT_NEAR(kcurve_parameter({0, 0}, {1, 2}, {0, 0}), 0.5, 1e-15);
  EXPECT_EQ(kcurve_parameter({1, 2}, {1, 2}, {3, 0}), 0.0);
  EXPECT_EQ(kcurve_parameter({3, 0}, {1, 2}, {1, 2}), 1.0);
}

TEST(KCurve, Eq7IsTheRootOfLambda) {
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0, 1);
  for (int c = 0; c < 200; ++c) {
    const std::array<Vec2, 3> q{Vec2{g(rng), g(rng)}, Vec2{g(rng), g(rng)}, Vec2{g(rng), g(rng)}};
    const std::vector<double> t = extrema({q.begin(), q.end()});
    const double t7 = quadratic_max_curvature_parameter(q);
    if (t.empty()) {
      EXPECT_TRUE(t7 == 0 || t7 == 1) << "case " << c << ": no extremum inside, Eq. 7 gave " << t7;
    } else {
      EXPECT_NEAR(t7, t[0], 1e-9) << "case " << c;
    }
  }
}

bool finite(const KCurve& k) {
  for (const auto& q : k.quadratics)
    for (const Vec2& c : q)
      if (!std::isfinite(c.x) || !std::isfinite(c.y)) return false;
  return std::isfinite(k.residual);
}

// Points near the largest double (fuzz_kcurve's findings, as read from its
// bytes): the cubic chain's split or elevation overflows. A clear error or
// a finite chain, never a crash (the exact classifier used to get an
// infinity and raise SIGFPE).
TEST(KCurve, PointsNearTheLargestDoubleGiveAFiniteChainOrAClearError) {
  const std::vector<std::pair<bool, std::vector<Vec2>>> cases = {
      {true,
       {{1.760393235447819e+297, 2.326012833169336e+289}, {8.362188788023996e+307, 1.3857408240993618e+302},
        {5.7280892014183596e+296, 1.2449185823486819e+306}, {-5.621395936180985e+304, -4.9517179044352835e+295},
        {-1.3161571836712188e+302, 4.020935411027028e+303}}},
      {false,
       {{0.0, 0.0}, {8.87231475e-315, -8.707576121989343e+307}, {-8.777798510069901e+304, -2.002482340608276e+185},
        {-5.486124068823628e+303, 1.9999999999999998}, {4.073325944587168e+207, 9.790617806372213e+153}}}};
  for (const auto& [closed, points] : cases) {
    KCurveOptions o;
    o.closed = closed;
    o.max_iterations = 200;
    try {
      const KCurve k = kcurve(points, o);
      const BSpline chain = kcurve_cubic_chain(k);
      for (const Vec2& p : chain.points()) EXPECT_TRUE(std::isfinite(p.x) && std::isfinite(p.y));
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()), "");
    }
  }
}

TEST(KCurve, DegenerateInputIsAClearErrorOrAFiniteCurve) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(kcurve(std::vector<Vec2>{{0, 0}, {1, 1}}), InputError);
  EXPECT_THROW(kcurve(std::vector<Vec2>{{0, 0}, {1, 1}}, {.closed = true}), InputError);
  EXPECT_THROW(kcurve(std::vector<Vec2>{}), InputError);
  EXPECT_THROW(kcurve(std::vector<Vec2>{{0, 0}, {1, nan}, {2, 0}}), InputError);
  EXPECT_THROW(kcurve(std::vector<Vec2>{{0, 0}, {1, 1}, {1, 1}, {2, 0}}), InputError);
  EXPECT_THROW(kcurve(std::vector<Vec2>{{0, 0}, {1, 1}, {2, 0}, {0, 0}}, {.closed = true}), InputError);
  EXPECT_THROW(kcurve(std::vector<Vec2>{{0, 0}, {1, 1}, {2, 0}}, {.tolerance = 0}), InputError);
  EXPECT_THROW(kcurve(std::vector<Vec2>{{0, 0}, {1, 1}, {2, 0}}, {.max_iterations = 0}), InputError);
  try {
    (void)kcurve(std::vector<Vec2>{{0, 0}, {1, 1}, {1, 1}, {2, 0}});
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("points[1]"), std::string::npos) << e.what();
  }
  // Collinear points, open and closed (folded back), and an open curve whose
  // ends coincide (the vanishing leading coefficient inside the iteration).
  for (const auto& [pts, closed] : std::vector<std::pair<std::vector<Vec2>, bool>>{
           {{{0, 0}, {1, 0}, {2, 0}, {3, 0}}, false},
           {{{0, 0}, {1, 1}, {3, 3}}, false},
           {{{0, 0}, {1, 0}, {3, 0}}, true},
           {{{0, 0}, {1, 2}, {0, 0}}, false},
           {{{0, 0}, {1, 2}, {2, 0}, {1, 2}, {0, 0}}, false}}) {
    SCOPED_TRACE(str(pts, closed));
    try {
      const KCurve k = kcurve(pts, {.closed = closed});
      EXPECT_TRUE(finite(k));
      EXPECT_NO_THROW((void)kcurve_quadratic_spline(k));
      EXPECT_NO_THROW((void)kcurve_cubic_chain(k));
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
  }
}

// Issue 42 E3: the work budget bounds a solve by the input's size. A
// budget too small for the input stops the solve (not converged, and
// budget_spent says why); with the default, a small curve is unaffected.
TEST(KCurveBudget, WorkBudgetStopsTheSolveAndSaysSo) {
  const std::vector<Vec2> points{{0, 0}, {1, 2}, {3, 2.5}, {4, 0.5}, {6, 1}};
  KCurveOptions o;
  const KCurve free = kcurve(points, o);
  ASSERT_TRUE(free.converged());
  EXPECT_FALSE(free.budget_spent);
  o.max_point_iterations = 3 * 2;  // two iterations of the three interpolated points
  const KCurve cut = kcurve(points, o);
  EXPECT_TRUE(cut.budget_spent);
  EXPECT_LE(cut.iterations, 2);
  EXPECT_FALSE(cut.converged()) << "two iterations cannot reach 1e-10";
  o.max_point_iterations = -1;
  EXPECT_THROW(kcurve(points, o), InputError);
}

// A zero-length quadratic (its two joints coincide) is found, so that cmr
// kcurve refuses it instead of printing it as a success.
TEST(KCurveBudget, DegeneratePiecesAreTheZeroLengthQuadratics) {
  KCurve k;
  k.quadratics = {{Vec2(0, 0), Vec2(1, 1), Vec2(2, 0)}, {Vec2(2, 0), Vec2(2.5, 0.5), Vec2(2, 0)},
                  {Vec2(2, 0), Vec2(3, -1), Vec2(4, 0)}};
  EXPECT_EQ(kcurve_degenerate_pieces(k), std::vector<int>{1});
  k.quadratics[1][2] = Vec2(2.5, 0);
  k.quadratics[2][0] = Vec2(2.5, 0);
  EXPECT_EQ(kcurve_degenerate_pieces(k), std::vector<int>{});
}

}  // namespace
}  // namespace cmr
