#include "numeric/bernstein.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace cmr {
namespace {

Bernstein<double> random_poly(std::mt19937_64& rng, int degree) {
  std::uniform_real_distribution<double> u(-1, 1);
  Bernstein<double> c(degree + 1);
  for (double& x : c) x = u(rng);
  return c;
}

TEST(Bernstein, BinomialIsExactFor128Bits) {
  EXPECT_EQ(static_cast<unsigned long long>(binomial(10, 3)), 120ULL);
  EXPECT_EQ(static_cast<unsigned long long>(binomial(53, 26)), 973469712824056ULL);
  // C(120, 60) = 9.66...e34; check it against the recurrence C(n,k) = C(n-1,k-1) + C(n-1,k).
  EXPECT_TRUE(binomial(120, 60) == binomial(119, 59) + binomial(119, 60));
  // Pascal's rule across the looked-up rows (n < 33) and the computed ones.
  for (int n = 1; n <= 40; ++n)
    for (int k = 0; k <= n; ++k) EXPECT_TRUE(binomial(n, k) == binomial(n - 1, k - 1) + binomial(n - 1, k)) << n << " " << k;
  EXPECT_TRUE(binomial(32, 16) == Int128(601080390));
}

TEST(Bernstein, ProductIsPointwiseProduct) {
  std::mt19937_64 rng(1);
  for (int m = 0; m <= 6; ++m)
    for (int n = 0; n <= 6; ++n) {
      const auto a = random_poly(rng, m), b = random_poly(rng, n);
      const auto c = bernstein_product(a, b);
      ASSERT_EQ(c.size(), static_cast<std::size_t>(m + n + 1));
      for (double t : {0.0, 0.3, 0.77, 1.0})
        EXPECT_NEAR(bernstein_eval(c, t), bernstein_eval(a, t) * bernstein_eval(b, t), 1e-13)
            << "m=" << m << " n=" << n << " t=" << t;
    }
}

TEST(Bernstein, DerivativeMatchesFiniteDifferences) {
  std::mt19937_64 rng(2);
  const auto c = random_poly(rng, 7);
  const auto d = bernstein_derivative(c);
  const double h = 1e-6;
  for (double t : {0.1, 0.5, 0.9})
    EXPECT_NEAR(bernstein_eval(d, t), (bernstein_eval(c, t + h) - bernstein_eval(c, t - h)) / (2 * h), 1e-7);
}

TEST(Bernstein, SubdivisionAndElevationKeepThePolynomial) {
  std::mt19937_64 rng(3);
  const auto c = random_poly(rng, 6);
  Bernstein<double> l, r;
  bernstein_subdivide(c, 0.3, l, r);
  const auto e = bernstein_elevate(c);
  for (double t : {0.0, 0.25, 0.6, 1.0}) {
    EXPECT_NEAR(bernstein_eval(l, t), bernstein_eval(c, 0.3 * t), 1e-14) << "t=" << t;
    EXPECT_NEAR(bernstein_eval(r, t), bernstein_eval(c, 0.3 + 0.7 * t), 1e-14) << "t=" << t;
    EXPECT_NEAR(bernstein_eval(e, t), bernstein_eval(c, t), 1e-14) << "t=" << t;
  }
  Bernstein<double> hl(7), hr(7), w(7);
  bernstein_halve(c.data(), c.size(), hl.data(), hr.data(), w.data());
  bernstein_subdivide(c, 0.5, l, r);
  for (int i = 0; i < 7; ++i) {
    EXPECT_NEAR(hl[i], l[i], 1e-15);
    EXPECT_NEAR(hr[i], r[i], 1e-15);
  }
}

TEST(Bernstein, BoundedArithmeticEnclosesTheExactValue) {
  std::mt19937_64 rng(4);
  for (int trial = 0; trial < 200; ++trial) {
    const auto a = random_poly(rng, 5), b = random_poly(rng, 4);
    const Bernstein<Bounded> A(a.begin(), a.end()), B(b.begin(), b.end());
    const Bernstein<Rational> Ae(a.begin(), a.end()), Be(b.begin(), b.end());
    const auto P = bernstein_product(bernstein_derivative(A), B);
    const auto Pe = bernstein_product(bernstein_derivative(Ae), Be);
    for (std::size_t k = 0; k < P.size(); ++k) {
      const Rational diff = abs(Pe[k] - Rational(P[k].v));
      ASSERT_LE(diff, Rational(P[k].e)) << "trial " << trial << " coefficient " << k;
      ASSERT_GT(P[k].e, 0.0);
    }
  }
}

TEST(Bernstein, ReductionUndoesElevationExactlyAndEnclosesInBoundedArithmetic) {
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<int> num(-1000, 1000);
  for (int n = 1; n <= 12; ++n) {
    Bernstein<Rational> c;
    for (int i = 0; i <= n; ++i) {
      c.push_back(Rational(num(rng), 64));
      c.back().canonicalize();  // GMP compares canonical fractions only
    }
    const Bernstein<Rational> e = bernstein_elevate(c);
    EXPECT_EQ(bernstein_reduce(e), c) << "n=" << n;  // bernstein_reduce also checks that both sweeps agree
    // The elevated coefficients rounded to double, each with a bound on its
    // rounding: the Bounded reduction must enclose the exact c.
    Bernstein<Bounded> eb;
    for (const Rational& x : e) eb.push_back(Bounded(x.get_d(), Bounded::kRound * std::abs(x.get_d())));
    const Bernstein<Bounded> rb = bernstein_reduce(eb);
    ASSERT_EQ(rb.size(), c.size());
    for (int i = 0; i <= n; ++i) {
      const Rational gap = abs(Rational(rb[i].v) - c[i]);
      EXPECT_LE(gap, Rational(rb[i].e)) << "n=" << n << " i=" << i;
    }
  }
}

}  // namespace
}  // namespace cmr
