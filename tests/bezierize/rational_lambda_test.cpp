// Rational curves: D and lambda in Bernstein form (rational_lambda.hpp)
// against the exact generator script, exact arithmetic, closed-form conic
// curvature and finite differences; verdicts of analyze on conics and NURBS,
// and their invariance under degree elevation and knot insertion.
#include "bezierize/rational_lambda.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <random>

#include "bezierize/algorithms.hpp"
#include "bezierize/analyze.hpp"
#include "bezierize/extract.hpp"
#include "bezierize/knot_ops.hpp"
#include "spline/curvature.hpp"
#include "spline/errors.hpp"
#include "tests/bezierize/rational_lambda_reference.hpp"

namespace cmr {
namespace {

template <class T>
std::vector<HPoint<T>> homogeneous(const std::vector<Vec2>& P, const std::vector<double>& w) {
  std::vector<HPoint<T>> out;
  for (std::size_t i = 0; i < P.size(); ++i) out.push_back(to_hpoint<T>(P[i], w[i]));
  return out;
}

BSpline reference_curve(const reference::RationalLambdaReference& ref) {
  std::vector<Vec2> P;
  for (auto [x, y] : ref.points) P.emplace_back(x, y);
  return BSpline::bezier(P, ref.name, ref.weights);
}

TEST(RationalLambda, MatchesTheExactReferenceFromTheGeneratorScript) {
  for (const auto& ref : reference::rational_lambda_references()) {
    const BSpline s = reference_curve(ref);
    const int n = s.degree();
    const auto H = homogeneous<Rational>(s.points(), s.weights());
    const auto xi = rational_lambda_bernstein<Rational>(H);
    const auto d = rational_d_bernstein<Rational>(H);
    ASSERT_EQ(static_cast<int>(xi.size()) - 1, 8 * n - 12) << ref.name;
    ASSERT_EQ(static_cast<int>(d.size()) - 1, 3 * n - 6) << ref.name;
    ASSERT_EQ(xi.size(), ref.xi.size()) << ref.name;
    ASSERT_EQ(d.size(), ref.d.size()) << ref.name;
    for (std::size_t k = 0; k < xi.size(); ++k) EXPECT_EQ(xi[k], Rational(ref.xi[k])) << ref.name << " xi_" << k;
    for (std::size_t k = 0; k < d.size(); ++k) EXPECT_EQ(d[k], Rational(ref.d[k])) << ref.name << " D_" << k;
    // The certified double path encloses the exact coefficients.
    const auto xb = rational_lambda_bernstein<Bounded>(homogeneous<Bounded>(s.points(), s.weights()));
    ASSERT_EQ(xb.size(), xi.size());
    for (std::size_t k = 0; k < xi.size(); ++k)
      EXPECT_LE(std::abs(xb[k].v - xi[k].get_d()), xb[k].e * (1 + 1e-12) + 1e-300) << ref.name << " xi_" << k;
  }
}

TEST(RationalLambda, DegreeIsExactly8nMinus12ForGenericWeights) {
  // The leading terms cancel (rational_lambda.hpp): computed exactly at
  // 8n-11, the top power coefficient vanishes (bernstein_reduce checks it),
  // and the next one generally does not.
  std::mt19937_64 rng(1313);
  std::uniform_real_distribution<double> coord(-4, 4), weight(0.25, 4);
  for (int n = 2; n <= 6; ++n) {
    std::vector<Vec2> P;
    std::vector<double> w;
    for (int i = 0; i <= n; ++i) {
      P.emplace_back(coord(rng), coord(rng));
      w.push_back(weight(rng));
    }
    const auto xi = rational_lambda_bernstein<Rational>(homogeneous<Rational>(P, w));
    ASSERT_EQ(static_cast<int>(xi.size()) - 1, 8 * n - 12) << "n=" << n;
    // Leading power coefficient at degree N: sum_i (-1)^(N-i) C(N,i) xi_i.
    const int N = 8 * n - 12;
    Rational lead = 0;
    for (int i = 0; i <= N; ++i) {
      Rational c = Scalar<Rational>::ratio(binomial(N, i), 1) * xi[i];
      lead += (N - i) % 2 == 0 ? c : Rational(-c);
    }
    EXPECT_NE(sgn(lead), 0) << "n=" << n << ": lambda has degree below 8n-12 for random data";
  }
}

TEST(RationalLambda, ValuesMatchPointwiseCurvatureAndFiniteDifferences) {
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> coord(-3, 3), weight(0.3, 3);
  for (int n = 2; n <= 5; ++n) {
    for (int trial = 0; trial < 5; ++trial) {
      std::vector<Vec2> P;
      std::vector<double> w;
      for (int i = 0; i <= n; ++i) {
        P.emplace_back(coord(rng), coord(rng));
        w.push_back(weight(rng));
      }
      const BSpline s = BSpline::bezier(P, "", w);
      const auto H = homogeneous<double>(P, w);
      const auto xi = rational_lambda_bernstein<double>(H);
      const auto d = rational_d_bernstein<double>(H);
      for (double t : {0.1, 0.35, 0.6, 0.85}) {
        const CurvatureSample c = curvature_at(s, t);
        EXPECT_NEAR(bernstein_eval(xi, t), c.lambda, 1e-8 * (1 + std::abs(c.lambda))) << "n=" << n << " t=" << t;
        EXPECT_NEAR(bernstein_eval(d, t), c.eta, 1e-9 * (1 + std::abs(c.eta))) << "n=" << n << " t=" << t;
        // kappa from the projected curve's own derivatives (Leibniz in derivative()).
        const Vec2 d1 = derivative(s, t, 1), d2 = derivative(s, t, 2);
        const double kappa = det(d1, d2) / std::pow(dot(d1, d1), 1.5);
        EXPECT_NEAR(c.kappa, kappa, 1e-8 * (1 + std::abs(kappa))) << "n=" << n << " t=" << t;
        // dkappa/ds by central differences of kappa over arc length.
        const double h = 1e-5;
        const double dk = (curvature(s, t + h) - curvature(s, t - h)) / (2 * h) / std::sqrt(dot(d1, d1));
        EXPECT_NEAR(c.dkappa_ds, dk, 1e-4 * (1 + std::abs(dk))) << "n=" << n << " t=" << t;
      }
    }
  }
}

// Curvature of the conic F(x, y) = 0 at a point on it:
// |F_y^2 F_xx - 2 F_x F_y F_xy + F_x^2 F_yy| / (F_x^2 + F_y^2)^(3/2).
double ellipse_curvature(Vec2 p, double a, double b) {  // x^2/a^2 + y^2/b^2 = 1
  const double fx = 2 * p.x / (a * a), fy = 2 * p.y / (b * b), fxx = 2 / (a * a), fyy = 2 / (b * b);
  return std::abs(fy * fy * fxx + fx * fx * fyy) / std::pow(fx * fx + fy * fy, 1.5);
}

TEST(RationalLambda, ConicsHaveTheirClosedFormCurvatureAndVerdicts) {
  struct Case {
    const char* name;
    double (*kappa)(Vec2);
    Curvature verdict;
  };
  const Case cases[] = {
      {"circle_quarter", [](Vec2) { return 1.0; }, Curvature::constant},
      {"ellipse_quarter", [](Vec2 p) { return ellipse_curvature(p, 3, 2); }, Curvature::decreasing},
      // y = x^2: 2 / (1 + 4x^2)^(3/2)
      {"parabola_half", [](Vec2 p) { return 2 / std::pow(1 + 4 * p.x * p.x, 1.5); }, Curvature::decreasing},
      // x y = 25: 2 x y / (x^2 + y^2)^(3/2)
      {"hyperbola", [](Vec2 p) { return 2 * p.x * p.y / std::pow(dot(p, p), 1.5); }, Curvature::non_monotone},
  };
  for (const Case& c : cases) {
    const auto& refs = reference::rational_lambda_references();
    const auto it = std::find_if(refs.begin(), refs.end(), [&](const auto& r) { return std::string(r.name) == c.name; });
    ASSERT_NE(it, refs.end()) << c.name;
    const BSpline s = reference_curve(*it);
    ASSERT_TRUE(s.is_rational()) << c.name;
    for (double t = 0; t <= 1; t += 0.0625) {
      const CurvatureSample k = curvature_at(s, t);
      EXPECT_NEAR(std::abs(k.kappa), c.kappa(k.point), 1e-12 * c.kappa(k.point)) << c.name << " t=" << t;
    }
    const SplineAnalysis a = analyze(s);
    EXPECT_EQ(a.segments[0].monotonicity.curvature, c.verdict) << c.name << ": " << to_string(a.segments[0].monotonicity.curvature);
    EXPECT_EQ(a.segments[0].inflection.inflection, Inflection::none) << c.name;
  }
}

TEST(RationalLambda, CirclesHaveLambdaIdenticallyZeroExactly) {
  // A quarter circle of any radius, centre and orientation: an isosceles
  // control triangle with a right angle at P1 and w1^2 / (w0 w2) = 1/2.
  std::mt19937_64 rng(9);
  std::uniform_int_distribution<int> small(-8, 8);
  for (int trial = 0; trial < 20; ++trial) {
    const Vec2 c(small(rng), small(rng));
    Vec2 u(small(rng), small(rng));
    if (u == Vec2(0.0)) u = Vec2(1, 2);
    const Vec2 v(-u.y, u.x);
    const std::vector<Vec2> P = {c + u, c + u + v, c + v};
    const std::vector<double> w = trial % 2 ? std::vector<double>{2, 1, 1} : std::vector<double>{0.5, 1, 4};
    const auto xi = rational_lambda_bernstein<Rational>(homogeneous<Rational>(P, w));
    for (std::size_t k = 0; k < xi.size(); ++k) EXPECT_EQ(sgn(xi[k]), 0) << "trial " << trial << " xi_" << k;
    EXPECT_EQ(analyze(BSpline::bezier(P, "", w)).segments[0].monotonicity.curvature, Curvature::constant);
  }
}

TEST(RationalLambda, FullCircleNurbsIsConstantWithoutJumps) {
  // Four quarter arcs (weights 2,1,1 scaled to agree at the joints), knots
  // of multiplicity 2: C0 joints whose curvature jump is exactly 0.
  const BSpline s = BSpline::make(2, {0, 0, 1, 1, 2, 2, 3, 3, 4, 4},
                                  {{1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}, {-1, -1}, {0, -1}, {1, -1}, {1, 0}},
                                  "circle", {2, 1, 1, 0.5, 0.5, 0.25, 0.25, 0.125, 0.125});
  for (double t = 0; t <= 4; t += 0.125) {
    EXPECT_NEAR(std::sqrt(dot(evaluate(s, t), evaluate(s, t))), 1.0, 1e-15) << "t=" << t;
    EXPECT_NEAR(curvature(s, t), 1.0, 1e-14) << "t=" << t;
  }
  const SplineAnalysis a = analyze(s);
  for (const SegmentClass& c : a.segments) EXPECT_EQ(c.monotonicity.curvature, Curvature::constant);
  for (const Joint& j : a.joints) EXPECT_EQ(j.jump, 0) << "joint " << j.index;
  EXPECT_TRUE(a.joint_conflicts.empty());
  EXPECT_EQ(a.cmr, Direction::increasing);  // all constant: Algorithm 1's rule order
}

// The homogeneous curve through knot_ops' primitive in exact arithmetic.
std::vector<std::vector<HPoint<Rational>>> exact_homogeneous_segments(const BSpline& s, std::vector<Rational> knots,
                                                                      int degree) {
  PolarSpline<Rational> xy{s.degree(), {s.knots().begin(), s.knots().end()}, {}}, w = xy;
  for (int i = 0; i < s.point_count(); ++i) {
    const HPoint<Rational> h = to_hpoint<Rational>(s.points()[i], s.weight(i));
    xy.points.push_back({h.x, h.y});
    w.points.push_back({h.z, Rational(0)});
  }
  const PolarSpline<Rational> rxy = rewrite_on_knots(xy, knots, degree), rw = rewrite_on_knots(w, knots, degree);
  std::vector<HPoint<Rational>> window;
  for (std::size_t i = 0; i < rxy.points.size(); ++i) window.push_back({rxy.points[i].x, rxy.points[i].y, rw.points[i].x});
  std::vector<std::vector<HPoint<Rational>>> out;
  const int m = static_cast<int>(window.size());
  for (int j = degree - 1; j <= m - 2; ++j)
    if (rxy.knots[j] < rxy.knots[j + 1])
      out.push_back(bezier_points(rxy.knots, window, degree, j, rxy.knots[j], rxy.knots[j + 1]));
  return out;
}

TEST(RationalLambda, ElevatedAndRefinedCirclesKeepLambdaZeroExactly) {
  const BSpline s = BSpline::bezier({{1, 0}, {1, 1}, {0, 1}}, "", {2, 1, 1});
  const std::vector<Rational> knots(s.knots().begin(), s.knots().end());
  for (const auto& H : exact_homogeneous_segments(s, elevated_knots(knots, Rational(0), Rational(1)), 3))
    for (const Rational& c : rational_lambda_bernstein<Rational>(H)) EXPECT_EQ(sgn(c), 0) << "elevated";
  const auto split = exact_homogeneous_segments(s, knots_with(knots, Rational(1, 3), 1), 2);
  ASSERT_EQ(split.size(), 2u);
  for (const auto& H : split)
    for (const Rational& c : rational_lambda_bernstein<Rational>(H)) EXPECT_EQ(sgn(c), 0) << "inserted";
}

TEST(RationalLambda, ExactlyElevatedAndInsertedConicsKeepTheirVerdicts) {
  for (const char* name : {"ellipse_quarter", "parabola_half", "hyperbola"}) {
    const auto& refs = reference::rational_lambda_references();
    const auto it = std::find_if(refs.begin(), refs.end(), [&](const auto& r) { return std::string(r.name) == name; });
    ASSERT_NE(it, refs.end());
    const BSpline s = reference_curve(*it);
    const Curvature verdict = analyze(s).segments[0].monotonicity.curvature;
    const std::vector<Rational> knots(s.knots().begin(), s.knots().end());
    for (const auto& [what, segments] :
         {std::pair{"elevated", exact_homogeneous_segments(s, elevated_knots(knots, Rational(0), Rational(1)), 3)},
          std::pair{"inserted", exact_homogeneous_segments(s, knots_with(knots, Rational(1, 3), 1), 2)}}) {
      std::vector<Curvature> parts;
      for (const auto& H : segments) parts.push_back(algorithm1(rational_lambda_bernstein<Rational>(H), 12)->curvature);
      if (verdict == Curvature::non_monotone) {
        // Split at 1/3 the hyperbola's pieces may be monotone, in opposite directions.
        const bool whole = parts.size() == 1 && parts[0] == Curvature::non_monotone;
        const bool opposite = std::count(parts.begin(), parts.end(), Curvature::increasing) > 0 &&
                              std::count(parts.begin(), parts.end(), Curvature::decreasing) > 0;
        const bool any = std::count(parts.begin(), parts.end(), Curvature::non_monotone) > 0;
        EXPECT_TRUE(whole || opposite || any) << name << " " << what;
      } else {
        for (Curvature c : parts) EXPECT_EQ(c, verdict) << name << " " << what << ": " << to_string(c);
      }
    }
  }
}

TEST(RationalLambda, ElevationAndKnotInsertionKeepTheVerdicts) {
  // Curves whose verdicts do not hang on rounding (strictly monotone or
  // clearly not); the double knot operations round the new points. The
  // circle, the quarter ellipse and the half parabola have lambda = 0 at an
  // end (a vertex), which rounding may tip either way: they are checked in
  // exact arithmetic below.
  std::vector<BSpline> curves;
  for (const auto& ref : reference::rational_lambda_references())
    if (std::string(ref.name) == "hyperbola" || std::string(ref.name) == "cubic" || std::string(ref.name) == "quartic")
      curves.push_back(reference_curve(ref));
  curves.push_back(BSpline::make(3, {0, 0, 0, 1, 2, 3, 3, 3}, {{0, 0}, {1, 2}, {3, 3}, {5, 2.5}, {6.5, 1}, {7, -1}},
                                 "nurbs", {1, 1.5, 0.75, 2, 1, 1.25}));
  for (const BSpline& s : curves) {
    const SplineAnalysis before = analyze(s);
    std::vector<std::pair<const char*, BSpline>> variants = {{"elevated", elevate_degree(s)},
                                                             {"elevated twice", elevate_degree(elevate_degree(s))}};
    // Inserting into a degree >= 3 curve keeps the new joints C2 (no jump test).
    const BSpline e = s.degree() >= 3 ? s : elevate_degree(s);
    variants.push_back({"inserted", insert_knot(e, 0.3 * e.domain_begin() + 0.7 * e.domain_end(), 1)});
    variants.push_back({"refined", refine(e)});
    for (const auto& [what, v] : variants) {
      ASSERT_TRUE(v.is_rational()) << s.name() << " " << what;
      for (double t = 0; t <= 1; t += 0.125) {
        const double u = s.domain_begin() + t * (s.domain_end() - s.domain_begin());
        EXPECT_NEAR(std::sqrt(dot(evaluate(v, u) - evaluate(s, u), evaluate(v, u) - evaluate(s, u))), 0, 1e-12) << s.name() << " " << what << " t=" << t;
      }
      const SplineAnalysis after = analyze(v);
      EXPECT_EQ(after.cmrwi, before.cmrwi) << s.name() << " " << what << ": " << to_string(after.cmrwi);
      EXPECT_EQ(after.cmr, before.cmr) << s.name() << " " << what << ": " << to_string(after.cmr);
    }
  }
}

TEST(RationalLambda, KnotRemovalIsRefusedForRationalCurves) {
  const BSpline s = BSpline::make(3, {0, 0, 0, 1, 2, 2, 2}, {{0, 0}, {1, 2}, {3, 3}, {4, 1}, {5, 0}}, "", {1, 2, 1, 2, 1});
  try {
    (void)remove_knot(s, 1, 1e-9);
    FAIL() << "removal accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not supported for rational curves"), std::string::npos) << e.what();
  }
}

TEST(RationalLambda, EqualWeightsAreThePolynomialCurve) {
  const std::vector<Vec2> P = {{0, 0}, {1, 2}, {3, 3}, {4, 1}};
  const BSpline r = BSpline::bezier(P, "", {2.5, 2.5, 2.5, 2.5});
  EXPECT_FALSE(r.is_rational());
  const SegmentClass a = analyze(r).segments[0], b = analyze(BSpline::bezier(P)).segments[0];
  EXPECT_EQ(a.monotonicity.curvature, b.monotonicity.curvature);
  EXPECT_EQ(a.monotonicity.depth, b.monotonicity.depth);
}

}  // namespace
}  // namespace cmr
