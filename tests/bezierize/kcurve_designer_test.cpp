// bezierize/kcurve on designer-like point sets: 4-12 points clicked around a
// circle (random angles in order, radius noise +-30%), open and closed. The
// iteration converges on at least 99% of them; every piece of a cubic chain
// is certified monotone by the exact classifier (what `cmr analyze` says);
// collinear points give a straight curve or one clear error. The gate
// extrema-at-nodes on the same chains is checked in tests/report.
#include "tests/bezierize/kcurve_sets.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "bezierize/analyze.hpp"
#include "bezierize/kcurve.hpp"
#include "spline/errors.hpp"

namespace cmr {
namespace {

KCurve solve(const test::PointSet& s) {
  KCurveOptions o;
  o.closed = s.closed;
  return kcurve(s.points, o);
}

TEST(KCurveDesigner, ConvergesOnAtLeast99PercentOf400SeededSets) {
  const std::vector<test::PointSet> sets = test::designer_sets(2017, 400);
  std::vector<std::string> failed;
  std::size_t off_point = 0;
  for (const test::PointSet& s : sets) {
    try {
      const KCurve k = solve(s);
      off_point += !k.off_point_maxima.empty();
      if (!k.converged())
        failed.push_back(s.str() + " (residual " + std::to_string(k.residual) + " after " +
                         std::to_string(k.iterations) + " iterations)");
    } catch (const InputError& e) {
      failed.push_back(s.str() + " (" + e.what() + ")");
    }
  }
  std::string list;
  for (const std::string& f : failed) list += "\n  " + f;
  EXPECT_LE(failed.size() * 100, sets.size()) << failed.size() << " of " << sets.size() << " did not converge:" << list;
  // Most are κ-curves proper; the others are the published fixed point with
  // a point on a joint, flagged (7% of these sets when this was written).
  EXPECT_LE(off_point * 10, sets.size()) << off_point << " of " << sets.size() << " have a maximum off their point";
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
