// The floating-point shortcuts of analyze and the report (exactness-tracked
// doubles, certified float root isolation; numeric/fast_path.hpp) against
// the exact-only path (ExactOnlyScope: every decision they make taken in
// rationals instead): on seeded random B-splines and on the glyphs of real
// fonts, every verdict, class, shape, joint decision, root enclosure and
// event must be identical, and every certified curvature within the
// certified error of the exact value.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <sstream>

#include "bezierize/algorithms.hpp"
#include "bezierize/analyze.hpp"
#include "bezierize/extract.hpp"
#include "numeric/fast_path.hpp"
#include "numeric/fast_roots.hpp"
#include "bezierize/lambda.hpp"
#include "io/font.hpp"
#include "report/batch.hpp"
#include "report/report.hpp"

namespace cmr::report {
namespace {

// Both values NaN, or equal within the certified error of two certified
// values of the same exact curvature.
::testing::AssertionResult same_kappa(double a, double b) {
  if (std::isnan(a) && std::isnan(b)) return ::testing::AssertionSuccess();
  if (std::fabs(a - b) <= 2.5 * kKappaRelError * std::max(std::fabs(a), std::fabs(b)))
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "kappa " << a << " vs exact " << b;
}

std::string where(const std::string& what, int index) { return what + " " + std::to_string(index); }

void expect_same_analysis(const SplineAnalysis& f, const SplineAnalysis& x, const std::string& ctx) {
  ASSERT_EQ(f.shapes.size(), x.shapes.size()) << ctx;
  for (std::size_t i = 0; i < f.shapes.size(); ++i) {
    const std::string c = ctx + ", " + where("segment", static_cast<int>(i));
    const SegmentShape &a = f.shapes[i], &b = x.shapes[i];
    EXPECT_EQ(a.pole, b.pole) << c;
    EXPECT_EQ(a.straight, b.straight) << c;
    EXPECT_EQ(a.cusp, b.cusp) << c;
    EXPECT_EQ(a.inflection, b.inflection) << c;
    EXPECT_EQ(a.kappa_zero_start, b.kappa_zero_start) << c;
    EXPECT_EQ(a.kappa_zero_end, b.kappa_zero_end) << c;
    EXPECT_EQ(a.kappa_sign, b.kappa_sign) << c;
    const SegmentClass &p = f.segments[i], &q = x.segments[i];
    EXPECT_EQ(p.monotonicity.curvature, q.monotonicity.curvature) << c;
    EXPECT_EQ(p.monotonicity.depth, q.monotonicity.depth) << c;
    EXPECT_EQ(p.inflection.inflection, q.inflection.inflection) << c;
    EXPECT_EQ(p.inflection.depth, q.inflection.depth) << c;
    EXPECT_EQ(p.inflection.kappa_sign, q.inflection.kappa_sign) << c;
    EXPECT_EQ(p.exact_used, q.exact_used) << c;
  }
  ASSERT_EQ(f.joints.size(), x.joints.size()) << ctx;
  std::vector<Joint> fj = f.joints, xj = x.joints;
  if (f.seam) fj.push_back(*f.seam);
  if (x.seam) xj.push_back(*x.seam);
  ASSERT_EQ(fj.size(), xj.size()) << ctx;
  for (std::size_t i = 0; i < fj.size(); ++i) {
    const std::string c = ctx + ", " + where("joint", fj[i].index);
    EXPECT_EQ(fj[i].jump, xj[i].jump) << c;
    EXPECT_EQ(fj[i].zero_tangent, xj[i].zero_tangent) << c;
    EXPECT_EQ(fj[i].g1, xj[i].g1) << c;
    EXPECT_EQ(fj[i].g2, xj[i].g2) << c;
    EXPECT_TRUE(same_kappa(fj[i].kappa_left, xj[i].kappa_left)) << c;
    EXPECT_TRUE(same_kappa(fj[i].kappa_right, xj[i].kappa_right)) << c;
    if (!std::isnan(xj[i].angle_deg)) {
      EXPECT_EQ(fj[i].angle_deg, xj[i].angle_deg) << c;
    }
  }
  EXPECT_EQ(f.cmrwi, x.cmrwi) << ctx;
  EXPECT_EQ(f.cmr, x.cmr) << ctx;
  EXPECT_EQ(f.cmr_algorithm2, x.cmr_algorithm2) << ctx;
  EXPECT_EQ(f.cusp, x.cusp) << ctx;
  EXPECT_EQ(f.joint_conflicts, x.joint_conflicts) << ctx;
}

void expect_same_roots(const std::vector<SpanRoot>& f, const std::vector<SpanRoot>& x, const std::string& ctx) {
  ASSERT_EQ(f.size(), x.size()) << ctx;
  for (std::size_t k = 0; k < f.size(); ++k) {
    const std::string c = ctx + ", " + where("root", static_cast<int>(k));
    EXPECT_EQ(f[k].t, x[k].t) << c;
    EXPECT_EQ(f[k].t_lo, x[k].t_lo) << c;
    EXPECT_EQ(f[k].t_hi, x[k].t_hi) << c;
    EXPECT_EQ(f[k].exact, x[k].exact) << c;
    EXPECT_EQ(f[k].multiplicity, x[k].multiplicity) << c;
    EXPECT_EQ(f[k].sign_before, x[k].sign_before) << c;
    EXPECT_EQ(f[k].sign_after, x[k].sign_after) << c;
    EXPECT_EQ(f[k].at, x[k].at) << c;
    EXPECT_TRUE(same_kappa(f[k].kappa, x[k].kappa)) << c;
  }
}

void expect_same_report(const SplineReport& f, const SplineReport& x, const std::string& ctx) {
  expect_same_analysis(f.analysis, x.analysis, ctx);
  EXPECT_EQ(f.pass, x.pass) << ctx;
  EXPECT_EQ(f.requirement_pass, x.requirement_pass) << ctx;
  ASSERT_EQ(f.spans.size(), x.spans.size()) << ctx;
  for (std::size_t i = 0; i < f.spans.size(); ++i) {
    const std::string c = ctx + ", " + where("segment", static_cast<int>(i));
    EXPECT_EQ(f.spans[i].lambda_zero, x.spans[i].lambda_zero) << c;
    EXPECT_EQ(f.spans[i].eta_zero, x.spans[i].eta_zero) << c;
    EXPECT_EQ(f.spans[i].near_constant, x.spans[i].near_constant) << c;
    expect_same_roots(f.spans[i].extrema, x.spans[i].extrema, c + " extrema");
    expect_same_roots(f.spans[i].inflections, x.spans[i].inflections, c + " inflections");
  }
  ASSERT_EQ(f.extrema.size(), x.extrema.size()) << ctx;
  for (std::size_t k = 0; k < f.extrema.size(); ++k) {
    EXPECT_EQ(f.extrema[k].t, x.extrema[k].t) << ctx << " curve extremum " << k;
    EXPECT_EQ(f.extrema[k].kind, x.extrema[k].kind) << ctx << " curve extremum " << k;
    EXPECT_EQ(f.extrema[k].segment, x.extrema[k].segment) << ctx << " curve extremum " << k;
    EXPECT_EQ(f.extrema[k].joint, x.extrema[k].joint) << ctx << " curve extremum " << k;
  }
  ASSERT_EQ(f.inflections.size(), x.inflections.size()) << ctx;
  for (std::size_t k = 0; k < f.inflections.size(); ++k) {
    EXPECT_EQ(f.inflections[k].t, x.inflections[k].t) << ctx << " curve inflection " << k;
    EXPECT_EQ(f.inflections[k].kind, x.inflections[k].kind) << ctx << " curve inflection " << k;
  }
  ASSERT_EQ(f.gates.size(), x.gates.size()) << ctx;
  for (std::size_t g = 0; g < f.gates.size(); ++g) {
    ASSERT_EQ(f.gates[g].violations.size(), x.gates[g].violations.size()) << ctx << " gate " << to_string(f.gates[g].gate);
    for (std::size_t v = 0; v < f.gates[g].violations.size(); ++v)
      EXPECT_EQ(f.gates[g].violations[v].message, x.gates[g].violations[v].message) << ctx;
  }
}

ReportOptions type_gates() {
  ReportOptions o;
  o.regions = false;
  parse_require_list("curvature-extrema-at-nodes:runs,curvature-extrema-at-nodes,g2-at-smooth-nodes,no-inflection", o);
  return o;
}

// Random splines of the kinds the shortcuts meet: small integer and
// half-integer coordinates (exact in double: fonts), random doubles, straight
// runs, repeated knots (C0 and C1 joints), cusps (a repeated point).
BSpline random_spline(std::mt19937_64& rng, int trial) {
  std::uniform_int_distribution<int> degree_of(2, 5), small(-40, 40), pick(0, 9);
  std::uniform_real_distribution<double> real(-10, 10);
  const int d = degree_of(rng);
  const int m = d + 1 + static_cast<int>(rng() % 8);
  const bool integer = trial % 2 == 0;
  std::vector<Vec2> P;
  for (int i = 0; i < m; ++i) {
    Vec2 p = integer ? Vec2(small(rng), small(rng)) * (trial % 4 == 0 ? 0.5 : 1.0) : Vec2(real(rng), real(rng));
    const int k = pick(rng);
    if (i >= 2 && k == 0) p = P[i - 1] + (P[i - 1] - P[i - 2]);  // collinear: straight runs
    if (i >= 1 && k == 1) p = P[i - 1];                          // a repeated point: zero tangents, cusps
    P.push_back(p);
  }
  // Knots: clamped, interior integers with random multiplicities (1..d).
  std::vector<double> knots(d, 0.0);
  int interior = m - d - 1;  // polar form: m + d - 1 knots, d at each clamped end
  double u = 0;
  while (interior > 0) {
    u += integer ? 1.0 : 0.5 + (rng() % 5) * 0.25;
    const int mult = std::min(interior, 1 + static_cast<int>(rng() % d));
    for (int k = 0; k < mult; ++k) knots.push_back(u);
    interior -= mult;
  }
  u += 1;
  for (int k = 0; k < d; ++k) knots.push_back(u);
  return BSpline::make(d, knots, P, "random " + std::to_string(trial));
}

TEST(FastPath, RandomSplinesGetTheExactVerdictsClassesRootsAndEvents) {
  std::mt19937_64 rng(2411);
  const ReportOptions options = type_gates();
  int made = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::optional<BSpline> s;
    try {
      s = random_spline(rng, trial);
    } catch (const InputError&) {
      continue;  // an invalid draw (a span of zero length, ...)
    }
    ++made;
    const SplineReport fast = judged_report(*s, options);
    SplineReport exact;
    {
      const ExactOnlyScope scope;
      exact = judged_report(*s, options);
    }
    expect_same_report(fast, exact, s->name());
    if (HasFatalFailure()) return;
  }
  EXPECT_GT(made, 300);
}

TEST(FastPath, StraightClassIsWhatTheExactAlgorithmsGive) {
  // A straight cubic and quadratic: classify_segment's exact fallback and
  // Algorithms 1 and 2 on the exact coefficients.
  for (const std::vector<Vec2>& P : {std::vector<Vec2>{{0, 0}, {1, 1}, {2.5, 2.5}, {3, 3}},
                                     std::vector<Vec2>{{0, 0}, {1, 2}, {2, 4}}}) {
    const BSpline s = BSpline::bezier(P);
    const SegmentClass c = classify_segment(s, s.segments()[0]);
    const SegmentClass k = straight_class();
    EXPECT_EQ(c.monotonicity.curvature, k.monotonicity.curvature);
    EXPECT_EQ(c.monotonicity.depth, k.monotonicity.depth);
    EXPECT_EQ(c.inflection.inflection, k.inflection.inflection);
    EXPECT_EQ(c.inflection.depth, k.inflection.depth);
    EXPECT_EQ(c.inflection.kappa_sign, k.inflection.kappa_sign);
    EXPECT_EQ(c.exact_used, k.exact_used);
    const auto B = segment_bezier_points<Rational>(s, s.segments()[0]);
    EXPECT_EQ(algorithm1(lambda_bernstein<Rational>(B), 12)->curvature, Curvature::constant);
    EXPECT_EQ(algorithm2(eta_bernstein<Rational>(B), 12)->inflection, Inflection::present);
    EXPECT_TRUE(segment_shape(s, s.segments()[0]).straight);
  }
}

TEST(FastPath, BoundedIsolationEqualsExactIsolationOnRandomPolynomials) {
  std::mt19937_64 rng(77);
  int decided = 0, total = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const int n = 1 + static_cast<int>(rng() % 9);
    Bernstein<Rational> p;
    for (int i = 0; i <= n; ++i) {
      // Small integers (exact roots at halving points happen), or doubles.
      const long v = static_cast<long>(rng() % 21) - 10;
      p.push_back(trial % 2 ? Rational(v) : Rational(std::ldexp(static_cast<double>(static_cast<long>(rng() % 2001) - 1000), -7)));
    }
    Bernstein<Bounded> b;
    for (const Rational& c : p) b.push_back(Bounded(c.get_d()));  // exact doubles
    const auto fast = isolate_roots_bounded(b, {});
    ++total;
    if (!fast) continue;
    ++decided;
    const std::vector<RootInterval> exact = isolate_roots(p);
    ASSERT_EQ(fast->size(), exact.size()) << "trial " << trial;
    for (std::size_t k = 0; k < exact.size(); ++k) {
      EXPECT_EQ(Rational((*fast)[k].lo()), exact[k].lo) << "trial " << trial << " root " << k;
      EXPECT_EQ(Rational((*fast)[k].hi()), exact[k].hi) << "trial " << trial << " root " << k;
      EXPECT_EQ((*fast)[k].multiplicity, exact[k].multiplicity) << "trial " << trial << " root " << k;
      EXPECT_EQ((*fast)[k].sign_before, exact[k].sign_before) << "trial " << trial << " root " << k;
      EXPECT_EQ((*fast)[k].sign_after, exact[k].sign_after) << "trial " << trial << " root " << k;
    }
  }
  EXPECT_GT(decided, total / 2) << "the float isolation should decide most polynomials";
}

void compare_font(const char* path, const char* glyphs) {
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is not installed";
  const import::Font font = import::read_font(path, import::parse_glyph_spec(glyphs));
  const ReportOptions options = type_gates();
  int contours = 0;
  for (const import::Glyph& g : font.glyphs)
    for (const import::Contour& c : g.contours) {
      const SplineReport fast = judged_report(c.spline, options);
      SplineReport exact;
      {
        const ExactOnlyScope scope;
        exact = judged_report(c.spline, options);
      }
      expect_same_report(fast, exact, c.spline.name());
      if (::testing::Test::HasFatalFailure()) return;
      ++contours;
    }
  EXPECT_GT(contours, 100) << path;
}

TEST(FastPath, DejaVuSansLatinGlyphsGetTheExactResults) {
  compare_font("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf", "U+0021-U+017F");
}

TEST(FastPath, NimbusSansLatinGlyphsGetTheExactResults) {
  compare_font("/usr/share/fonts/opentype/urw-base35/NimbusSans-Regular.otf", "U+0021-U+017F");
}

}  // namespace
}  // namespace cmr::report
