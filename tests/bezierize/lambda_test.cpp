#include "bezierize/lambda.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "spline/curvature.hpp"
#include "tests/bezierize/lambda_reference.hpp"
#include "tests/test_util.hpp"

namespace cmr {
namespace {

template <class T>
std::vector<Point<T>> as(const std::vector<Vec2>& P) {
  std::vector<Point<T>> out;
  for (const Vec2& p : P) out.push_back(to_point<T>(p));
  return out;
}

TEST(Lambda, MatchesTheExactReferenceFromTheGeneratorScript) {
  for (const auto& ref : reference::lambda_references()) {
    std::vector<Vec2> P;
    for (auto [x, y] : ref.points) P.emplace_back(x, y);
    const auto xi = lambda_bernstein<Rational>(as<Rational>(P));
    const auto nu = eta_bernstein<Rational>(as<Rational>(P));
    ASSERT_EQ(xi.size(), ref.xi.size()) << ref.name;
    ASSERT_EQ(nu.size(), ref.nu.size()) << ref.name;
    for (std::size_t k = 0; k < xi.size(); ++k) EXPECT_EQ(xi[k], Rational(ref.xi[k])) << ref.name << " xi_" << k;
    for (std::size_t k = 0; k < nu.size(); ++k) EXPECT_EQ(nu[k], Rational(ref.nu[k])) << ref.name << " nu_" << k;
  }
}

TEST(Lambda, DegreesAreExactly4nMinus7And2nMinus4AndValuesMatchPointwise) {
  std::mt19937_64 rng(41);
  for (int n = 2; n <= 9; ++n) {
    const auto P = test::random_points(rng, n + 1);
    const auto xi = lambda_bernstein<double>(P);
    const auto nu = eta_bernstein<double>(P);
    ASSERT_EQ(static_cast<int>(xi.size()) - 1, 4 * n - 7) << "n=" << n;
    ASSERT_EQ(static_cast<int>(nu.size()) - 1, 2 * n - 4) << "n=" << n;
    const BSpline s = BSpline::bezier(P);
    for (double t : {0.0, 0.1, 0.5, 0.93, 1.0}) {
      const CurvatureSample c = curvature_at(s, t);
      EXPECT_NEAR(bernstein_eval(xi, t), c.lambda, 1e-9 * (1 + std::abs(c.lambda))) << "n=" << n << " t=" << t;
      EXPECT_NEAR(bernstein_eval(nu, t), c.eta, 1e-10 * (1 + std::abs(c.eta))) << "n=" << n << " t=" << t;
    }
  }
}

TEST(Lambda, SignAndSizeAgreeWithFiniteDifferencesOfKappaAlongArcLength) {
  std::mt19937_64 rng(42);
  for (int trial = 0; trial < 50; ++trial) {
    const auto P = test::random_points(rng, 4);
    const BSpline s = BSpline::bezier(P);
    const auto xi = lambda_bernstein<double>(P);
    for (double t = 0.05; t < 1; t += 0.1) {
      const double h = 1e-6;
      const Vec2 d1 = derivative(s, t, 1);
      const double g = dot(d1, d1);
      const double fd = (curvature(s, t + h) - curvature(s, t - h)) / (std::sqrt(g) * 2 * h);  // dkappa/ds
      const double predicted = bernstein_eval(xi, t) / (g * g * g);
      EXPECT_NEAR(predicted, fd, 1e-4 * (1 + std::abs(fd))) << "trial " << trial << " t=" << t;
      if (std::abs(fd) > 1e-3) {
        EXPECT_EQ(predicted > 0, fd > 0) << "trial " << trial << " t=" << t;
      }
    }
  }
}

TEST(Lambda, ReversingTheCurveReversesXi) {
  std::mt19937_64 rng(43);
  for (int n = 2; n <= 7; ++n) {
    auto P = test::random_points(rng, n + 1);
    const auto xi = lambda_bernstein<Rational>(as<Rational>(P));
    std::reverse(P.begin(), P.end());
    const auto rev = lambda_bernstein<Rational>(as<Rational>(P));
    const std::size_t N = xi.size() - 1;
    for (std::size_t i = 0; i <= N; ++i) EXPECT_EQ(rev[i], xi[N - i]) << "n=" << n << " i=" << i;
  }
}

TEST(Lambda, BoundedCoefficientsEncloseTheExactOnes) {
  std::mt19937_64 rng(44);
  for (int n = 2; n <= 12; ++n) {
    const auto P = test::random_points(rng, n + 1, 100);
    const auto b = lambda_bernstein<Bounded>(as<Bounded>(P));
    const auto e = lambda_bernstein<Rational>(as<Rational>(P));
    for (std::size_t k = 0; k < b.size(); ++k)
      ASSERT_LE(abs(e[k] - Rational(b[k].v)), Rational(b[k].e)) << "n=" << n << " k=" << k;
  }
}

}  // namespace
}  // namespace cmr
