// The space curve polynomials of bezierize/space_lambda.hpp against the exact
// references of tests/bezierize/gen_space_reference.py (issue 25).
#include "bezierize/space_lambda.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tests/bezierize/space_reference.hpp"

namespace cmr {
namespace {

template <class T>
std::vector<Point3<T>> as3(const std::vector<std::array<double, 3>>& P) {
  std::vector<Point3<T>> out;
  for (const auto& p : P) out.push_back(Point3<T>{T(p[0]), T(p[1]), T(p[2])});
  return out;
}

void expect_exact(const Bernstein<Rational>& got, const std::vector<std::string>& want, const std::string& what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (std::size_t k = 0; k < got.size(); ++k) EXPECT_EQ(got[k], Rational(want[k])) << what << "_" << k;
}

void expect_rounded(const Bernstein<double>& got, const std::vector<std::string>& want, const std::string& what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  double scale = 0;
  for (const std::string& w : want) scale = std::max(scale, std::fabs(Rational(w).get_d()));
  for (std::size_t k = 0; k < got.size(); ++k)
    EXPECT_NEAR(got[k], Rational(want[k]).get_d(), 1e-11 * scale) << what << "_" << k;
}

TEST(SpaceLambda, RationalCoefficientsEqualTheGeneratorsExactly) {
  for (const auto& ref : reference::space_references()) {
    const auto P = as3<Rational>(ref.points);
    const SpacePolynomials<Rational> p = space_polynomials<Rational>(P);
    expect_exact(p.c2, ref.c2, std::string(ref.name) + " |c|^2");
    expect_exact(p.lambda3, ref.lambda3, std::string(ref.name) + " lambda3");
    const Bernstein<Rational> N = torsion_numerator_bernstein<Rational>(P), T = torsion_sign_bernstein<Rational>(P);
    if (ref.N.empty()) {  // identically zero: every coefficient is 0
      for (const Rational& x : N) EXPECT_EQ(sgn(x), 0) << ref.name << " N";
      for (const Rational& x : T) EXPECT_EQ(sgn(x), 0) << ref.name << " T";
    } else {
      expect_exact(N, ref.N, std::string(ref.name) + " N");
      expect_exact(T, ref.T, std::string(ref.name) + " T");
    }
  }
}

TEST(SpaceLambda, DoubleCoefficientsEqualTheGeneratorsToRounding) {
  for (const auto& ref : reference::space_references()) {
    const auto P = as3<double>(ref.points);
    expect_rounded(lambda3_bernstein<double>(P), ref.lambda3, std::string(ref.name) + " lambda3");
    expect_rounded(space_polynomials<double>(P).c2, ref.c2, std::string(ref.name) + " |c|^2");
    if (!ref.N.empty()) {
      expect_rounded(torsion_numerator_bernstein<double>(P), ref.N, std::string(ref.name) + " N");
      expect_rounded(torsion_sign_bernstein<double>(P), ref.T, std::string(ref.name) + " T");
    }
  }
}

TEST(SpaceLambda, BoundedCoefficientsEncloseTheExactOnes) {
  for (const auto& ref : reference::space_references()) {
    const auto P = as3<Bounded>(ref.points);
    const Bernstein<Bounded> l = lambda3_bernstein<Bounded>(P);
    ASSERT_EQ(l.size(), ref.lambda3.size()) << ref.name;
    for (std::size_t k = 0; k < l.size(); ++k) {
      const Rational diff = Rational(l[k].v) - Rational(ref.lambda3[k]);
      EXPECT_LE(std::fabs(diff.get_d()), l[k].e) << ref.name << " lambda3_" << k;
    }
    if (ref.T.empty()) continue;
    const Bernstein<Bounded> t = torsion_sign_bernstein<Bounded>(P);
    ASSERT_EQ(t.size(), ref.T.size()) << ref.name;
    for (std::size_t k = 0; k < t.size(); ++k) {
      const Rational diff = Rational(t[k].v) - Rational(ref.T[k]);
      EXPECT_LE(std::fabs(diff.get_d()), t[k].e) << ref.name << " T_" << k;
    }
  }
}

TEST(SpaceLambda, DegreesAre6nMinus11And3nMinus9And7nMinus18) {
  std::mt19937_64 rng(2511);
  std::uniform_real_distribution<double> u(-4, 4);
  for (int n = 2; n <= 9; ++n) {
    std::vector<Point3<double>> P;
    for (int i = 0; i <= n; ++i) P.emplace_back(u(rng), u(rng), u(rng));
    EXPECT_EQ(static_cast<int>(lambda3_bernstein<double>(P).size()) - 1, 6 * n - 11) << "n=" << n;
    EXPECT_EQ(static_cast<int>(space_polynomials<double>(P).c2.size()) - 1, 4 * n - 8) << "n=" << n;
    if (n >= 3) {
      EXPECT_EQ(static_cast<int>(torsion_numerator_bernstein<double>(P).size()) - 1, 3 * n - 9) << "n=" << n;
      EXPECT_EQ(static_cast<int>(torsion_sign_bernstein<double>(P).size()) - 1, 7 * n - 18) << "n=" << n;
    } else {
      EXPECT_TRUE(torsion_sign_bernstein<double>(P).empty());
    }
  }
}

// A planar curve (z = 0): c = (0, 0, eta) and lambda3 = 2 eta lambda exactly.
TEST(SpaceLambda, PlanarCurveGivesTwiceEtaTimesThePlanesLambda) {
  std::mt19937_64 rng(77);
  std::uniform_int_distribution<int> u(-20, 20);
  for (int n = 2; n <= 7; ++n) {
    std::vector<Point<Rational>> P2;
    std::vector<Point3<Rational>> P3;
    for (int i = 0; i <= n; ++i) {
      const Rational x(u(rng), 4), y(u(rng), 4);
      P2.push_back({x, y});
      P3.push_back({x, y, Rational(0)});
    }
    const Bernstein<Rational> want = bernstein_product(eta_bernstein<Rational>(P2), lambda_bernstein<Rational>(P2));
    const Bernstein<Rational> got = lambda3_bernstein<Rational>(P3);
    ASSERT_EQ(got.size(), want.size()) << "n=" << n;
    for (std::size_t k = 0; k < got.size(); ++k) EXPECT_EQ(got[k], 2 * want[k]) << "n=" << n << " k=" << k;
    for (const Rational& x : torsion_numerator_bernstein<Rational>(P3)) EXPECT_EQ(sgn(x), 0) << "n=" << n;
  }
}

// Pointwise: lambda3 / g^4 is d(kappa^2)/dt and T / |c|^4 is d tau / dt, by
// central differences of kappa^2 = |c|^2 / g^3 and tau = N / |c|^2.
TEST(SpaceLambda, ValuesMatchFiniteDifferencesOfKappaSquaredAndTorsion) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-2, 2);
  for (int n = 3; n <= 6; ++n) {
    std::vector<Point3<double>> P;
    for (int i = 0; i <= n; ++i) P.emplace_back(u(rng), u(rng), u(rng));
    const SpacePolynomials<double> p = space_polynomials<double>(P);
    const Bernstein<double> N = torsion_numerator_bernstein<double>(P), T = torsion_sign_bernstein<double>(P);
    const auto k2 = [&](double t) { return bernstein_eval(p.c2, t) / std::pow(bernstein_eval(p.g, t), 3); };
    const auto tau = [&](double t) { return bernstein_eval(N, t) / bernstein_eval(p.c2, t); };
    for (double t : {0.2, 0.5, 0.8}) {
      const double h = 1e-6, g = bernstein_eval(p.g, t), c2 = bernstein_eval(p.c2, t);
      const double dk = (k2(t + h) - k2(t - h)) / (2 * h), want_k = bernstein_eval(p.lambda3, t) / std::pow(g, 4);
      EXPECT_NEAR(dk, want_k, 1e-5 * (1 + std::fabs(want_k))) << "n=" << n << " t=" << t;
      const double dt = (tau(t + h) - tau(t - h)) / (2 * h), want_t = bernstein_eval(T, t) / (c2 * c2);
      EXPECT_NEAR(dt, want_t, 1e-5 * (1 + std::fabs(want_t))) << "n=" << n << " t=" << t;
    }
  }
}

// ---- rational space curves ----

template <class T>
std::vector<HPoint3<T>> as4(const std::vector<std::array<double, 3>>& P, const std::vector<double>& w) {
  std::vector<HPoint3<T>> out;
  for (std::size_t i = 0; i < P.size(); ++i) {
    const T wi(w[i]);
    out.push_back(HPoint3<T>{T(P[i][0]) * wi, T(P[i][1]) * wi, T(P[i][2]) * wi, wi});
  }
  return out;
}

TEST(RationalSpaceLambda, RationalCoefficientsEqualTheGeneratorsExactly) {
  for (const auto& ref : reference::rational_space_references()) {
    const auto H = as4<Rational>(ref.points, ref.weights);
    const SpacePolynomials<Rational> p = space_polynomials<Rational>(H);
    expect_exact(p.c2, ref.E, std::string(ref.name) + " E");
    expect_exact(p.g, ref.G, std::string(ref.name) + " G");
    expect_exact(p.lambda3, ref.lambda3, std::string(ref.name) + " lambda3r");
    const Bernstein<Rational> N = torsion_numerator_bernstein<Rational>(H);
    if (!ref.N.empty()) expect_exact(N, ref.N, std::string(ref.name) + " Nr");
    const Bernstein<Rational> T = torsion_sign_bernstein<Rational>(H);
    if (ref.N.empty()) {
      for (const Rational& x : N) EXPECT_EQ(sgn(x), 0) << ref.name << " Nr";
      for (const Rational& x : T) EXPECT_EQ(sgn(x), 0) << ref.name << " Tr";
    } else {
      expect_exact(T, ref.T, std::string(ref.name) + " Tr");
    }
  }
}

TEST(RationalSpaceLambda, DoubleCoefficientsEqualTheGeneratorsToRounding) {
  for (const auto& ref : reference::rational_space_references()) {
    const auto H = as4<double>(ref.points, ref.weights);
    expect_rounded(lambda3_bernstein<double>(H), ref.lambda3, std::string(ref.name) + " lambda3r");
    expect_rounded(space_polynomials<double>(H).c2, ref.E, std::string(ref.name) + " E");
    if (!ref.N.empty()) {
      expect_rounded(torsion_numerator_bernstein<double>(H), ref.N, std::string(ref.name) + " Nr");
      expect_rounded(torsion_sign_bernstein<double>(H), ref.T, std::string(ref.name) + " Tr");
    }
  }
}

TEST(RationalSpaceLambda, BoundedCoefficientsEncloseTheExactOnes) {
  for (const auto& ref : reference::rational_space_references()) {
    const auto H = as4<Bounded>(ref.points, ref.weights);
    const auto check = [&](const Bernstein<Bounded>& got, const std::vector<std::string>& want, const char* what) {
      ASSERT_EQ(got.size(), want.size()) << ref.name << " " << what;
      for (std::size_t k = 0; k < got.size(); ++k) {
        const Rational diff = Rational(got[k].v) - Rational(want[k]);
        EXPECT_LE(std::fabs(diff.get_d()), got[k].e) << ref.name << " " << what << "_" << k;
      }
    };
    check(lambda3_bernstein<Bounded>(H), ref.lambda3, "lambda3r");
    if (!ref.T.empty()) check(torsion_sign_bernstein<Bounded>(H), ref.T, "Tr");
  }
}

// Unit weights: the homogeneous formulas give the polynomial ones, lambda3r
// being lambda3 degree-elevated from 6n-11 to 11n-18 (and Tr = T elevated
// from 7n-18 to 11n-26, Nr = N from 3n-9 to 4n-12).
TEST(RationalSpaceLambda, UnitWeightsGiveThePolynomialFormulasElevated) {
  const auto elevate_to = [](Bernstein<Rational> p, std::size_t size) {
    while (p.size() < size) p = bernstein_elevate(p);
    return p;
  };
  for (const auto& ref : reference::space_references()) {
    const auto P = as3<Rational>(ref.points);
    const auto H = as4<Rational>(ref.points, std::vector<double>(ref.points.size(), 1.0));
    const int n = static_cast<int>(P.size()) - 1;
    const Bernstein<Rational> l = lambda3_bernstein<Rational>(H);
    ASSERT_EQ(static_cast<int>(l.size()) - 1, 11 * n - 18) << ref.name;
    const Bernstein<Rational> want = elevate_to(lambda3_bernstein<Rational>(P), l.size());
    for (std::size_t k = 0; k < l.size(); ++k) EXPECT_EQ(l[k], want[k]) << ref.name << " lambda3r_" << k;
    if (n < 3 || ref.T.empty()) continue;
    const Bernstein<Rational> t = torsion_sign_bernstein<Rational>(H);
    ASSERT_EQ(static_cast<int>(t.size()) - 1, 11 * n - 26) << ref.name;
    const Bernstein<Rational> wt = elevate_to(torsion_sign_bernstein<Rational>(P), t.size());
    for (std::size_t k = 0; k < t.size(); ++k) EXPECT_EQ(t[k], wt[k]) << ref.name << " Tr_" << k;
    const Bernstein<Rational> N = torsion_numerator_bernstein<Rational>(H);
    const Bernstein<Rational> wn = elevate_to(torsion_numerator_bernstein<Rational>(P), N.size());
    for (std::size_t k = 0; k < N.size(); ++k) EXPECT_EQ(N[k], wn[k]) << ref.name << " Nr_" << k;
  }
}

// Pointwise: d(kappa^2)/dt = W^5 lambda3r / G^4 and d tau/dt = W Tr / E^2 by
// central differences of kappa^2 = E W^6 / G^3 and tau = W^2 Nr / E.
TEST(RationalSpaceLambda, ValuesMatchFiniteDifferencesOfKappaSquaredAndTorsion) {
  std::mt19937_64 rng(19);
  std::uniform_real_distribution<double> u(-2, 2), uw(0.3, 3);
  for (int n = 2; n <= 6; ++n) {
    std::vector<HPoint3<double>> H;
    Bernstein<double> W;
    for (int i = 0; i <= n; ++i) {
      const double w = uw(rng);
      H.emplace_back(w * u(rng), w * u(rng), w * u(rng), w);
      W.push_back(w);
    }
    const SpacePolynomials<double> p = space_polynomials<double>(H);
    const Bernstein<double> N = torsion_numerator_bernstein<double>(H), T = torsion_sign_bernstein<double>(H);
    const auto k2 = [&](double t) {
      return bernstein_eval(p.c2, t) * std::pow(bernstein_eval(W, t), 6) / std::pow(bernstein_eval(p.g, t), 3);
    };
    const auto tau = [&](double t) { return std::pow(bernstein_eval(W, t), 2) * bernstein_eval(N, t) / bernstein_eval(p.c2, t); };
    for (double t : {0.2, 0.5, 0.8}) {
      const double h = 1e-6, g = bernstein_eval(p.g, t), E = bernstein_eval(p.c2, t), w = bernstein_eval(W, t);
      const double dk = (k2(t + h) - k2(t - h)) / (2 * h), want_k = std::pow(w, 5) * bernstein_eval(p.lambda3, t) / std::pow(g, 4);
      EXPECT_NEAR(dk, want_k, 1e-5 * (1 + std::fabs(want_k))) << "n=" << n << " t=" << t;
      if (n < 3) continue;
      const double dt = (tau(t + h) - tau(t - h)) / (2 * h), want_t = w * bernstein_eval(T, t) / (E * E);
      EXPECT_NEAR(dt, want_t, 1e-5 * (1 + std::fabs(want_t))) << "n=" << n << " t=" << t;
    }
  }
}

}  // namespace
}  // namespace cmr
