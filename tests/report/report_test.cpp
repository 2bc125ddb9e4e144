// cmr report: certified extrema and inflections against exact values derived
// independently (symmetry, exact de Casteljau halving, closed forms), the
// curve-level events against dense sampling, the batch and gate behaviour of
// the command, and the HTML page as headless Chromium renders it.
#include "report/report.hpp"
#include "report/extremum.hpp"

#include <cairo.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "numeric/fast_path.hpp"
#include "bezierize/lambda.hpp"
#include "region/region.hpp"
#include "spline/curvature.hpp"
#include "spline/spline_json.hpp"
#include "io/output.hpp"
#include "tests/test_util.hpp"
#include "report/batch.hpp"
#include "tests/cli_util.hpp"

namespace cmr::report {
namespace {

using Json = nlohmann::json;
namespace fs = std::filesystem;

// A curve symmetric about the y axis: kappa(t) = kappa(1-t), so lambda is odd
// about t = 1/2 and vanishes there exactly.
std::vector<Vec2> arch(double a) { return {{-1, 0}, {-a, 1}, {a, 1}, {1, 0}}; }

ReportOptions no_regions() {
  ReportOptions o;
  o.regions = false;
  return o;
}

bool contains(const SpanRoot& r, const Rational& x) { return Rational(r.t_lo) <= x && x <= Rational(r.t_hi); }

const char* kind_of(const SpanRoot& r) {
  return r.sign_before == r.sign_after ? "touch" : (r.sign_before > 0 ? "maximum" : "minimum");
}

TEST(ReportRoots, SymmetricArchHasItsExtremumExactlyAtOneHalf) {
  const SplineReport r = report_spline(BSpline::bezier(arch(0.5)), no_regions());
  ASSERT_EQ(r.spans[0].extrema.size(), 1u);
  const SpanRoot& x = r.spans[0].extrema[0];
  EXPECT_TRUE(x.exact);
  EXPECT_EQ(x.t, 0.5);
  EXPECT_EQ(x.at, SpanRoot::At::interior);
  // Clockwise arch: kappa < 0, most negative in the middle (sampled independently).
  EXPECT_LT(curvature(*r.spline, 0.5), curvature(*r.spline, 0.45));
  EXPECT_LT(curvature(*r.spline, 0.5), curvature(*r.spline, 0.55));
  EXPECT_STREQ(kind_of(x), "minimum");
  ASSERT_EQ(r.extrema.size(), 1u);
  EXPECT_EQ(r.extrema[0].t, 0.5);
  EXPECT_EQ(r.extrema[0].kind, -1);
  EXPECT_EQ(r.extrema[0].segment, 0);
  EXPECT_EQ(r.monotone_pieces, 2);
  EXPECT_EQ(r.kappa_min, x.kappa);
  EXPECT_TRUE(r.inflections.empty());
}

// Rational conics against closed forms. Quarter ellipse x^2/9 + y^2/4 = 1
// from (3, 0) to (0, 2): kappa falls from a/b^2 = 3/4 to b/a^2 = 2/9, with
// lambda = 0 exactly at both vertices (the ends).
TEST(ReportRoots, RationalQuarterEllipseHasItsVertexCurvaturesAtTheEnds) {
  const SplineReport r = report_spline(BSpline::bezier({{3, 0}, {3, 2}, {0, 2}}, "ellipse", {2, 1, 1}), no_regions());
  EXPECT_NEAR(r.kappa_max, 0.75, 1e-15);
  EXPECT_EQ(r.t_max, 0.0);
  EXPECT_NEAR(r.kappa_min, 2.0 / 9, 1e-15);
  EXPECT_EQ(r.t_min, 1.0);
  EXPECT_TRUE(r.extrema.empty());
  EXPECT_EQ(r.monotone_pieces, 1);
  ASSERT_EQ(r.spans[0].extrema.size(), 2u);  // the roots of lambda at the ends, exactly
  EXPECT_EQ(r.spans[0].extrema[0].at, SpanRoot::At::start);
  EXPECT_EQ(r.spans[0].extrema[1].at, SpanRoot::At::end);
  ASSERT_EQ(r.spans[0].homogeneous.size(), 3u);  // (w x, w y, w) of the Bezier points
  EXPECT_EQ(r.spans[0].homogeneous[0], glm::dvec3(6, 0, 2));
  EXPECT_EQ(r.spans[0].homogeneous[2], glm::dvec3(0, 2, 1));
}

// The hyperbola x y = 25 between (2.5, 10) and (10, 2.5), symmetric about
// y = x: its curvature 2xy / (x^2 + y^2)^(3/2) peaks at the vertex (5, 5),
// t = 1/2 exactly, with kappa = 1/sqrt(50).
TEST(ReportRoots, RationalHyperbolaPeaksExactlyAtItsVertex) {
  const SplineReport r =
      report_spline(BSpline::bezier({{2.5, 10}, {4, 4}, {10, 2.5}}, "hyperbola", {1, 1.25, 1}), no_regions());
  ASSERT_EQ(r.extrema.size(), 1u);
  EXPECT_EQ(r.extrema[0].t, 0.5);
  EXPECT_EQ(r.extrema[0].kind, 1);
  EXPECT_NEAR(r.extrema[0].kappa, 1 / std::sqrt(50.0), 1e-15);
  ASSERT_EQ(r.spans[0].extrema.size(), 1u);
  EXPECT_TRUE(r.spans[0].extrema[0].exact);
  EXPECT_NEAR(r.kappa_max, 1 / std::sqrt(50.0), 1e-15);
  EXPECT_EQ(r.monotone_pieces, 2);
}

TEST(ReportRoots, LeftHalfOfTheArchHasItsStationaryPointExactlyAtTheEnd) {
  // Exact de Casteljau at 1/2 (every value is a short dyadic): the left half
  // ends where the arch has its extremum.
  const std::vector<Vec2> P = arch(0.5);
  const Vec2 p01 = 0.5 * (P[0] + P[1]), p12 = 0.5 * (P[1] + P[2]), p23 = 0.5 * (P[2] + P[3]);
  const Vec2 p012 = 0.5 * (p01 + p12), p123 = 0.5 * (p12 + p23);
  const SplineReport r = report_spline(BSpline::bezier({P[0], p01, p012, 0.5 * (p012 + p123)}), no_regions());
  ASSERT_EQ(r.spans[0].extrema.size(), 1u);
  const SpanRoot& x = r.spans[0].extrema[0];
  EXPECT_TRUE(x.exact);
  EXPECT_EQ(x.t, 1.0);
  EXPECT_EQ(x.at, SpanRoot::At::end);
  EXPECT_STREQ(kind_of(x), "minimum");  // of the segment's polynomial, which goes on past the end
  // On the curve itself the curvature only falls: one monotone piece, no extremum.
  EXPECT_TRUE(r.extrema.empty());
  EXPECT_EQ(r.monotone_pieces, 1);
}

TEST(ReportRoots, ExtremumOnAJointIsReportedThere) {
  // The arch as a B-spline whose joint t = 1 is the arch's middle (dyadic
  // blossom arguments: the spline is exactly the arch).
  const BSpline s = test::polynomial_as_bspline(BSpline::bezier(arch(0.5)), {0, 0, 0, 1, 2, 2, 2});
  const SplineReport r = report_spline(s, no_regions());
  ASSERT_EQ(r.spans.size(), 2u);
  ASSERT_EQ(r.spans[0].extrema.size(), 1u);
  ASSERT_EQ(r.spans[1].extrema.size(), 1u);
  EXPECT_EQ(r.spans[0].extrema[0].at, SpanRoot::At::end);
  EXPECT_EQ(r.spans[1].extrema[0].at, SpanRoot::At::start);
  ASSERT_EQ(r.extrema.size(), 1u);
  EXPECT_EQ(r.extrema[0].t, 1.0);
  EXPECT_EQ(r.extrema[0].joint, 1);
  EXPECT_EQ(r.extrema[0].segment, -1);
  EXPECT_EQ(r.extrema[0].kind, -1);
  ASSERT_EQ(r.joints.size(), 1u);
  EXPECT_EQ(r.joints[0].continuity, "C2");
}

TEST(ReportRoots, QuadraticExtremumAtTheVertexOneFifth) {
  // P(t) = (0,0), (1,1), (3,0): |P'|^2 is least at t = a.(a-b)/|a-b|^2 = 1/5
  // (a = P1-P0, b = P2-P1), where a parabola's |kappa| peaks.
  const SplineReport r = report_spline(BSpline::bezier({{0, 0}, {1, 1}, {3, 0}}), no_regions());
  ASSERT_EQ(r.spans[0].extrema.size(), 1u);
  const SpanRoot& x = r.spans[0].extrema[0];
  EXPECT_FALSE(x.exact);
  EXPECT_TRUE(contains(x, Rational(1, 5))) << x.t_lo << " " << x.t_hi;
  EXPECT_LE(x.t_hi - x.t_lo, 1e-12);
  EXPECT_NEAR(x.t, 0.2, 1e-12);
  EXPECT_STREQ(kind_of(x), "minimum");  // clockwise: kappa < 0
}

TEST(ReportRoots, InflectionAtFourThirdsInASplineParameter) {
  // (3t, 3t^3 - 3t^2): eta = 3 * (18t - 6), zero at t = 1/3. Written over the
  // knots 0,0,0,1,2,4,4,4 (dyadic blossom arguments, so exactly the same
  // curve), t = 1/3 of the domain [0, 4] is 4/3, inside segment 1 = [1, 2].
  const BSpline cubic = BSpline::bezier({{0, 0}, {1, 0}, {2, -1}, {3, 0}});
  const SplineReport r = report_spline(test::polynomial_as_bspline(cubic, {0, 0, 0, 1, 2, 4, 4, 4}), no_regions());
  ASSERT_EQ(r.spans.size(), 3u);
  EXPECT_TRUE(r.spans[0].inflections.empty());
  EXPECT_TRUE(r.spans[2].inflections.empty());
  ASSERT_EQ(r.spans[1].inflections.size(), 1u);
  const SpanRoot& x = r.spans[1].inflections[0];
  EXPECT_TRUE(contains(x, Rational(4, 3)));
  EXPECT_LE(x.t_hi - x.t_lo, 1e-12 * 1.0 + 4e-16);  // tolerance times the segment length, plus outward rounding
  EXPECT_NE(x.sign_before, x.sign_after);
  ASSERT_EQ(r.inflections.size(), 1u);
  EXPECT_EQ(r.inflections[0].segment, 1);
  EXPECT_EQ(r.inflections[0].kind, 1);  // concave down, then up
}

// The symmetric arch family changes, near a = 0.64, from one extremum at
// t = 1/2 to three (lambda'(1/2) crosses zero). Just past that point the
// outer two lie 2x apart with x ~ 3e-7.
TEST(ReportRoots, ExtremaCloserThanOneMillionthAreAllFound) {
  auto slope = [](double a) {  // lambda'(1/2), in double: only to aim
    return bernstein_eval(bernstein_derivative(lambda_bernstein<double>(arch(a))), 0.5);
  };
  double lo = 0.6, hi = 0.7;
  ASSERT_GT(slope(lo), 0);
  ASSERT_LT(slope(hi), 0);
  for (int i = 0; i < 100; ++i) (slope(0.5 * (lo + hi)) > 0 ? lo : hi) = 0.5 * (lo + hi);
  const double a0 = lo;
  // lambda(1/2 + y) ~ c1 y + c3 y^3 with c1 ~ slope'(a0) (a - a0): roots at y = +-x when c1 = -c3 x^2.
  const double c3 =
      bernstein_eval(
          bernstein_derivative(bernstein_derivative(bernstein_derivative(lambda_bernstein<double>(arch(a0))))), 0.5) /
      6;
  const double dslope = (slope(a0 + 1e-6) - slope(a0 - 1e-6)) / 2e-6;
  const double x = 3e-7;
  const double a = a0 - c3 * x * x / dslope;

  // Independent proof that lambda has three sign changes within 1/2 +- 2x:
  // exact evaluation of its Bernstein form at four rational points.
  std::vector<Point<Rational>> P;
  for (const Vec2& p : arch(a)) P.push_back(to_point<Rational>(p));
  const Bernstein<Rational> xi = lambda_bernstein<Rational>(P);
  const int s = c3 > 0 ? 1 : -1;
  const double ys[] = {-2 * x, -0.5 * x, 0.5 * x, 2 * x};
  const int expected[] = {-s, s, -s, s};
  for (int i = 0; i < 4; ++i)
    ASSERT_EQ(sgn(bernstein_eval(xi, Rational(Rational(0.5) + Rational(ys[i])))), expected[i]) << "y = " << ys[i];

  const SplineReport r = report_spline(BSpline::bezier(arch(a)), no_regions());
  std::vector<SpanRoot> close;
  for (const SpanRoot& e : r.spans[0].extrema)
    if (std::fabs(e.t - 0.5) < 1e-6) close.push_back(e);
  ASSERT_EQ(close.size(), 3u);
  EXPECT_LT(close[2].t - close[0].t, 1e-6);
  EXPECT_TRUE(close[1].exact);
  EXPECT_EQ(close[1].t, 0.5);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(close[i].sign_before != close[i].sign_after) << "root " << i;
  EXPECT_EQ(r.extrema.size(), 3u);
  EXPECT_EQ(r.monotone_pieces, 4);
}

// Curve-level events against dense sampling of the curvature (an evaluator
// independent of the Bernstein machinery): between consecutive extrema the
// sampled curvature moves in the direction the events say, and at each
// inflection it changes sign. Seeded random splines with joints of every
// multiplicity, so that jumps and corners occur.
TEST(ReportEvents, AgreeWithSampledCurvature) {
  std::mt19937_64 rng(7);
  const std::vector<std::vector<double>> knot_sets = {{0, 1, 2, 3, 4, 5, 6, 7, 8},
                                                      {0, 0, 0, 1, 1, 2, 3, 3, 3},
                                                      {0, 0, 0, 1, 1, 1, 2, 2, 2},
                                                      {0, 0.5, 1, 1, 3, 4, 4.5, 6, 7}};
  for (int trial = 0; trial < 40; ++trial) {
    const std::vector<double>& knots = knot_sets[trial % knot_sets.size()];
    const BSpline s = BSpline::make(3, knots, test::random_points(rng, static_cast<int>(knots.size()) - 2));
    const SplineReport r = report_spline(s, no_regions());
    SCOPED_TRACE("trial " + std::to_string(trial));
    ASSERT_EQ(r.monotone_pieces, static_cast<int>(r.extrema.size()) + 1);
    // Boundaries of the monotone pieces, with the direction on each.
    std::vector<double> cuts{s.domain_begin()};
    for (const CurveEvent& e : r.extrema) cuts.push_back(e.t);
    cuts.push_back(s.domain_end());
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
      const double a = cuts[k], b = cuts[k + 1];
      if (b - a < 1e-3) continue;  // too short to sample
      const int dir = k < r.extrema.size() ? r.extrema[k].kind : -r.extrema.back().kind;
      double prev = std::numeric_limits<double>::quiet_NaN();
      for (int i = 1; i < 200; ++i) {
        const double t = a + (b - a) * i / 200;
        if (s.multiplicity(t) > 0) continue;  // a knot: curvature may jump, and the jump is an event itself
        const double kappa = curvature(s, t);
        if (std::isfinite(prev) && std::isfinite(kappa)) {
          const double slack = 1e-9 * (std::fabs(kappa) + std::fabs(prev));
          EXPECT_GE(dir * (kappa - prev), -slack) << "piece " << k << " [" << a << ", " << b << "] t = " << t;
        }
        prev = kappa;
      }
    }
    for (const CurveEvent& e : r.inflections) {
      const double h = 1e-7;
      if (e.joint >= 0) continue;  // at a joint the sign test needs the one-sided curvatures
      if (e.t - h <= s.domain_begin() || e.t + h >= s.domain_end()) continue;
      EXPECT_LE(curvature(s, e.t - h) * e.kind, 0) << "inflection at " << e.t;
      EXPECT_GE(curvature(s, e.t + h) * e.kind, 0) << "inflection at " << e.t;
    }
  }
}

TEST(ReportJoints, ContinuityFromKnotsAndTangents) {
  // Knot 1 has multiplicity 3: C0 by the knots. P3 = f(1,1,1) is the joint,
  // P2 = f(0,1,1) and P4 = f(1,1,2) give the end tangents there.
  const std::vector<double> knots{0, 0, 0, 1, 1, 1, 2, 2, 2};
  const std::vector<Vec2> straight{{0, 0}, {1, 1}, {2, 1}, {3, 1}, {4, 1}, {5, 0}, {6, 1}};
  const SplineReport g1 = report_spline(BSpline::make(3, knots, straight), no_regions());
  ASSERT_EQ(g1.joints.size(), 1u);
  EXPECT_EQ(g1.joints[0].continuity, "C0");  // from the knots; G1 is reported apart
  EXPECT_TRUE(g1.joints[0].joint.g1);
  EXPECT_FALSE(g1.joints[0].corner);
  std::vector<Vec2> bent = straight;
  bent[4] = {4, 2};
  const SplineReport c0 = report_spline(BSpline::make(3, knots, bent), no_regions());
  EXPECT_EQ(c0.joints[0].continuity, "C0");
  EXPECT_FALSE(c0.joints[0].joint.g1);
  EXPECT_TRUE(c0.joints[0].corner);
  const SplineReport c1 = report_spline(
      BSpline::make(3, {0, 0, 0, 1, 1, 2, 2, 2}, {{0, 0}, {1, 1}, {2, 1}, {3, 0}, {4, 0}, {5, 1}}), no_regions());
  EXPECT_EQ(c1.joints[0].continuity, "C1");
}

TEST(ReportRequirement, ParsesTheThreeForms) {
  EXPECT_EQ(parse_requirement("cmrwi").mode, Mode::cmrwi);
  EXPECT_EQ(parse_requirement("cmr").mode, Mode::cmr);
  EXPECT_EQ(parse_requirement("split:2").split, 2);
  EXPECT_THROW(parse_requirement("split:"), InputError);
  EXPECT_THROW(parse_requirement("split:x"), InputError);
  EXPECT_THROW(parse_requirement("monotone"), InputError);
}

// A monotone class A cubic with P2 pulled off: moving P2 back fixes it, so
// its region is not empty (about 1.6% of the default view).
BSpline spiral() { return test::class_a_bezier(3, -0.5, 1.5); }
BSpline pulled_spiral() {
  const BSpline s = spiral();
  return s.with_point(2, s.points()[2] + Vec2(0.0, 0.3));
}

TEST(ReportRequirement, ParsesTheExtremumAtASplit) {
  EXPECT_EQ(parse_requirement("split:2").extremum, Extremum::any);
  EXPECT_EQ(parse_requirement("split:2:sharpest").extremum, Extremum::sharpest);
  EXPECT_EQ(parse_requirement("split:3:flattest").extremum, Extremum::flattest);
  EXPECT_EQ(parse_requirement("split:3:flattest").split, 3);
  for (const char* t : {"split:2", "split:2:sharpest", "split:2:flattest", "cmr", "cmrwi"})
    EXPECT_EQ(to_string(parse_requirement(t)), t);
  for (const char* bad : {"split:2:mid", "split::sharpest", "split:sharpest", "split:2:sharpest:flattest", "split:2sharpest",
                          "split:2:max", "split:2:min"})
    EXPECT_THROW(parse_requirement(bad), InputError) << bad;
  // The signed names are refused with the hint to the |kappa| ones.
  try {
    parse_requirement("split:2:max");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("use split:2:sharpest or :flattest"), std::string::npos) << e.what();
  }
}

// split:S means a curvature extremum at joint S: a curve monotone across S
// fails it (it used to pass), a minimum passes split:S and split:S:min, a
// maximum split:S and split:S:max. The curves are one cubic each written on
// knots 0,0,0,1,2,2,2 (joint 1 at the middle): a spiral (monotone), the
// clockwise arch (kappa < 0, most negative in the middle: a minimum) and the
// mirrored arch (counter-clockwise: a maximum).
TEST(ReportRequirement, SplitMeansAnExtremumAtTheJoint) {
  const std::vector<double> knots{0, 0, 0, 1, 2, 2, 2};
  std::vector<Vec2> up = arch(0.5);
  for (Vec2& p : up) p.y = -p.y;
  struct Case {
    const char* name;
    BSpline spline;
    const char* require;
    bool pass;
  };
  const Case cases[] = {
      {"spiral", test::polynomial_as_bspline(spiral(), knots), "split:1", false},
      {"spiral", test::polynomial_as_bspline(spiral(), knots), "split:1:sharpest", false},
      {"spiral", test::polynomial_as_bspline(spiral(), knots), "split:1:flattest", false},
      // Both arches are sharpest in the middle: mirroring flips the signed
      // extremum, not the |kappa| one.
      {"minimum", test::polynomial_as_bspline(BSpline::bezier(arch(0.5)), knots), "split:1", true},
      {"minimum", test::polynomial_as_bspline(BSpline::bezier(arch(0.5)), knots), "split:1:sharpest", true},
      {"minimum", test::polynomial_as_bspline(BSpline::bezier(arch(0.5)), knots), "split:1:flattest", false},
      {"maximum", test::polynomial_as_bspline(BSpline::bezier(up), knots), "split:1", true},
      {"maximum", test::polynomial_as_bspline(BSpline::bezier(up), knots), "split:1:sharpest", true},
      {"maximum", test::polynomial_as_bspline(BSpline::bezier(up), knots), "split:1:flattest", false},
  };
  for (const Case& c : cases) {
    ReportOptions o = no_regions();
    o.require = parse_requirement(c.require);
    const SplineReport r = report_spline(c.spline, o);
    EXPECT_EQ(r.pass, c.pass) << c.name << " " << c.require << ": split verdict " << to_string(*r.analysis.split);
    // The certified extrema of the report say the same: one extremum, on joint 1, of the named kind.
    const bool extremum_on_joint = r.extrema.size() == 1 && r.extrema[0].joint == 1;
    if (std::string(c.name) != "spiral") {
      EXPECT_TRUE(extremum_on_joint) << c.name;
      EXPECT_EQ(r.extrema[0].kind, std::string(c.name) == "maximum" ? 1 : -1) << c.name;
      EXPECT_EQ(event_kind(r, r.extrema[0]), ExtremumKind::sharpest) << c.name;
    } else {
      EXPECT_TRUE(r.extrema.empty()) << c.name;
    }
  }
}

// The fix search looks for the extremum the gate asks for: every example it
// offers passes the gate when verified with analyze.
TEST(ReportRequirement, FixesOfASplitGateHaveTheRequiredExtremum) {
  const BSpline s = test::polynomial_as_bspline(spiral(), {0, 0, 0, 1, 2, 2, 2});
  for (const char* gate : {"split:1:sharpest", "split:1:flattest"}) {
    ReportOptions o;
    o.require = parse_requirement(gate);
    o.region_size = 48;
    o.backend = std::make_shared<CpuRegionBackend>(1);
    SplineReport r = report_spline(s, o);
    ASSERT_FALSE(r.pass) << gate;
    find_fixes(r, o);
    int found = 0;
    for (const Fix& f : *r.fixes) {
      if (!f.example) continue;
      ++found;
      EXPECT_TRUE(f.verified) << gate << " point " << f.point;
      const SplineAnalysis a = analyze(s.with_point(f.point, *f.example), [&] {
        AnalyzeOptions ao;
        ao.split = 1;
        return ao;
      }());
      EXPECT_TRUE(split_passes(*a.split, o.require->extremum, a.joints[0])) << gate << " point " << f.point;
    }
    EXPECT_GT(found, 0) << gate;
  }
}

// Issue 36: for split:3:flattest on docs/analyze.md's wave (segments 2..3,
// where the joint is sharpest) the report credited points with pixels whose
// extremum at the joint is the sharpest one, and points that act on no
// judged segment (P0: all 9,216 pixels) with the whole view. Every count is
// now the gate's own region: held here to exact re-judging, pixel by
// pixel (the exact-only path, ExactOnlyScope), and every example passes.
/// Finds the region fixes of `spline` under `gate` and holds every count to
/// exact re-judging, pixel by pixel (the exact-only path, ExactOnlyScope):
/// the pixels where moving the point there passes the gate. Returns the
/// report's fixes.
std::vector<Fix> fixes_held_to_exact_rejudging(const BSpline& spline, const std::string& gate,
                                               std::optional<SegmentRange> segments) {
  ReportOptions o;
  o.require = parse_requirement(gate);
  o.segments = segments;
  o.region_size = 24;
  o.backend = std::make_shared<CpuRegionBackend>(1);
  SplineReport r = report_spline(spline, o);
  EXPECT_FALSE(r.pass) << gate;
  find_fixes(r, o);
  if (!r.fixes) {
    ADD_FAILURE() << gate << ": no fixes";
    return {};
  }
  const int S = *o.require->split;
  AnalyzeOptions ao;
  ao.split = S;
  ao.split_mode = Mode::cmrwi;
  ao.segments = o.segments;
  ao.continuity = o.continuity;
  ao.classify.max_depth = o.max_depth;
  const auto passes_exactly = [&](const BSpline& s) {
    ExactOnlyScope exact;
    const SplineAnalysis a = analyze(s, ao);
    return a.split && split_passes(*a.split, o.require->extremum, a.joints[S - 1]);
  };
  EXPECT_FALSE(passes_exactly(spline)) << gate;
  for (const Fix& f : *r.fixes) {
    RegionRequest ro;
    ro.point = f.point;
    ro.mode = Mode::cmrwi;
    ro.split = S;
    ro.segments = o.segments;
    ro.max_depth = o.max_depth;
    ro.width = ro.height = o.region_size;
    const RegionResult image = o.backend->render(RegionProblem::make(spline, ro));
    std::uint64_t exact = 0;
    for (int j = 0; j < image.height; ++j)
      for (int i = 0; i < image.width; ++i)
        exact += passes_exactly(spline.with_point(f.point, pixel_center(image.view, image.width, image.height, i, j))) ? 1 : 0;
    EXPECT_EQ(f.pixels, exact) << gate << " P" << f.point;
    EXPECT_EQ(f.example.has_value(), f.pixels > 0) << gate << " P" << f.point;
    if (f.example) {
      EXPECT_TRUE(f.verified) << gate << " P" << f.point;
      EXPECT_TRUE(passes_exactly(spline.with_point(f.point, *f.example))) << gate << " P" << f.point;
    }
  }
  return *r.fixes;
}

// Issue 36: for split:3:flattest on docs/analyze.md's wave (segments 2..3,
// where the joint is the sharpest point) the report credited 7 points with
// pixels whose extremum at the joint is the sharpest one, P0 (which acts on
// no judged segment) with all 9,216, and none with an example. Every count
// is now the gate's own region, held to exact re-judging pixel by pixel; on
// the wave no single point makes the joint the flattest in the view. On a
// spiral both kinds are reachable, and every counted pixel passes too.
TEST(ReportFixes, SplitFlattestCountsOnlyTheGatesOwnRegionHeldToExactRejudging) {
  const BSpline wave = read_spline_file(std::string(CMR_SOURCE_DIR) + "/examples/wave.json");
  const std::vector<Fix> w = fixes_held_to_exact_rejudging(wave, "split:3:flattest", SegmentRange{2, 3});
  ASSERT_EQ(w.size(), 7u);
  EXPECT_EQ(w[0].pixels, 0u);  // P0 and P1 act on no judged segment (segment 2 is P2..P5)
  EXPECT_EQ(w[1].pixels, 0u);
  const BSpline spiral_curve = test::polynomial_as_bspline(spiral(), {0, 0, 0, 1, 2, 2, 2});
  for (const char* gate : {"split:1:sharpest", "split:1:flattest"}) {
    std::uint64_t claimed = 0;
    for (const Fix& f : fixes_held_to_exact_rejudging(spiral_curve, gate, std::nullopt)) claimed += f.pixels;
    EXPECT_GT(claimed, 0u) << gate << ": no point has a region: the check proves nothing";
  }
}

// The same through the command: report.json's entries and the page agree.
TEST(ReportFixes, SplitFlattestJsonAndPageAgree) {
  const fs::path out = test::scratch() / "wave_flattest";
  fs::remove_all(out);
  const test::Outcome r = test::run("report " + std::string(CMR_SOURCE_DIR) +
                                    "/examples/wave.json --require split:3:flattest --segments 2..3 --backend cpu "
                                    "--region-size 32 --out " + out.string());
  ASSERT_EQ(r.code, 1) << r.err;
  const Json doc = Json::parse(test::slurp(out / "report.json"));
  const Json& fixes = doc["splines"][0]["fixes"];
  int with_region = 0;
  for (const Json& f : fixes) {
    const bool region = f["region_pixels"].get<std::uint64_t>() > 0;
    EXPECT_EQ(!f["example"].is_null(), region) << f.dump();
    if (region) {
      EXPECT_TRUE(f["verified"].get<bool>()) << f.dump();
    }
    with_region += region ? 1 : 0;
  }
  EXPECT_EQ(fixes[0]["region_pixels"], 0);
  const std::string page = test::slurp(out / "index.html");
  std::size_t shown = 0;
  for (std::size_t at = page.find("<figcaption>move P"); at != std::string::npos;
       at = page.find("<figcaption>move P", at + 1))
    ++shown;
  EXPECT_EQ(shown, static_cast<std::size_t>(with_region));
  EXPECT_EQ(page.find("No single control point has a region") == std::string::npos, with_region > 0);
}

/// The fill colours of the extremum marks (radius 4.5) of a page, in order.
std::vector<std::string> extremum_colours(const std::string& html) {
  std::vector<std::string> out;
  const std::string mark = "r=\"4.5\" fill=\"";
  for (std::size_t at = html.find(mark); at != std::string::npos; at = html.find(mark, at + 1))
    out.push_back(html.substr(at + mark.size(), 7));
  return out;
}

// Issue 36: the legend said "maxima red, minima blue" (signed kappa) beside
// messages that say "sharpest" and "flattest" (|kappa|). The marks are now
// coloured by |kappa|, so a mirrored curve (kappa negated: signed maxima
// become minima) keeps every colour, and the caption says so.
TEST(ReportPage, ExtremaAreColouredByAbsoluteCurvatureLikeTheMessages) {
  const BSpline s = BSpline::make(3, {0, 0, 0, 1, 2, 2, 2}, {{0, 0}, {1, 1.5}, {2, -1}, {3, 1.2}, {4, 0}});
  std::vector<Vec2> mirrored_points;
  for (const Vec2& p : s.points()) mirrored_points.push_back(Vec2(-p.x, p.y));
  const BSpline m = BSpline::make(3, {0, 0, 0, 1, 2, 2, 2}, mirrored_points);
  ReportOptions o = no_regions();
  const std::string a = report_sections_html({report_spline(s, o)}, 0, o);
  const std::string b = report_sections_html({report_spline(m, o)}, 0, o);
  const std::vector<std::string> ca = extremum_colours(a), cb = extremum_colours(b);
  ASSERT_GE(ca.size(), 4u);  // two extrema, each on the curve and on the plot
  EXPECT_EQ(ca, cb);
  EXPECT_NE(std::find(ca.begin(), ca.end(), "#d00000"), ca.end());  // a sharpest point
  EXPECT_NE(a.find("sharpest points (largest |κ|) red, flattest (smallest |κ|) blue"), std::string::npos);
  EXPECT_EQ(a.find("maxima red"), std::string::npos);
  // The plot's marks (after the curve's) are red exactly where the messages say "sharpest".
  const SplineReport r = report_spline(s, o);
  ASSERT_LE(r.extrema.size(), ca.size());
  for (std::size_t i = 0; i < r.extrema.size(); ++i)
    EXPECT_EQ(ca[ca.size() - r.extrema.size() + i] == "#d00000", event_kind(r, r.extrema[i]) == ExtremumKind::sharpest)
        << "t = " << r.extrema[i].t;
}

TEST(ReportFixes, FindTheMovedPointAndVerifyTheExample) {
  ASSERT_TRUE(report_spline(spiral(), no_regions()).pass);
  ReportOptions o;
  o.backend = std::make_shared<CpuRegionBackend>();
  o.region_size = 64;
  SplineReport r = report_spline(pulled_spiral(), o);
  ASSERT_FALSE(r.pass);
  find_fixes(r, o);
  ASSERT_TRUE(r.fixes);
  ASSERT_EQ(r.fixes->size(), 4u);
  const Fix& f = (*r.fixes)[2];
  EXPECT_GT(f.pixels, 0u);
  ASSERT_TRUE(f.example);
  EXPECT_TRUE(f.verified);
  EXPECT_FALSE(f.thumbnail_png.empty());
  const Direction moved = analyze(r.spline->with_point(2, *f.example)).cmr;
  EXPECT_TRUE(moved == Direction::increasing || moved == Direction::decreasing) << to_string(moved);
  for (const Fix& g : *r.fixes) EXPECT_EQ(g.example.has_value(), g.pixels > 0) << "P" << g.point;
}

TEST(ReportFixes, ThumbnailsAreDrawnInMemoryWithoutTemporaryFiles) {
  // Earlier versions drew each thumbnail to a file in the temporary folder
  // and read it back; now nothing may appear there.
  const fs::path tmp = test::scratch() / "tmpdir";
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  const std::string saved = std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "";
  ::setenv("TMPDIR", tmp.c_str(), 1);
  ReportOptions o;
  o.backend = std::make_shared<CpuRegionBackend>();
  o.region_size = 32;
  std::vector<ReportInput> inputs(1);
  inputs[0].file = "pulled";
  inputs[0].spline = pulled_spiral();
  const std::vector<SplineReport> reports = report_batch(std::move(inputs), o);
  saved.empty() ? ::unsetenv("TMPDIR") : ::setenv("TMPDIR", saved.c_str(), 1);
  ASSERT_TRUE(reports[0].fixes);
  int thumbnails = 0;
  for (const Fix& f : *reports[0].fixes) {
    if (f.thumbnail_png.empty()) continue;
    ++thumbnails;
    EXPECT_EQ(f.thumbnail_png.substr(0, 4), "\x89PNG") << "P" << f.point;
  }
  EXPECT_GT(thumbnails, 0);
  EXPECT_TRUE(fs::is_empty(tmp)) << "a temporary file was left in " << tmp;
}


// ---------------------------------------------------------- semantics --
// README, "Semantics": the report states what analyze states.

// Cubic Bezier pieces joined at C0 knots (multiplicity 3).
BSpline bezier_chain(const std::vector<Vec2>& points) {
  std::vector<double> knots;
  const int pieces = (static_cast<int>(points.size()) - 1) / 3;
  for (int k = 0; k <= pieces; ++k) knots.insert(knots.end(), {double(k), double(k), double(k)});
  return BSpline::make(3, knots, points);
}

TEST(ReportSemantics, CuspHasNoFiniteCurvatureRange) {
  // P'(1/2) = 0 (x' = 6(1-2t)^2, y' = 6(1-2t)).
  const SplineReport r = report_spline(BSpline::bezier({{0, 0}, {2, 2}, {0, 2}, {2, 0}}), no_regions());
  EXPECT_TRUE(r.cusp);
  EXPECT_TRUE(r.spans[0].shape.cusp);
  EXPECT_TRUE(std::isnan(r.kappa_min));
  EXPECT_TRUE(std::isnan(r.kappa_max));
  const Json doc = Json::parse(report_json({r}, no_regions()).dump());
  const Json& sj = doc["splines"][0];
  EXPECT_EQ(sj["segments"][0]["class"], "cusp");
  EXPECT_EQ(sj["curvature"]["cusp"], true);
  EXPECT_TRUE(sj["curvature"]["min"]["kappa"].is_null());
  EXPECT_TRUE(sj["curvature"]["max"]["kappa"].is_null());
  EXPECT_NE(report_html({r}, no_regions()).find("no finite range"), std::string::npos);
}

TEST(ReportSemantics, LeavingAStraightWithZeroCurvatureIsNoInflection) {
  // Straight, then a cubic whose first three points continue it: eta = 0 at
  // the joint, > 0 inside. No inflection, CMR passes (the paper's Algorithm 2
  // alone would say "present").
  const SplineReport r =
      report_spline(bezier_chain({{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 0}, {5, 0}, {5.5, 0.5}}), no_regions());
  EXPECT_TRUE(r.inflections.empty());
  EXPECT_TRUE(r.pass);  // judged by CMR
  EXPECT_EQ(r.analysis.cmr_algorithm2, Direction::none);
  const Json doc = Json::parse(report_json({r}, no_regions()).dump());
  const Json& seg = doc["splines"][0]["segments"];
  EXPECT_EQ(seg[0]["class"], "straight");
  EXPECT_EQ(seg[0]["inflection"], "none");
  EXPECT_EQ(seg[0]["algorithm2"], "present");
  EXPECT_EQ(seg[1]["class"], "regular");
  EXPECT_EQ(seg[1]["inflection"], "none");
  EXPECT_EQ(seg[1]["zero_curvature_at"], "start");
  EXPECT_EQ(seg[1]["algorithm2"], "present");
  const Json& joint = doc["splines"][0]["joints"][0];
  EXPECT_EQ(joint["continuity"], "C0");
  EXPECT_EQ(joint["g1"], true);
  EXPECT_EQ(joint["g2"], true);
  EXPECT_EQ(doc["splines"][0]["verdict"]["cmr_algorithm2"], "none");
}

TEST(ReportSemantics, ExtremumCurvatureIsCertified) {
  // The symmetric arch's extremum is exactly t = 1/2. Independent value: the
  // pointwise double formula (spline/curvature.hpp), whose derivatives at
  // t = 1/2 are exact dyadic numbers for these points.
  const SplineReport r = report_spline(BSpline::bezier(arch(0.5)), no_regions());
  ASSERT_EQ(r.spans[0].extrema.size(), 1u);
  const double k = r.spans[0].extrema[0].kappa;
  const double want = curvature(*r.spline, 0.5);
  EXPECT_LE(std::fabs(k - want), 1e-14 * std::fabs(want));
  // The range ends are the certified joint/end curvatures.
  EXPECT_EQ(r.kappa_max, certified_end_curvature(*r.spline, r.spline->segments()[0], 0));
}

// ------------------------------------------------------------ the command --

std::string spline_file(const std::string& name, const BSpline& s) {
  const fs::path p = test::scratch() / name;
  write_spline_file(p, s);
  return p.string();
}

Json read_json(const fs::path& p) { return Json::parse(test::slurp(p)); }

TEST(ReportCommand, BadFilesAreReportedAndTheRestGoOn) {
  const std::string good = spline_file("good.json", spiral());
  const std::string bad = test::write("broken.json", "{\"points\": [[0,0],");
  const fs::path out = test::scratch() / "batch";
  fs::remove_all(out);
  const test::Outcome r = test::run("report " + good + " " + bad + " /nonexistent/x.json " + good + " --out " +
                                    out.string() + " --no-thumbnails --require cmr");
  EXPECT_EQ(r.code, 2) << r.err;
  const Json doc = read_json(out / "report.json");
  EXPECT_EQ(doc["schema"], "cmr-report/2");
  ASSERT_EQ(doc["splines"].size(), 4u);
  EXPECT_EQ(doc["splines"][0]["status"], "pass");
  EXPECT_EQ(doc["splines"][1]["status"], "invalid");
  EXPECT_NE(doc["splines"][1]["error"].get<std::string>().find("malformed JSON"), std::string::npos);
  EXPECT_EQ(doc["splines"][2]["status"], "invalid");
  EXPECT_EQ(doc["splines"][3]["status"], "pass");
  EXPECT_FALSE(doc["splines"][3]["segments"].empty());
  EXPECT_EQ(doc["summary"]["invalid"], 2);
  EXPECT_EQ(doc["summary"]["exit_code"], 2);
  const std::string html = test::slurp(out / "index.html");
  EXPECT_NE(html.find("broken.json"), std::string::npos);
  EXPECT_NE(html.find("id=\"s3\""), std::string::npos);
  EXPECT_NE(html.find("INVALID"), std::string::npos);
  // One line on stderr per bad file, naming it.
  EXPECT_NE(r.err.find("broken.json"), std::string::npos);
  EXPECT_NE(r.err.find("/nonexistent/x.json"), std::string::npos);
}

struct GateCase {
  const char* name;
  const char* require;  // empty: no gate
  bool pulled;          // the failing spline instead of the passing one
  int code;
};

void PrintTo(const GateCase& c, std::ostream* os) { *os << c.name; }

class ReportGate : public ::testing::TestWithParam<GateCase> {};

TEST_P(ReportGate, ExitCode) {
  const GateCase& c = GetParam();
  const std::string file = spline_file(std::string(c.name) + ".json", c.pulled ? pulled_spiral() : spiral());
  const fs::path out = test::scratch() / (std::string("gate_") + c.name);
  const std::string gate = *c.require ? std::string(" --require ") + c.require : "";
  const test::Outcome r = test::run("report " + file + " --out " + out.string() + " --no-thumbnails" + gate);
  EXPECT_EQ(r.code, c.code) << r.err;
  EXPECT_TRUE(fs::exists(out / "report.json"));
  EXPECT_TRUE(fs::exists(out / "index.html"));
}

INSTANTIATE_TEST_SUITE_P(Table, ReportGate,
                         ::testing::Values(GateCase{"pass_cmr", "cmr", false, 0},
                                           GateCase{"pass_cmrwi", "cmrwi", false, 0},
                                           GateCase{"fail_cmr", "cmr", true, 1},
                                           GateCase{"fail_cmrwi", "cmrwi", true, 1},
                                           GateCase{"fail_ungated", "", true, 0}),
                         [](const auto& p) { return std::string(p.param.name); });

TEST(ReportCommand, SplitGatePassesAnExtremumAtTheJoint) {
  const BSpline s = test::polynomial_as_bspline(BSpline::bezier(arch(0.5)), {0, 0, 0, 1, 2, 2, 2});
  const std::string file = spline_file("arch_split.json", s);
  const fs::path out = test::scratch() / "split";
  EXPECT_EQ(test::run("report " + file + " --out " + out.string() + " --no-thumbnails --require split:1").code, 0);
  EXPECT_EQ(read_json(out / "report.json")["splines"][0]["verdict"]["split"], "dec-inc");
  EXPECT_EQ(test::run("report " + file + " --out " + out.string() + " --no-thumbnails --require cmrwi").code, 1);
  const test::Outcome bad = test::run("report " + file + " --out " + out.string() + " --require split:5");
  EXPECT_EQ(bad.code, 2);  // the spline has no joint 5: that input is invalid
  EXPECT_NE(read_json(out / "report.json")["splines"][0]["error"].get<std::string>().find("split 5"),
            std::string::npos);
}

// --segments: only those spans judged (and gated); the others reported as ignored.
TEST(ReportCommand, SegmentsJudgeOnlyTheirSpans) {
  // Curvature increases on segments 0-1, decreases on 2, increases on 3.
  const BSpline wave = BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7, 8},
                                     {{0.058, 0.128}, {1.274, 0.936}, {2.065, -0.298}, {3.236, -0.998},
                                      {3.765, 0.132}, {5.069, -0.719}, {6.078, 0.783}});
  const std::string file = spline_file("wave.json", wave);
  const fs::path out = test::scratch() / "segments";
  const std::string base = "report " + file + " --out " + out.string() + " --no-thumbnails";
  EXPECT_EQ(test::run(base + " --require cmrwi").code, 1);
  EXPECT_EQ(test::run(base + " --require cmrwi --segments 0..1").code, 0);
  Json doc = read_json(out / "report.json");
  EXPECT_EQ(doc["settings"]["segments"], Json({0, 1}));
  const Json& sp = doc["splines"][0];
  EXPECT_EQ(sp["verdict"]["cmrwi"], "increasing");
  EXPECT_EQ(sp["verdict"]["segments"], Json({0, 1}));
  ASSERT_EQ(sp["segments"].size(), 4u);
  EXPECT_EQ(sp["segments"][1]["curvature"], "increasing");
  EXPECT_EQ(sp["segments"][2]["curvature"], "ignored");
  EXPECT_EQ(sp["segments"][3]["ignored"], true);
  EXPECT_NE(test::slurp(out / "index.html").find("ignored"), std::string::npos);
  // Decreasing, then increasing where kappa < 0: a signed minimum, the sharpest point.
  EXPECT_EQ(test::run(base + " --require split:3:sharpest --segments 2..3").code, 0);
  EXPECT_EQ(test::run(base + " --require split:3:flattest --segments 2..3").code, 1);
  EXPECT_EQ(test::run(base + " --require split:2:sharpest --segments 1..2").code, 0);  // a signed maximum, kappa > 0
  const test::Outcome old = test::run(base + " --require split:3:min --segments 2..3");
  EXPECT_EQ(old.code, 2);
  EXPECT_NE(old.err.find("use split:3:sharpest or :flattest"), std::string::npos) << old.err;
  const test::Outcome bad = test::run(base + " --segments 2..9");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(read_json(out / "report.json")["splines"][0]["error"].get<std::string>().find("segments 2..9"),
            std::string::npos);
  EXPECT_EQ(test::run(base + " --segments 2..x").code, 2);
}

TEST(ReportCommand, RejectsAnUnknownRequirementWithOneLine) {
  const test::Outcome r = test::run("report " + spline_file("any.json", spiral()) + " --out " +
                                    (test::scratch() / "unknown").string() + " --require monotone");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
  EXPECT_NE(r.err.find("--require"), std::string::npos) << r.err;
}

TEST(ReportCommand, FixesCarryThumbnails) {
  const fs::path out = test::scratch() / "fixes";
  const test::Outcome r = test::run("report " + spline_file("pulled.json", pulled_spiral()) + " --out " + out.string() +
                                    " --backend cpu --region-size 48 --require cmr");
  EXPECT_EQ(r.code, 1) << r.err;
  const Json doc = read_json(out / "report.json");
  const Json& fix = doc["splines"][0]["fixes"][2];
  EXPECT_GT(fix["region_pixels"].get<int>(), 0);
  EXPECT_TRUE(fix["verified"].get<bool>());
  EXPECT_NE(test::slurp(out / "index.html").find("data:image/png;base64,"), std::string::npos);
}

TEST(ReportCommand, AFolderWhereAnOutputGoesIsAnInputErrorAndWritesNeitherFile) {
  const fs::path out = test::scratch() / "blocked";
  fs::remove_all(out);
  fs::create_directories(out / "index.html");
  const test::Outcome r =
      test::run("report " + spline_file("blocked.json", spiral()) + " --out " + out.string() + " --no-thumbnails");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(r.err, "cmr: " + (out / "index.html").string() + ": is a directory\n");
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(out)) names.push_back(e.path().filename().string());
  EXPECT_EQ(names, std::vector<std::string>{"index.html"}) << "report.json (or a temporary) was left behind";
}

TEST(ReportCommand, ExamplesRun) {
  const std::string dir = std::string(CMR_SOURCE_DIR) + "/examples/report/";
  const fs::path out = test::scratch() / "examples";
  const test::Outcome r = test::run("report " + dir + "spiral.json " + dir + "wavy.json " + dir + "arch.json " + dir +
                                    "pulled.json --out " + out.string() + " --backend cpu --region-size 48");
  EXPECT_EQ(r.code, 0) << r.err;
  const Json doc = read_json(out / "report.json");
  ASSERT_EQ(doc["splines"].size(), 4u);
  EXPECT_EQ(doc["splines"][0]["status"], "pass");
  EXPECT_EQ(doc["splines"][3]["status"], "fail");
}

// The page as a browser shows it: headless Chromium renders it to a PNG that
// is not blank and shows the red maxima and blue minima of the figures.
TEST(ReportHtml, HeadlessChromiumShowsTheFigures) {
  const fs::path chromium = "/usr/bin/chromium";
  if (!fs::exists(chromium)) GTEST_SKIP() << "no " << chromium;
  const fs::path out = test::scratch() / "shot";
  const BSpline wavy =
      BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7}, {{0, 0}, {1, 2}, {3, 3}, {5, 2.5}, {6.5, 1}, {7, -1}});
  ASSERT_EQ(test::run("report " + spline_file("wavy.json", wavy) + " --out " + out.string() + " --no-thumbnails").code,
            0);
  const fs::path png = out / "shot.png";
  const std::string cmd = "timeout 120 " + chromium.string() +
                          " --headless --no-sandbox --disable-gpu --disable-background-networking"
                          " --disable-component-update --disable-sync --no-first-run --user-data-dir=" +
                          (out / "profile").string() + " --screenshot=" + png.string() +
                          " --window-size=1000,1200 file://" + fs::absolute(out / "index.html").string() +
                          " >/dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  cairo_surface_t* image = cairo_image_surface_create_from_png(png.c_str());
  ASSERT_EQ(cairo_surface_status(image), CAIRO_STATUS_SUCCESS) << png;
  const int w = cairo_image_surface_get_width(image), h = cairo_image_surface_get_height(image);
  const int stride = cairo_image_surface_get_stride(image);
  const unsigned char* data = cairo_image_surface_get_data(image);
  long ink = 0, red = 0, blue = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint32_t px;
      std::memcpy(&px, data + y * stride + 4 * x, 4);
      const int r = (px >> 16) & 255, g = (px >> 8) & 255, b = px & 255;
      ink += (r + g + b) < 600;
      red += r > 170 && g < 50 && b < 50;
      blue += b > 170 && r < 50 && g < 100;
    }
  cairo_surface_destroy(image);
  EXPECT_GT(ink, w * h / 100) << "blank page";
  EXPECT_GT(red, 40) << "no red (maxima, FAIL badge)";
  EXPECT_GT(blue, 40) << "no blue (minima, comb)";
}


TEST(ReportCommand, AnalyzeAndReportAgreeOnJointsWithAnAngleTolerance) {
  // Quadratic outline in integer font units, C0 at (171, 170) between
  // (100, 100) and (241, 240): the tangents differ by 0.406 degrees.
  const std::string file = spline_file(
      "font.json", BSpline::make(2, {0, 0, 1, 1, 2, 2}, {{0, 0}, {100, 100}, {171, 170}, {241, 240}, {400, 250}}));
  for (const std::string tol : {"", " --angle-tol 0.5"}) {
    const fs::path out = test::scratch() / "font_report";
    fs::remove_all(out);
    const test::Outcome a = test::run("analyze " + file + tol);
    ASSERT_EQ(a.code, 0) << a.err;
    const test::Outcome r = test::run("report " + file + " --out " + out.string() + " --no-thumbnails" + tol);
    ASSERT_EQ(r.code, 0) << r.err;
    const Json aj = Json::parse(a.out)["joints"][0];
    const Json rj = read_json(out / "report.json")["splines"][0]["joints"][0];
    for (const char* key : {"continuity", "g1", "g2", "angle", "zero_tangent", "kappa_left", "kappa_right", "jump"})
      EXPECT_EQ(aj[key], rj[key]) << key << " with '" << tol << "'";
    EXPECT_EQ(aj["g1"], !tol.empty()) << tol;
    EXPECT_EQ(rj["corner"], tol.empty()) << tol;
  }
  for (const std::string bad : {" --angle-tol -1", " --angle-tol 180", " --curvature-tol 2"}) {
    const test::Outcome a = test::run("analyze " + file + bad);
    EXPECT_EQ(a.code, 2) << bad;
    const fs::path out = test::scratch() / "font_bad";
    fs::remove_all(out);
    const test::Outcome r = test::run("report " + file + " --out " + out.string() + " --no-thumbnails" + bad);
    EXPECT_EQ(r.code, 2) << bad;
    EXPECT_FALSE(fs::exists(out / "report.json")) << bad;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
}


TEST(ReportCommand, AnalyzeAndReportAgreeOnSegmentSemantics) {
  // A straight, a curve leaving it with zero curvature, and a cusp.
  const std::string leaving =
      spline_file("leaving.json", bezier_chain({{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 0}, {5, 0}, {5.5, 0.5}}));
  const std::string cusp = spline_file("cusp.json", BSpline::bezier({{0, 0}, {2, 2}, {0, 2}, {2, 0}}));
  const fs::path out = test::scratch() / "semantics_report";
  fs::remove_all(out);
  ASSERT_EQ(test::run("report " + leaving + " " + cusp + " --out " + out.string() + " --no-thumbnails").code, 0);
  const Json doc = read_json(out / "report.json");
  const std::vector<std::string> files{leaving, cusp};
  for (std::size_t i = 0; i < files.size(); ++i) {
    const test::Outcome a = test::run("analyze " + files[i]);
    ASSERT_EQ(a.code, 0) << a.err;
    const Json aj = Json::parse(a.out);
    const Json& rj = doc["splines"][i];
    ASSERT_EQ(aj["segments"].size(), rj["segments"].size());
    for (std::size_t k = 0; k < aj["segments"].size(); ++k)
      for (const char* key : {"class", "curvature", "inflection", "zero_curvature_at", "algorithm2"})
        EXPECT_EQ(aj["segments"][k][key], rj["segments"][k][key]) << files[i] << " segment " << k << " " << key;
    for (const char* key : {"cmrwi", "cmr", "cmr_algorithm2"})
      EXPECT_EQ(aj["spline"][key], rj["verdict"][key]) << files[i] << " " << key;
    EXPECT_EQ(aj["spline"]["cusp"], rj["curvature"]["cusp"]) << files[i];
  }
  EXPECT_EQ(doc["splines"][0]["segments"][1]["zero_curvature_at"], "start");
  EXPECT_EQ(doc["splines"][0]["verdict"]["cmr"], "increasing");
  EXPECT_EQ(doc["splines"][1]["segments"][0]["class"], "cusp");
  EXPECT_TRUE(doc["splines"][1]["curvature"]["min"]["kappa"].is_null());
}

}  // namespace
}  // namespace cmr::report
