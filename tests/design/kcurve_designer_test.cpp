// bezierize/kcurve on designer-like point sets: 4-12 points clicked around a
// circle (random angles in order, radius noise +-30%), open and closed. The
// iteration converges on at least 99% of them, and the counts of κ-curves
// proper / every maximum at a point / a maximum at no point are printed and
// held to docs/kcurve.md's floor; stray maxima are checked against the exact
// curvature extrema; every piece of a cubic chain
// is certified monotone by the exact classifier (what `cmr analyze` says);
// collinear points give a straight curve or one clear error. The gate
// curvature-extrema-at-nodes on the same chains is checked in tests/report.
#include "tests/design/kcurve_sets.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "bezierize/analyze.hpp"
#include "bezierize/extract.hpp"
#include "bezierize/lambda.hpp"
#include "numeric/roots.hpp"
#include "design/kcurve.hpp"
#include "spline/errors.hpp"

namespace cmr {
namespace {

KCurve solve(const test::PointSet& s) {
  KCurveOptions o;
  o.closed = s.closed;
  return kcurve(s.points, o);
}

/// What kcurve() gave one set: a κ-curve proper (every point its
/// quadratic's |κ| maximum), every maximum of |κ| at a point but some point
/// on a joint (off_point_maxima, no stray_maxima), a maximum of |κ| at no
/// point (stray_maxima), or no convergence / an error.
enum class Outcome { proper, maxima_at_points, stray_maximum, failed };

Outcome outcome(const KCurve& k) {
  if (!k.converged()) return Outcome::failed;
  if (k.off_point_maxima.empty()) return Outcome::proper;
  return k.stray_maxima.empty() ? Outcome::maxima_at_points : Outcome::stray_maximum;
}

/// The 400 sets of seed 2017 and their answers (solved once for the tests
/// below; an InputError's message where kcurve threw).
struct Solved {
  std::vector<test::PointSet> sets;
  std::vector<KCurve> curves;
  std::vector<std::string> errors;
};
const Solved& seeded_400() {
  static const Solved solved = [] {
    Solved out;
    out.sets = test::designer_sets(2017, 400);
    for (const test::PointSet& s : out.sets) {
      try {
        out.curves.push_back(solve(s));
        out.errors.emplace_back();
      } catch (const InputError& e) {
        out.curves.emplace_back();
        out.errors.emplace_back(e.what());
      }
    }
    return out;
  }();
  return solved;
}

TEST(KCurveDesigner, ConvergesOnAtLeast99PercentOf400SeededSets) {
  const Solved& solved = seeded_400();
  const std::vector<test::PointSet>& sets = solved.sets;
  std::vector<std::string> failed, stray;
  std::size_t proper = 0, at_points = 0;
  for (std::size_t c = 0; c < sets.size(); ++c) {
    const test::PointSet& s = sets[c];
    if (!solved.errors[c].empty()) {
      failed.push_back(s.str() + " (" + solved.errors[c] + ")");
      continue;
    }
    {
      const KCurve& k = solved.curves[c];
      switch (outcome(k)) {
        case Outcome::proper: ++proper; break;
        case Outcome::maxima_at_points: ++at_points; break;
        case Outcome::stray_maximum: stray.push_back(s.str()); break;
        case Outcome::failed:
          failed.push_back(s.str() + " (residual " + std::to_string(k.residual) + " after " +
                           std::to_string(k.iterations) + " iterations)");
      }
    }
  }
  // The counts docs/kcurve.md quotes.
  std::cout << "kappa-curves on " << sets.size() << " seeded designer-like sets: " << proper << " proper, "
            << at_points << " with every |kappa| maximum at a point (a point on a joint), " << stray.size()
            << " with a maximum at no point, " << failed.size() << " not converged\n";
  std::string list;
  for (const std::string& f : failed) list += "\n  " + f;
  EXPECT_LE(failed.size() * 100, sets.size()) << failed.size() << " of " << sets.size() << " did not converge:" << list;
  // Every point a maximum (the κ-curve proper) on at least 99%, and every
  // maximum of |κ| at a point (Yan et al.'s guarantee) on at least 99%.
  list.clear();
  for (const std::string& f : stray) list += "\n  " + f;
  EXPECT_GE((proper + at_points) * 100, 99 * sets.size())
      << stray.size() + failed.size() << " of " << sets.size() << " have a maximum at no point:" << list;
  EXPECT_GE(proper * 100, 99 * sets.size()) << proper << " of " << sets.size() << " are kappa-curves proper";
}

/// Parameters (enclosure midpoints) where lambda of the Bézier piece changes
/// sign in [0, 1]: its curvature extrema, certified by exact isolation
/// (independent of kcurve's Eq. 7).
std::vector<double> exact_extrema(const std::array<Vec2, 3>& q) {
  std::vector<Point<Rational>> exact;
  for (const Vec2& p : q) exact.push_back(to_point<Rational>(p));
  std::vector<double> out;
  for (const RootInterval& r : isolate_roots(lambda_bernstein<Rational>(exact), {1e-13}))
    if (r.sign_change()) out.push_back(nearest_double(Rational((r.lo + r.hi) / 2)));
  return out;
}

Vec2 quadratic_at(const std::array<Vec2, 3>& q, double t) {
  return (1 - t) * (1 - t) * q[0] + 2 * t * (1 - t) * q[1] + t * t * q[2];
}

double abs_kappa(const std::array<Vec2, 3>& q, double t) {
  const Vec2 d1 = 2.0 * ((1 - t) * (q[1] - q[0]) + t * (q[2] - q[1])), d2 = 2.0 * (q[0] - 2.0 * q[1] + q[2]);
  return std::abs(det(d1, d2)) / std::pow(glm::length(d1), 3);
}

/// The quadratics with a local maximum of |κ| at none of the points, from
/// the exact extrema: an interior extremum that is a maximum away from every
/// point, or a joint where |κ| rises from both sides.
std::vector<int> exact_stray_maxima(const KCurve& k, const std::vector<Vec2>& points, double distance) {
  auto at_point = [&](Vec2 v) {
    return std::any_of(points.begin(), points.end(), [&](Vec2 p) { return glm::length(v - p) <= distance; });
  };
  const int n = static_cast<int>(k.quadratics.size());
  std::vector<int> out;
  for (int i = 0; i < n; ++i) {
    const auto& q = k.quadratics[i];
    const std::vector<double> e = exact_extrema(q);
    bool stray = false;
    for (double t : e)
      if (t > 0 && t < 1 && abs_kappa(q, t) >= std::max(abs_kappa(q, 0), abs_kappa(q, 1)) &&
          !at_point(quadratic_at(q, t)))
        stray = true;
    if (e.empty() && (k.closed || i + 1 < n) && abs_kappa(q, 1) > abs_kappa(q, 0)) {
      const auto& r = k.quadratics[(i + 1) % n];
      if (exact_extrema(r).empty() && abs_kappa(r, 0) > abs_kappa(r, 1) && !at_point(q[2])) stray = true;
    }
    if (stray) out.push_back(i);
  }
  return out;
}

TEST(KCurveDesigner, StrayMaximaAgreeWithExactExtremaAndEachHasOneNote) {
  const Solved& solved = seeded_400();
  int checked = 0, strays = 0;
  for (std::size_t c = 0; c < solved.sets.size(); ++c) {
    const test::PointSet& s = solved.sets[c];
    const KCurve& k = solved.curves[c];
    if (!solved.errors[c].empty() || !k.converged()) continue;  // counted by the test above
    // Every set with a point off its maximum, and every tenth of the others.
    if (k.off_point_maxima.empty() && c % 10 != 0) continue;
    ++checked;
    Vec2 lo = s.points[0], hi = s.points[0];
    for (const Vec2& p : s.points) lo = glm::min(lo, p), hi = glm::max(hi, p);
    const double distance = 1e-7 * glm::length(hi - lo);
    EXPECT_EQ(k.stray_maxima, exact_stray_maxima(k, s.points, distance)) << s.str();
    strays += !k.stray_maxima.empty();
    const std::vector<std::string> notes = kcurve_off_point_notes(k, s.points);
    ASSERT_EQ(notes.size(), k.off_point_maxima.size()) << s.str();
    for (std::size_t j = 0; j < notes.size(); ++j) {
      const int point = s.closed ? k.off_point_maxima[j] : k.off_point_maxima[j] + 1;
      EXPECT_NE(notes[j].find("points[" + std::to_string(point) + "]"), std::string::npos) << notes[j];
      EXPECT_EQ(notes[j].find('\n'), std::string::npos) << notes[j];
    }
  }
  EXPECT_GE(checked, 40);
  EXPECT_GE(strays, 1) << "no set exercised the stray-maximum oracle";
}

TEST(KCurveDesigner, RestartsReachTheKappaCurveProperWhereThePublishedStartDoesNot) {
  // Set 293 of seed 2017: the published start (and the first six other
  // starts) leave points[2] on a joint; a later start finds the κ-curve proper.
  const test::PointSet s = test::designer_sets(2017, 400)[293];
  KCurveOptions o;
  o.closed = s.closed;
  o.restarts = 0;
  const KCurve first = kcurve(s.points, o);
  ASSERT_TRUE(first.converged()) << s.str();
  EXPECT_EQ(first.off_point_maxima, std::vector<int>{2}) << s.str();
  o.restarts = kKCurveRestarts;
  const KCurve best = kcurve(s.points, o);
  ASSERT_TRUE(best.converged()) << s.str();
  EXPECT_TRUE(best.off_point_maxima.empty()) << s.str();
  o.restarts = -1;
  try {
    (void)kcurve(s.points, o);
    ADD_FAILURE() << "restarts -1 was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("restarts -1 is below 0"), std::string::npos) << e.what();
  }
}

TEST(KCurveDesigner, EveryCubicPieceIsCertifiedMonotone) {
  int chains = 0;
  for (const test::PointSet& s : test::designer_sets(20240, 40)) {
    const KCurve k = solve(s);
    if (!k.converged()) continue;  // the rate is the test above
    ++chains;
    EXPECT_TRUE(kcurve_cubic_uncertified(k).empty()) << s.str();
    const BSpline chain = kcurve_cubic_chain(k);
    const SplineAnalysis a = analyze(chain);
    for (std::size_t i = 0; i < a.segments.size(); ++i) {
      const Curvature c = a.segments[i].monotonicity.curvature;
      EXPECT_TRUE(c == Curvature::increasing || c == Curvature::decreasing)
          << s.str() << ": piece " << i << " is " << to_string(c);
    }
    // The maxima of the κ-curve are joints of the chain, G1 and G2 within
    // analyze's default tolerances (the nudge changes curvature by ~1e-13).
    for (const Joint& j : a.joints) EXPECT_TRUE(j.g1) << s.str() << ": joint " << j.index;
  }
  EXPECT_GE(chains, 38);
}

TEST(KCurveDesigner, QuadraticJointsAreG2WithinTheDefaultTolerance) {
  for (const test::PointSet& s : test::designer_sets(31, 20)) {
    const KCurve k = solve(s);
    if (!k.converged()) continue;
    const SplineAnalysis a = analyze(kcurve_quadratic_spline(k));
    for (const Joint& j : a.joints)
      if (j.kappa_left * j.kappa_right > 0) {
        EXPECT_TRUE(j.g2) << s.str() << ": joint " << j.index;
      }
  }
}

TEST(KCurveCollinear, InOrderOpenPointsGiveAStraightCurve) {
  for (const std::vector<Vec2>& pts : std::vector<std::vector<Vec2>>{
           {{0, 0}, {1, 0}, {2, 0}, {3, 0}}, {{0, 0}, {1, 1}, {3, 3}}, {{0, 0}, {0.1, 0.2}, {0.2, 0.4}, {0.7, 1.4}}}) {
    const KCurve k = kcurve(pts);
    ASSERT_TRUE(k.converged()) << pts.size();
    EXPECT_TRUE(k.off_point_maxima.empty()) << pts.size() << " points: a straight curve has no maximum to miss";
    for (const SegmentClass& c : analyze(kcurve_cubic_chain(k)).segments)
      EXPECT_EQ(c.monotonicity.curvature, Curvature::constant) << pts.size() << " points";
  }
}

TEST(KCurveCollinear, ClosedOrTurningBackIsAnError) {
  const std::vector<Vec2> three{{0, 0}, {1, 0}, {2, 0}};
  try {
    (void)kcurve(three, {.closed = true});
    ADD_FAILURE() << "closed collinear points were accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("double back"), std::string::npos) << e.what();
  }
  const std::vector<Vec2> back{{0, 0}, {2, 0}, {1, 0}, {3, 0}};
  try {
    (void)kcurve(back);
    ADD_FAILURE() << "collinear points out of order were accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("points[2] turns back"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace cmr
