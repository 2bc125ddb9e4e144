#include "bezierize/classify.hpp"
#include "spline/errors.hpp"
#include "bezierize/algorithms.hpp"
#include "bezierize/decide.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "bezierize/lambda.hpp"
#include "tests/test_util.hpp"

namespace cmr {
namespace {

template <class T>
std::vector<Point<T>> as(const std::vector<Vec2>& P) {
  std::vector<Point<T>> out;
  for (const Vec2& p : P) out.push_back(to_point<T>(p));
  return out;
}

MonotonicityResult exact_algorithm1(const std::vector<Vec2>& P, int depth) {
  return *algorithm1(lambda_bernstein<Rational>(as<Rational>(P)), depth);
}
InflectionResult exact_algorithm2(const std::vector<Vec2>& P, int depth) {
  return *algorithm2(eta_bernstein<Rational>(as<Rational>(P)), depth);
}

// Bernstein coefficients (exact) of prod (t - r_i) times a constant.
Bernstein<Rational> with_roots(const std::vector<Rational>& roots, const Rational& scale) {
  Bernstein<Rational> p{scale};
  for (const Rational& r : roots) p = bernstein_product(p, Bernstein<Rational>{-r, 1 - r});
  return p;
}

TEST(Algorithm1, PaperRulesOnHandMadeCoefficients) {
  using B = Bernstein<Rational>;
  EXPECT_EQ(algorithm1(B{1, 2, 0, 3}, 12)->curvature, Curvature::increasing);
  EXPECT_EQ(algorithm1(B{-1, 0, -2}, 12)->curvature, Curvature::decreasing);
  EXPECT_EQ(algorithm1(B{-1, 5, 5, 2}, 12)->curvature, Curvature::non_monotone);
  EXPECT_EQ(algorithm1(B{-1, 5, 5, 2}, 12)->depth, 0);
  EXPECT_EQ(algorithm1(B{0, 0, 0}, 12)->curvature, Curvature::constant);
  // (t - 1/2)^2 >= 0 touches zero at a dyadic point: halves are [1/4,-1/4... no:
  // (t-1/2)^2 on [0,1/2] has coefficients 1/4, 0, 0 -> increasing at level 1.
  const auto sq = with_roots({Rational(1, 2), Rational(1, 2)}, 1);
  EXPECT_EQ(algorithm1(sq, 12)->curvature, Curvature::increasing);
  EXPECT_EQ(algorithm1(sq, 12)->depth, 1);
  // (t - 1/3)^2: a non-dyadic double root is never certified: undecided at D.
  const auto sq3 = with_roots({Rational(1, 3), Rational(1, 3)}, 1);
  EXPECT_EQ(algorithm1(sq3, 12)->curvature, Curvature::undecided);
  EXPECT_EQ(algorithm1(sq3, 12)->depth, 12);
  // (t - 1/2)^3 changes sign: the halves go opposite ways.
  const auto cube = with_roots({Rational(1, 2), Rational(1, 2), Rational(1, 2)}, 1);
  EXPECT_EQ(algorithm1(cube, 12)->curvature, Curvature::non_monotone);
  // Two roots 2^-20 apart are separated only below level 20.
  const auto close = with_roots({Rational(1, 3), Rational(1, 3) + Rational(1, 1 << 20)}, -1);
  EXPECT_EQ(algorithm1(close, 12)->curvature, Curvature::undecided);
  EXPECT_EQ(algorithm1(close, 30)->curvature, Curvature::non_monotone);
}

TEST(Algorithm2, PaperRulesOnHandMadeCoefficients) {
  using B = Bernstein<Rational>;
  EXPECT_EQ(algorithm2(B{1, 2, 3}, 12)->inflection, Inflection::none);
  EXPECT_EQ(algorithm2(B{1, 2, 3}, 12)->kappa_sign, 1);
  EXPECT_EQ(algorithm2(B{-1, -2, -3}, 12)->kappa_sign, -1);
  EXPECT_EQ(algorithm2(B{1, -2, -3}, 12)->inflection, Inflection::present);
  EXPECT_EQ(algorithm2(B{0, 2, 3}, 12)->inflection, Inflection::present);  // nu_0 nu_last <= 0
  // (1-2t)^2 touches zero at 1/2: the halves are [1,0,0] and [0,0,1], and a
  // zero end counts as an inflection by rule (1).
  EXPECT_EQ(algorithm2(B{1, -1, 1}, 12)->inflection, Inflection::present);
  EXPECT_EQ(algorithm2(B{1, -1, 1}, 12)->depth, 1);
  // (t-1/3)^2 touches zero at a non-dyadic point: never decided.
  const auto sq3 = with_roots({Rational(1, 3), Rational(1, 3)}, 1);
  EXPECT_EQ(algorithm2(sq3, 12)->inflection, Inflection::undecided);
}

TEST(Classifier, AgreesWithExactAlgorithmsOnRandomSegmentsOfDegree2To9) {
  std::mt19937_64 rng(51);
  int exact = 0, total = 0;
  for (int n = 2; n <= 9; ++n)
    for (int trial = 0; trial < 300; ++trial) {
      const auto P = test::random_points(rng, n + 1);
      const SegmentClass c = classify_bezier(P);
      const MonotonicityResult m = exact_algorithm1(P, 12);
      const InflectionResult i = exact_algorithm2(P, 12);
      ASSERT_EQ(c.monotonicity.curvature, m.curvature) << "n=" << n << " trial " << trial;
      ASSERT_EQ(c.monotonicity.depth, m.depth) << "n=" << n << " trial " << trial;
      ASSERT_EQ(c.inflection.inflection, i.inflection) << "n=" << n << " trial " << trial;
      ASSERT_EQ(c.inflection.depth, i.depth) << "n=" << n << " trial " << trial;
      exact += c.exact_used;
      ++total;
    }
  EXPECT_LT(exact, total / 100) << "the exact path should be rare on random data";
}

TEST(Classifier, SymmetricCubicHasItsExtremumExactlyAtTheMiddle) {
  // Mirror-symmetric about x = 2: kappa(1-t) = kappa(t), so lambda is odd
  // about 1/2: xi_i = -xi_{N-i} exactly, and rule (3) decides at level 0.
  const std::vector<Vec2> P = {{0, 0}, {1, 2}, {3, 2}, {4, 0}};
  const auto xi = lambda_bernstein<Rational>(as<Rational>(P));
  for (std::size_t i = 0; i < xi.size(); ++i) EXPECT_EQ(xi[i], -xi[xi.size() - 1 - i]) << "i=" << i;
  const SegmentClass c = classify_bezier(P);
  EXPECT_EQ(c.monotonicity.curvature, Curvature::non_monotone);
  EXPECT_EQ(c.monotonicity.depth, 0);
}

TEST(Classifier, RootExactlyAtAnEndIsMonotone) {
  // The left half of the symmetric cubic (de Casteljau at 1/2 is exact in
  // binary) has lambda(1) = 0 and curvature monotone on [0, 1].
  const std::vector<Vec2> P = {{0, 0}, {0.5, 1}, {1.25, 1.5}, {2, 1.5}};
  const auto xi = lambda_bernstein<Rational>(as<Rational>(P));
  ASSERT_EQ(sgn(xi.back()), 0);
  const SegmentClass c = classify_bezier(P);
  EXPECT_EQ(c.monotonicity.curvature, exact_algorithm1(P, 12).curvature);
  EXPECT_TRUE(c.monotonicity.curvature == Curvature::increasing ||
              c.monotonicity.curvature == Curvature::decreasing);
  EXPECT_TRUE(c.exact_used);
}

// Not finite: a clear error, where the exact path used to raise SIGFPE
// (GMP's mpq from an infinity; fuzz_kcurve's finding: a kappa-curve's
// piece elevated near the largest double).
TEST(Classifier, ANonFiniteControlPointIsAnInputError) {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  for (const Vec2 bad : {Vec2(inf, 0), Vec2(0, -inf), Vec2(nan, 1)}) {
    const std::vector<Vec2> P = {{0, 0}, bad, {1.25, 1.5}, {2, 1.5}};
    EXPECT_THROW(classify_bezier(P), InputError);
  }
}

TEST(Classifier, StraightSegmentIsConstantAndHasAnInflectionByAlgorithm2) {
  const std::vector<Vec2> line = {{0, 0}, {1, 1}, {2.5, 2.5}, {3, 3}};
  const SegmentClass c = classify_bezier(line);
  EXPECT_EQ(c.monotonicity.curvature, Curvature::constant);
  EXPECT_EQ(c.inflection.inflection, Inflection::present);
}

TEST(Classifier, QuadraticsAgreeWithSapidisFrey) {
  // Sapidis & Frey 1992 / CAD&A 2024 Eq. 7: the curvature maximum of a
  // quadratic is at t* = (P0-P1).(P0-2P1+P2) / |P0-2P1+P2|^2; the curvature is
  // monotone iff t* is outside (0, 1); |kappa| grows towards t*.
  std::mt19937_64 rng(52);
  for (int trial = 0; trial < 2000; ++trial) {
    const auto P = test::random_points(rng, 3);
    const Vec2 a = P[0] - P[1], b = P[0] - 2.0 * P[1] + P[2];
    const double t = dot(a, b) / dot(b, b);
    const SegmentClass c = classify_bezier(P);
    if (t > 1e-9 && t < 1 - 1e-9) {
      EXPECT_EQ(c.monotonicity.curvature, Curvature::non_monotone) << "trial " << trial << " t*=" << t;
    } else if (t < -1e-9 || t > 1 + 1e-9) {
      const double eta = det(P[1] - P[0], P[2] - P[1]);
      // |kappa| falls away from t*: after it (t* <= 0) |kappa| decreases.
      const bool abs_decreasing = t < 0;
      const Curvature want = (abs_decreasing == (eta > 0)) ? Curvature::decreasing : Curvature::increasing;
      EXPECT_EQ(c.monotonicity.curvature, want) << "trial " << trial << " t*=" << t;
      EXPECT_EQ(c.monotonicity.depth, 0);
    }
  }
}

TEST(Classifier, DegreeElevatedCubicClassifiesAsTheCubic) {
  std::mt19937_64 rng(53);
  int compared = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const auto P = test::random_points(rng, 4);
    std::vector<Vec2> E(5);  // exact in rationals; in double the elevated points round
    E[0] = P[0];
    E[4] = P[3];
    for (int i = 1; i <= 3; ++i) E[i] = (i / 4.0) * P[i - 1] + (1 - i / 4.0) * P[i];
    // Compare against the exactly elevated curve's exact classification, and
    // the cubic's: both decided -> the same direction.
    Bernstein<Rational> xs = lambda_bernstein<Rational>(as<Rational>(P));
    std::vector<Point<Rational>> Pe = as<Rational>(P), Ee(5);
    Ee[0] = Pe[0];
    Ee[4] = Pe[3];
    for (int i = 1; i <= 3; ++i) Ee[i] = Rational(i, 4) * Pe[i - 1] + Rational(4 - i, 4) * Pe[i];
    const MonotonicityResult cubic = *algorithm1(xs, 12);
    const MonotonicityResult quartic = *algorithm1(lambda_bernstein<Rational>(Ee), 12);
    const SegmentClass rounded = classify_bezier(E);
    if (cubic.curvature != Curvature::undecided && quartic.curvature != Curvature::undecided) {
      EXPECT_EQ(cubic.curvature, quartic.curvature) << "trial " << trial;
      ++compared;
    }
    if (rounded.monotonicity.curvature != Curvature::undecided && cubic.curvature != Curvature::undecided &&
        cubic.depth < 8) {
      EXPECT_EQ(rounded.monotonicity.curvature, cubic.curvature) << "trial " << trial;
    }
  }
  EXPECT_GT(compared, 450);
}

TEST(Classifier, CloseRootsAndEndRootsAreDecidedCorrectlyOrUndecided) {
  // lambda-like polynomials with roots 1e-6 apart or 1e-9 from an end, at
  // scales 2^-7..2^7: the Bounded path must equal the exact path.
  std::mt19937_64 rng(54);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  for (int trial = 0; trial < 300; ++trial) {
    const Rational r(u(rng));
    const Rational scale = Rational(1, 128) * (1 << (trial % 15));
    std::vector<Rational> roots;
    switch (trial % 4) {
      case 0: roots = {r, r + Rational(1, 1000000)}; break;
      case 1: roots = {Rational(1, 1000000000)}; break;
      case 2: roots = {Rational(999999999, 1000000000), r}; break;
      default: roots = {r, r + Rational(1, 1000000), Rational(-1, 1000000000)}; break;
    }
    const Bernstein<Rational> exact = with_roots(roots, scale);
    Bernstein<Bounded> rounded;
    for (const Rational& c : exact) rounded.emplace_back(c.get_d(), 0.0);
    // Rounding the coefficients moves them; compare with the exact result of
    // the rounded (double) coefficients, which is what the classifier sees.
    Bernstein<Rational> seen;
    for (const Bounded& c : rounded) seen.emplace_back(c.v);
    const MonotonicityResult truth = *algorithm1(seen, 12);
    const auto fast = algorithm1(rounded, 12);
    if (fast) {
      EXPECT_EQ(fast->curvature, truth.curvature) << "trial " << trial;
    }
    EXPECT_TRUE(truth.curvature == Curvature::non_monotone || truth.curvature == Curvature::undecided)
        << "trial " << trial << ": a sign change was missed (" << to_string(truth.curvature) << ")";
  }
}

}  // namespace
}  // namespace cmr
