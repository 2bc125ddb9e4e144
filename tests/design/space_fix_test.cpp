// The nearest certified repair of a space curve (design/space_fix.hpp):
// fixes re-judged independently by analyze_space on the spline rebuilt from
// the reported move, the nearest position against a brute-force label map,
// rational curves, nothing to fix, invariance under rotation.
#include "design/space_fix.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <glm/geometric.hpp>

#include "spline/errors.hpp"
#include "tests/design/scaled_fix.hpp"
#include "spline/fields.hpp"

namespace cmr {
namespace {

/// Fig. 8 of the paper (failing: segments 0 and 1) lifted into space
/// (examples/space/fig8_lifted.json).
SpaceSpline lifted(std::vector<double> weights = {}) {
  return SpaceSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7},
                           {{1.3, -1.43, 0}, {1.05, -0.06, 0.3}, {2.15, -1.31, 0.8}, {1.97, -3.83, 1.5},
                            {-2.23, -6.95, 2.4}, {-6.78, -9.78, 3.5}},
                           "fig8-lifted", std::move(weights));
}

/// How the legs right of the Bezier form's joints are lengthened, and how far
/// handle B4 is then slid along its tangent towards its node (factors of its leg).
constexpr double kLengthen = 1.05, kSlide = 0.2;

bool monotone(const SpaceAnalysis& a) {
  return a.curvature == Direction::increasing || a.curvature == Direction::decreasing;
}

/// The fix applied to the input by hand (not the result's own spline), then
/// judged by analyze_space: what a user re-running `cmr analyze` sees.
void expect_certified(const SpaceSpline& in, const SpaceFixResult& f, const std::string& what) {
  ASSERT_TRUE(f.fixed) << what << ": " << f.reason;
  ASSERT_EQ(f.moves.size(), 1u) << what;
  const SpacePointMove& m = f.moves.front();
  EXPECT_EQ(m.from, in.points()[static_cast<std::size_t>(m.point)]) << what;
  EXPECT_NEAR(glm::length(m.to - m.from), m.distance, 1e-12) << what;
  EXPECT_GT(m.distance, 0) << what;
  std::vector<Vec3> pts = in.points();
  pts[static_cast<std::size_t>(m.point)] = m.to;
  std::vector<double> w;
  if (in.is_rational()) w = in.weights();
  const SpaceSpline moved = SpaceSpline::make(in.degree(), in.knots(), pts, in.name(), w);
  for (std::size_t i = 0; i < pts.size(); ++i) EXPECT_EQ(f.spline->points()[i], pts[i]) << what << ": point " << i;
  EXPECT_FALSE(monotone(analyze_space(in))) << what << ": the input must fail";
  const SpaceAnalysis a = analyze_space(moved);
  EXPECT_TRUE(monotone(a)) << what << ": the moved spline is " << to_string(a.curvature);
  // The moved point stays in its plane.
  const Vec3 n = glm::cross(m.plane.u, m.plane.v);
  EXPECT_NEAR(glm::dot(m.to - m.from, n), 0, 1e-12 * f.size) << what;
}

TEST(SpaceFix, FailingPolynomialCubicGetsACertifiedFix) {
  const SpaceSpline s = lifted();
  const SpaceFixResult f = space_fix(s, {});
  EXPECT_EQ(f.failing_segments, (std::vector<int>{0, 1}));
  expect_certified(s, f, "fig8 lifted");
  EXPECT_FALSE(f.already);
  EXPECT_TRUE(f.certificate_holds);
  EXPECT_LT(f.max_distance, 0.01 * f.size);  // a small move (P2: about 0.3 % of the size)
  // The best unit is reported: no other candidate found a nearer fix.
  for (const SpaceUnitFix& u : f.units)
    if (u.found) {
      EXPECT_GE(u.distance, f.max_distance - 1e-15) << "P" << u.point;
    }
}

TEST(SpaceFix, NearestMatchesABruteForceLabelMap) {
  const SpaceSpline s = lifted();
  SpaceFixRequest req;
  req.points = {2};
  req.no_zero_curvature = false;
  const SpaceFixResult f = space_fix(s, req);
  expect_certified(s, f, "P2");
  const SpacePointMove& m = f.moves.front();
  // Every pixel centre of a 160 x 160 map of P2's plane around it that passes
  // lies no nearer than the fix, less one pixel diagonal and the tolerance.
  SpaceRegionRequest rr;
  rr.point = 2;
  rr.plane = m.plane;
  const double h = 2 * m.distance;
  rr.view = View{-h, -h, h, h};
  rr.width = rr.height = 160;
  const SpaceRegionProblem problem = SpaceRegionProblem::make(s, rr);
  const RegionResult img = problem.render(1);
  const double pixel = 2 * h / 160, tol = 1e-6 * f.size;
  double nearest = 1e300;
  for (int y = 0; y < 160; ++y)
    for (int x = 0; x < 160; ++x) {
      const Direction l = img.labels[static_cast<std::size_t>(y * 160 + x)];
      if (l != Direction::increasing && l != Direction::decreasing) continue;
      const Vec2 c = pixel_center(img.view, 160, 160, x, y);
      nearest = std::min(nearest, std::hypot(c.x, c.y));
    }
  ASSERT_LT(nearest, 1e300) << "the map around the fix has no passing pixel";
  EXPECT_GE(nearest, m.distance - tol - pixel * std::sqrt(2.0));
  EXPECT_LE(m.distance, nearest + tol + pixel * std::sqrt(2.0));
}

TEST(SpaceFix, FailingRationalCubicGetsACertifiedFix) {
  const SpaceSpline s = lifted({1, 1.2, 0.9, 1.1, 1, 1});
  SpaceFixRequest req;
  req.points = {2};  // the nearest candidate of the polynomial curve; keeps the test short
  const SpaceFixResult f = space_fix(s, req);
  expect_certified(s, f, "fig8 lifted, rational");
  EXPECT_EQ(f.spline->weights(), s.weights());
}

TEST(SpaceFix, AMonotoneCurveHasNothingToFix) {
  const SpaceSpline s = SpaceSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7},
                                          {{1.3, -1.43, 0}, {1.05, -0.06, 0.3}, {2.15, -1.31, 0.8}, {1.2, -4.03, 1.5},
                                           {-2.23, -6.95, 2.4}, {-6.78, -9.78, 3.5}});
  const SpaceFixResult f = space_fix(s, {});
  EXPECT_TRUE(f.already);
  EXPECT_TRUE(f.fixed);
  EXPECT_TRUE(f.moves.empty());
  EXPECT_TRUE(f.units.empty());
  EXPECT_EQ(f.evaluations, 0);
}

// A curve far from unit size (Fig. 8 lifted, times 2^600, 2^-600 and 2^1000)
// is searched as its copy scaled by a power of two (exact): the same fix as
// the copy's, scaled back bit for bit. Without it every default plane came
// out degenerate (glm::length of differences near 2^600 is infinite) and no
// fix was found.
TEST(SpaceFix, AFarOffCurveIsFixedAsItsScaledCopy) {
  const SpaceSpline s = lifted();
  const auto times = [&](int e) {
    std::vector<Vec3> pts;
    for (const Vec3& p : s.points()) pts.push_back(std::ldexp(1.0, e) * p);
    return SpaceSpline::make(3, s.knots(), pts);
  };
  for (const int e : {600, -600, 1000}) {
    const SpaceSpline far_curve = times(e);
    Vec3 lo = far_curve.points().front(), hi = lo;
    for (const Vec3& p : far_curve.points()) lo = glm::min(lo, p), hi = glm::max(hi, p);
    const int k = std::ilogb(std::hypot(hi.x - lo.x, hi.y - lo.y, hi.z - lo.z));  // the copy: times(e - k)
    const SpaceFixResult far = space_fix(far_curve, {});
    test::expect_copy_scaled_back(far, space_fix(times(e - k), {}), k, "fig8 lifted times 2^" + std::to_string(e));
    ASSERT_TRUE(far.spline);
    EXPECT_TRUE(monotone(analyze_space(*far.spline))) << "2^" << e;  // (expect_certified's tolerances are absolute)
  }
}

TEST(SpaceFix, RotatingTheCurveRotatesTheFix) {
  const SpaceSpline s = lifted();
  const SpaceFixResult f = space_fix(s, {});
  ASSERT_TRUE(f.fixed) << f.reason;
  std::mt19937 rng(25);
  std::normal_distribution<double> g;
  for (int trial = 0; trial < 2; ++trial) {
    // A seeded rotation (Gram-Schmidt of random vectors) and a translation.
    Vec3 a{g(rng), g(rng), g(rng)}, b{g(rng), g(rng), g(rng)};
    a = glm::normalize(a);
    b = glm::normalize(b - glm::dot(b, a) * a);
    const Vec3 c = glm::cross(a, b), shift{g(rng), g(rng), g(rng)};
    const auto R = [&](const Vec3& p) { return p.x * a + p.y * b + p.z * c; };
    std::vector<Vec3> pts;
    for (const Vec3& p : s.points()) pts.push_back(R(p) + shift);
    const SpaceSpline r = SpaceSpline::make(3, s.knots(), pts);
    const SpaceFixResult fr = space_fix(r, {});
    const std::string what = "rotation " + std::to_string(trial);
    expect_certified(r, fr, what);
    EXPECT_EQ(fr.failing_segments, f.failing_segments) << what;
    EXPECT_EQ(fr.moves.front().point, f.moves.front().point) << what;
    EXPECT_NEAR(fr.max_distance, f.max_distance, 1e-5 * f.size) << what;
    const Vec3 want = R(f.moves.front().to - f.moves.front().from);
    EXPECT_LT(glm::length(fr.moves.front().to - fr.moves.front().from - want), 1e-5 * f.size) << what;
  }
}

/// Spline s as piecewise cubic Beziers (knots of multiplicity 3: its joints
/// are C0 by their knots, G1 and G2 geometrically).
SpaceSpline bezier_form(const SpaceSpline& s, std::vector<double>& knots) {
  std::vector<Vec3> pts;
  knots.clear();
  for (const Segment& seg : s.segments()) {
    const std::vector<Vec3> b = bezier_points(s, seg);
    for (std::size_t i = pts.empty() ? 0 : 1; i < b.size(); ++i) pts.push_back(b[i]);
    for (int i = 0; i < 3; ++i) knots.push_back(seg.a);
  }
  for (int i = 0; i < 3; ++i) knots.push_back(s.segments().back().b);
  return SpaceSpline::make(3, knots, pts);
}

TEST(SpaceFix, KeepG1SlidesAHandleAlongItsTangent) {
  // The monotone lifted Fig. 8b in Bezier form, with handle B4 slid along its
  // tangent line towards node B3 (G1 kept): segment 1 or joint 1 fails.
  const SpaceSpline monotone_curve = SpaceSpline::make(
      3, {0, 1, 2, 3, 4, 5, 6, 7},
      {{1.3, -1.43, 0}, {1.05, -0.06, 0.3}, {2.15, -1.31, 0.8}, {1.2, -4.03, 1.5}, {-2.23, -6.95, 2.4},
       {-6.78, -9.78, 3.5}});
  std::vector<double> knots;
  const SpaceSpline b = bezier_form(monotone_curve, knots);
  // Its joints are G2 (on the boundary of the jump's sign); lengthening the
  // legs right of them makes them G1 with clear downward jumps.
  std::vector<Vec3> pts = b.points();
  pts[4] = pts[3] + kLengthen * (pts[4] - pts[3]);
  pts[7] = pts[6] + kLengthen * (pts[7] - pts[6]);
  {
    const SpaceAnalysis a0 = analyze_space(SpaceSpline::make(3, knots, pts));
    ASSERT_TRUE(monotone(a0)) << "the G1 Bezier form is " << to_string(a0.curvature);
    ASSERT_EQ(a0.joints[0].jump, -1);
  }
  pts[4] = pts[3] + kSlide * (pts[4] - pts[3]);
  const SpaceSpline bz = SpaceSpline::make(3, knots, pts);
  const SpaceAnalysis in = analyze_space(bz);
  ASSERT_FALSE(monotone(in));
  ASSERT_EQ(in.joints.size(), 2u);
  for (const SpaceJoint& j : in.joints) ASSERT_TRUE(j.continuity == 0 && j.g1) << j.index;
  SpaceFixRequest req;
  req.keep = Keep::g1;
  const SpaceFixResult f = space_fix(bz, req);
  EXPECT_EQ(f.tie_joints, (std::vector<int>{1, 2}));
  ASSERT_TRUE(f.fixed) << f.reason;
  EXPECT_TRUE(f.ties_hold);
  const int k = f.moves.front().point;
  std::vector<Vec3> moved = pts;
  moved[static_cast<std::size_t>(k)] = f.moves.front().to;
  const SpaceAnalysis a = analyze_space(SpaceSpline::make(3, knots, moved));
  EXPECT_TRUE(monotone(a)) << to_string(a.curvature);
  for (const SpaceJoint& j : a.joints) EXPECT_TRUE(j.g1) << "joint " << j.index << " lost G1 (P" << k << ")";
  // The moved handle stayed on its tangent line (k is a handle of node 3 or 6).
  const int node = k == 2 || k == 4 ? 3 : 6;
  ASSERT_TRUE(k == 2 || k == 4 || k == 5 || k == 7) << "P" << k << " is not a handle";
  const Vec3 t0 = glm::normalize(pts[static_cast<std::size_t>(k)] - pts[static_cast<std::size_t>(node)]);
  const Vec3 t1 = glm::normalize(moved[static_cast<std::size_t>(k)] - moved[static_cast<std::size_t>(node)]);
  EXPECT_LT(glm::length(t1 - t0), 1e-12) << "P" << k;
  // The nodes are named as not moving.
  for (const SpaceUnitFix& u : f.units)
    if (u.point == 3 || u.point == 6) {
      EXPECT_NE(u.reason.find("the node of a G1 joint"), std::string::npos) << u.point;
    }
}

TEST(SpaceFix, NoFixWithinMaxMoveNamesTheFailingSegments) {
  SpaceFixRequest req;
  req.max_move = 1e-3;
  const SpaceFixResult f = space_fix(lifted(), req);
  EXPECT_FALSE(f.fixed);
  EXPECT_TRUE(f.moves.empty());
  EXPECT_FALSE(f.spline.has_value());
  EXPECT_NE(plain_fields(f.reason).find("no certified fix within max_move 0.001 (failing segments: 0, 1"),
            std::string::npos)
      << f.reason;
  EXPECT_EQ(f.reason.find('\n'), std::string::npos);
}

TEST(SpaceFix, BadRequestsAreInputErrors) {
  SpaceFixRequest req;
  req.points = {9};
  EXPECT_THROW(space_fix(lifted(), req), InputError);
  req.points = {5};  // an end point of the last segment, which is monotone: acts on no failing segment
  try {
    space_fix(lifted(), req);
    ADD_FAILURE() << "P5 accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "points: P5 does not act on a failing segment (failing segments: 0, 1)");
  }
  req = {};
  req.plane_text = "0,0,0,1,0,0,2,0,0";
  EXPECT_THROW(space_fix(lifted(), req), InputError);
  req = {};
  req.max_move = -1;
  EXPECT_THROW(space_fix(lifted(), req), InputError);
  req = {};
  req.max_depth = kMaxDepth + 1;
  EXPECT_THROW(space_fix(lifted(), req), InputError);
}

}  // namespace
}  // namespace cmr
