// Knot operations: insertion, removal, elevation, refinement and clamping
// leave the curve unchanged (sampled against an independent Cox-de Boor
// evaluator, and exactly in rational arithmetic), and bad input is refused.
#include "bezierize/knot_ops.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <numeric>
#include <string>

#include "bezierize/analyze.hpp"
#include "numeric/exact.hpp"
#include "spline/errors.hpp"
#include "spline/spline_json.hpp"
#include "tests/test_util.hpp"

namespace cmr {
namespace {

/// Sampled positions must agree to this fraction of the curve's extent
/// (rounding of a few blossom evaluations of degree <= 6).
constexpr double kSameCurveRelative = 1e-12;
constexpr int kSamples = 400;

struct Family {
  std::string name;
  int degree;
  std::vector<double> knots;
};

/// Uniform, clamped and non-uniform (with a double knot) knots for degree d,
/// d + 5 points each.
std::vector<Family> families() {
  std::vector<Family> out;
  for (int d : {2, 3, 5}) {
    const int count = 2 * d + 4;  // m + d - 1 with m = d + 5
    Family uniform{"uniform_d" + std::to_string(d), d, {}};
    for (int i = 0; i < count; ++i) uniform.knots.push_back(i);
    Family clamped{"clamped_d" + std::to_string(d), d, std::vector<double>(d, 0.0)};
    for (int i = 1; i <= count - 2 * d; ++i) clamped.knots.push_back(i);
    clamped.knots.insert(clamped.knots.end(), d, count - 2 * d + 1);
    Family nonuniform{"nonuniform_d" + std::to_string(d), d, {}};
    double u = -1.5;
    for (int i = 0; i < count; ++i) {
      nonuniform.knots.push_back(u);
      if (i != d) u += 0.25 + 0.37 * ((i * 7) % 5);  // knots[d] == knots[d+1]: a double knot
    }
    out.push_back(uniform);
    out.push_back(clamped);
    out.push_back(nonuniform);
  }
  // Empty spans at the ends of the domain (points 0 and m-1 do not influence
  // the curve) and an interior knot of full multiplicity (a C0 joint).
  out.push_back({"empty_end_spans_d3", 3, {0, 1, 1, 1, 2, 3, 3.5, 3.5, 3.5, 9}});
  out.push_back({"c0_joint_d3", 3, {0, 0, 0, 1, 1, 1, 3, 3, 3}});
  return out;
}

BSpline make_spline(const Family& f, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const int m = static_cast<int>(f.knots.size()) - f.degree + 1;
  return BSpline::make(f.degree, f.knots, test::random_points(rng, m, 10.0), f.name);
}

/// Asserts that b is a on the same domain: dense samples of b (Cox-de Boor,
/// independent of the blossom) against a (blossom).
void expect_same_curve(const BSpline& a, const BSpline& b, const std::string& label) {
  ASSERT_EQ(a.domain_begin(), b.domain_begin()) << label;
  ASSERT_EQ(a.domain_end(), b.domain_end()) << label;
  const double tol = kSameCurveRelative * extent(a);
  double worst = 0, worst_t = 0;
  for (int i = 0; i <= kSamples; ++i) {
    const double t = a.domain_begin() + (a.domain_end() - a.domain_begin()) * i / kSamples;
    const Vec2 p = evaluate(a, t), q = test::cox_de_boor(b, t);
    const double dist = std::hypot(p.x - q.x, p.y - q.y);
    if (dist > worst) worst = dist, worst_t = t;
  }
  EXPECT_LE(worst, tol) << label << ": the curves differ by " << worst << " at t = " << worst_t;
}

/// Proves exactly that `fine` is `coarse` on the whole domain: on every
/// segment of `fine` (inside one segment of `coarse`) the two polynomials, of
/// degree <= fine.degree, agree at fine.degree + 1 distinct rational parameters.
void expect_same_curve_exactly(const PolarSpline<Rational>& coarse, const PolarSpline<Rational>& fine,
                               const std::string& label) {
  const int m = static_cast<int>(fine.points.size()), mc = static_cast<int>(coarse.points.size());
  const int d = fine.degree, dc = coarse.degree;
  std::vector<int> spans;
  for (int j = d - 1; j <= m - 2; ++j)
    if (fine.knots[j] < fine.knots[j + 1]) spans.push_back(j);
  ASSERT_FALSE(spans.empty()) << label;
  std::vector<int> coarse_spans;
  for (int j = dc - 1; j <= mc - 2; ++j)
    if (coarse.knots[j] < coarse.knots[j + 1]) coarse_spans.push_back(j);
  EXPECT_EQ(fine.knots[spans.front()], coarse.knots[coarse_spans.front()]) << label << ": domain start";
  EXPECT_EQ(fine.knots[spans.back() + 1], coarse.knots[coarse_spans.back() + 1]) << label << ": domain end";
  for (int j : spans) {
    const Rational &c = fine.knots[j], &e = fine.knots[j + 1];
    const int jc = span_holding(coarse.knots, dc, mc, c, e);
    ASSERT_GE(jc, 0) << label << ": span " << j << " is not inside one old segment";
    for (int q = 0; q <= d; ++q) {
      const Rational t = c + (e - c) * Rational(q) / d;
      const std::vector<Rational> tf(d, t), tc(dc, t);
      const auto p = blossom_span(fine.knots, fine.points, d, j, tf.data());
      const auto r = blossom_span(coarse.knots, coarse.points, dc, jc, tc.data());
      EXPECT_TRUE(p.x == r.x && p.y == r.y) << label << ": span " << j << " differs at t = " << t.get_d();
    }
  }
}

/// A value strictly inside segment `index` of s (a fixed, non-dyadic fraction).
double inside(const BSpline& s, int index) {
  const Segment& g = s.segments()[index];
  return g.a + (g.b - g.a) * 0.3183;
}

TEST(KnotOps, InsertOneToDegreeTimesLeavesTheCurve) {
  for (const Family& f : families()) {
    const BSpline s = make_spline(f, 101);
    const int mid = s.segment_count() / 2;
    for (double u : {inside(s, mid), s.segments()[mid].a, s.domain_begin(), s.domain_end()}) {
      const int k = s.multiplicity(u);
      for (int times = 1; times + k <= f.degree; ++times) {
        const std::string label = f.name + " u=" + std::to_string(u) + " times=" + std::to_string(times);
        const BSpline r = insert_knot(s, u, times);
        EXPECT_EQ(r.point_count(), s.point_count() + times) << label;
        EXPECT_EQ(r.multiplicity(u), k + times) << label;
        expect_same_curve(s, r, label);
        const PolarSpline<Rational> exact = polar_spline<Rational>(s);
        const Rational ue(u);
        expect_same_curve_exactly(exact, rewrite_on_knots(exact, knots_with(exact.knots, ue, times), f.degree),
                                  label + " (exact)");
      }
    }
  }
}

TEST(KnotOps, InsertCopiesUntouchedPointsAndAgreesWithBoehm) {
  for (const Family& f : families()) {
    const BSpline s = make_spline(f, 102);
    const double u = inside(s, s.segment_count() / 2);
    const BSpline blossomed = insert_knot(s, u, 1), boehm = insert_knot(s, u);
    ASSERT_EQ(blossomed.knots(), boehm.knots()) << f.name;
    const int j = s.segment_at(u).span;
    for (int i = 0; i < blossomed.point_count(); ++i) {
      const Vec2 p = blossomed.points()[i], q = boehm.points()[i];
      if (i <= j - f.degree + 1 || i >= j + 2) {
        EXPECT_EQ(p, q) << f.name << ": point " << i << " is outside the window of u and must be copied";
      } else {
        EXPECT_NEAR(p.x, q.x, kSameCurveRelative * extent(s)) << f.name << " point " << i;
        EXPECT_NEAR(p.y, q.y, kSameCurveRelative * extent(s)) << f.name << " point " << i;
      }
    }
  }
}

TEST(KnotOps, RemovingAnInsertedKnotGivesTheOriginalBack) {
  for (const Family& f : families()) {
    const BSpline s = make_spline(f, 103);
    const int mid = s.segment_count() / 2;
    for (double u : {inside(s, mid), s.segments()[mid].a}) {
      if (s.multiplicity(u) == f.degree) continue;  // nothing to insert
      const std::string label = f.name + " u=" + std::to_string(u);
      const BSpline r = insert_knot(s, u, 1);
      const KnotRemoval back = remove_knot(r, u, kRemovalRelativeTolerance * extent(s));
      EXPECT_EQ(back.spline.knots(), s.knots()) << label;
      EXPECT_LE(back.distance, kSameCurveRelative * extent(s)) << label;
      for (int i = 0; i < s.point_count(); ++i) {
        EXPECT_NEAR(back.spline.points()[i].x, s.points()[i].x, kSameCurveRelative * extent(s)) << label << " point " << i;
        EXPECT_NEAR(back.spline.points()[i].y, s.points()[i].y, kSameCurveRelative * extent(s)) << label << " point " << i;
      }
      // In rationals the original comes back exactly.
      const PolarSpline<Rational> exact = polar_spline<Rational>(s);
      const Rational ue(u);
      const auto inserted = rewrite_on_knots(exact, knots_with(exact.knots, ue, 1), f.degree);
      const int last = static_cast<int>(std::upper_bound(inserted.knots.begin(), inserted.knots.end(), ue) -
                                        inserted.knots.begin()) - 1;
      const auto removed = remove_knot_at(inserted, last);
      ASSERT_EQ(removed.points.size(), exact.points.size()) << label;
      for (std::size_t i = 0; i < exact.points.size(); ++i)
        EXPECT_TRUE(removed.points[i].x == exact.points[i].x && removed.points[i].y == exact.points[i].y)
            << label << ": point " << i << " is not restored exactly";
    }
  }
}

TEST(KnotOps, RemovingAnEssentialKnotIsMeasuredAndRefused) {
  for (const Family& f : families()) {
    const BSpline s = make_spline(f, 104);
    const double u = s.segments()[s.segment_count() / 2].a;  // a knot with generic points on both sides
    const std::string label = f.name + " u=" + std::to_string(u);
    const KnotRemoval forced = remove_knot(s, u, std::numeric_limits<double>::infinity());
    ASSERT_GT(forced.distance, kRemovalRelativeTolerance * extent(s)) << label;
    // The reported distance bounds the sampled deviation and is not far above it.
    double sampled = 0;
    for (int i = 0; i <= kSamples; ++i) {
      const double t = s.domain_begin() + (s.domain_end() - s.domain_begin()) * i / kSamples;
      const Vec2 p = evaluate(s, t), q = test::cox_de_boor(forced.spline, t);
      sampled = std::max(sampled, std::hypot(p.x - q.x, p.y - q.y));
    }
    EXPECT_LE(sampled, forced.distance * (1 + 1e-12)) << label;
    EXPECT_GE(sampled, forced.distance / 20) << label << ": the bound is far from the deviation";
    try {
      (void)remove_knot(s, u, forced.distance / 2);
      ADD_FAILURE() << label << ": removal beyond the tolerance was accepted";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("moves the curve by up to"), std::string::npos) << label << ": " << msg;
      EXPECT_NE(msg.find("more than the tolerance"), std::string::npos) << label << ": " << msg;
    }
  }
}

TEST(KnotOps, ElevationRaisesTheDegreeAndKeepsTheCurveAndContinuity) {
  for (const Family& f : families()) {
    const BSpline s = make_spline(f, 105);
    const BSpline e = elevate_degree(s);
    EXPECT_EQ(e.degree(), f.degree + 1) << f.name;
    EXPECT_EQ(e.segment_count(), s.segment_count()) << f.name;
    for (std::size_t i = 1; i < s.segments().size(); ++i) {
      const double u = s.segments()[i].a;
      EXPECT_EQ(e.multiplicity(u), s.multiplicity(u) + 1) << f.name << " knot " << u;
    }
    expect_same_curve(s, e, f.name);
    const PolarSpline<Rational> exact = polar_spline<Rational>(s);
    const Rational a(s.domain_begin()), b(s.domain_end());
    expect_same_curve_exactly(exact, rewrite_on_knots(exact, elevated_knots(exact.knots, a, b), f.degree + 1),
                              f.name + " (exact)");
  }
}

TEST(KnotOps, RefineSplitsEverySegmentAndKeepsTheCurve) {
  for (const Family& f : families()) {
    const BSpline s = make_spline(f, 106);
    const BSpline r = refine(s);
    ASSERT_EQ(r.segment_count(), 2 * s.segment_count()) << f.name;
    for (int i = 0; i < s.segment_count(); ++i) {
      const Segment& g = s.segments()[i];
      EXPECT_EQ(r.segments()[2 * i].b, std::midpoint(g.a, g.b)) << f.name << " segment " << i;
    }
    expect_same_curve(s, r, f.name);
    const PolarSpline<Rational> exact = polar_spline<Rational>(s);
    expect_same_curve_exactly(
        exact, rewrite_on_knots(exact, refined_knots(exact.knots, f.degree, s.point_count()), f.degree),
        f.name + " (exact)");
  }
}

TEST(KnotOps, ClampGivesEndKnotsOfMultiplicityDegreeAndKeepsTheCurve) {
  for (const Family& f : families()) {
    const BSpline s = make_spline(f, 107);
    const BSpline c = clamp(s);
    const int d = f.degree;
    const std::vector<double>& K = c.knots();
    for (int i = 0; i < d; ++i) {
      EXPECT_EQ(K[i], s.domain_begin()) << f.name << " knot " << i;
      EXPECT_EQ(K[K.size() - 1 - i], s.domain_end()) << f.name << " knot from the end " << i;
    }
    EXPECT_EQ(c.segment_count(), s.segment_count()) << f.name;
    // The first and last control points are the curve's end points.
    EXPECT_EQ(c.points().front(), evaluate(c, c.domain_begin())) << f.name;
    expect_same_curve(s, c, f.name);
    EXPECT_EQ(clamp(c).knots(), c.knots()) << f.name << ": clamping is idempotent";
    const PolarSpline<Rational> exact = polar_spline<Rational>(s);
    const Rational a(s.domain_begin()), b(s.domain_end());
    expect_same_curve_exactly(exact, rewrite_on_knots(exact, clamped_knots(exact.knots, d, a, b), d),
                              f.name + " (exact)");
  }
}

TEST(KnotOps, UniformKeepsPointsAndNumbersTheKnots) {
  const BSpline s = make_spline(families()[5], 108);  // non-uniform cubic
  const BSpline u = make_uniform(s);
  EXPECT_EQ(u.points(), s.points());
  for (std::size_t i = 0; i < u.knots().size(); ++i) EXPECT_EQ(u.knots()[i], static_cast<double>(i)) << "knot " << i;
  EXPECT_EQ(u.domain_begin(), s.degree() - 1);
  EXPECT_EQ(u.domain_end(), s.point_count() - 1);
}

TEST(KnotOps, SetKnotMovesOneKnotAndValidates) {
  const BSpline s = make_spline(families()[3], 109);  // uniform cubic, knots 0..9
  const BSpline moved = set_knot(s, 4, 4.5);
  std::vector<double> want = s.knots();
  want[4] = 4.5;
  EXPECT_EQ(moved.knots(), want);
  EXPECT_EQ(moved.points(), s.points());
}

struct Bad {
  const char* name;
  std::function<void()> op;
  const char* message_part;
};

TEST(KnotOps, BadInputsAreRefusedWithOneActionableLine) {
  const BSpline cubic = make_spline(families()[3], 110);  // uniform cubic, knots 0..9, domain [2, 7]
  std::vector<double> top_knots(2 * kMaxDegree, 0.0);
  std::fill(top_knots.begin() + kMaxDegree, top_knots.end(), 1.0);
  std::mt19937_64 rng(111);
  const BSpline top = BSpline::make(kMaxDegree, top_knots, test::random_points(rng, kMaxDegree + 1));
  const std::vector<Bad> cases = {
      {"insert_below_domain", [&] { (void)insert_knot(cubic, 1.5, 1); }, "knot 1.5 lies outside the domain [2, 7]"},
      {"insert_above_domain", [&] { (void)insert_knot(cubic, 7.5, 1); }, "outside the domain"},
      {"insert_nan", [&] { (void)insert_knot(cubic, std::nan(""), 1); }, "not a finite number"},
      {"insert_zero_times", [&] { (void)insert_knot(cubic, 3.5, 0); }, "times must be at least 1"},
      {"insert_beyond_degree", [&] { (void)insert_knot(cubic, 3, 3); }, "makes 4, above the degree 3"},
      {"remove_not_a_knot", [&] { (void)remove_knot(cubic, 3.5, 1); }, "knot 3.5 is not in the knot vector"},
      {"remove_domain_end", [&] { (void)remove_knot(cubic, 2, 1); }, "only interior knots can be removed"},
      {"remove_negative_tol", [&] { (void)remove_knot(cubic, 4, -1); }, "tolerance must be zero or more"},
      {"set_index_high", [&] { (void)set_knot(cubic, 10, 3); }, "knot index 10 is out of range 0..9"},
      {"set_index_negative", [&] { (void)set_knot(cubic, -1, 3); }, "out of range"},
      {"set_breaks_order", [&] { (void)set_knot(cubic, 4, 2.5); }, "knots[4] (2.5) is smaller than knots[3] (3)"},
      {"set_multiplicity", [&] { (void)set_knot(make_spline(families()[4], 1), 3, 0); }, "multiplicity above"},
      {"set_infinite", [&] { (void)set_knot(cubic, 4, INFINITY); }, "not a finite number"},
      {"elevate_beyond_max", [&] { (void)elevate_degree(top); }, "highest degree supported"},
  };
  for (const Bad& c : cases) {
    try {
      c.op();
      ADD_FAILURE() << c.name << ": accepted";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(c.message_part), std::string::npos) << c.name << ": " << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << c.name << ": not one line: " << msg;
    }
  }
}

TEST(KnotOps, AnalyzeVerdictIsAPropertyOfTheCurve) {
  std::vector<std::filesystem::path> files;
  for (const char* dir : {"examples", "examples/figures"})
    for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(CMR_SOURCE_DIR) / dir))
      if (entry.path().extension() == ".json") files.push_back(entry.path());
  ASSERT_GE(files.size(), 10u);
  int monotone = 0, not_monotone = 0;  // the examples must hold both verdicts
  for (const auto& file : files) {
    const BSpline s = read_spline_file(file);
    const SplineAnalysis base = analyze(s);
    ++(base.cmrwi == Direction::none ? not_monotone : monotone);
    const std::vector<std::pair<std::string, BSpline>> variants = {
        {"insert", insert_knot(s, inside(s, 0), 1)}, {"elevate", elevate_degree(s)}, {"refine", refine(s)}};
    for (const auto& [op, v] : variants) {
      const SplineAnalysis a = analyze(v);
      EXPECT_EQ(to_string(a.cmrwi), std::string(to_string(base.cmrwi))) << file.filename() << " after " << op;
      EXPECT_EQ(to_string(a.cmr), std::string(to_string(base.cmr))) << file.filename() << " after " << op;
    }
  }
  EXPECT_GE(monotone, 3);
  EXPECT_GE(not_monotone, 3);
}

}  // namespace
}  // namespace cmr
