#include "numeric/roots.hpp"

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <utility>
#include <vector>

namespace cmr {
namespace {

Rational q(long num, long den = 1) {
  Rational r(num, den);
  r.canonicalize();
  return r;
}

// scale * prod (t - r)^m in Bernstein form on [0, 1], from the factors: the
// reference roots are the r given here, independent of the code under test.
Bernstein<Rational> from_roots(const std::vector<std::pair<Rational, int>>& roots, Rational scale = 1) {
  Bernstein<Rational> p{scale};
  for (const auto& [r, m] : roots)
    for (int i = 0; i < m; ++i) p = bernstein_product(p, Bernstein<Rational>{-r, Rational(1 - r)});
  return p;
}

std::string str(const Rational& x) { return x.get_str(); }

// Every listed root r lies in its enclosure, with its multiplicity, in order.
void expect_roots(const Bernstein<Rational>& p, const std::vector<std::pair<Rational, int>>& expected,
                  double tolerance = 1e-12) {
  const std::vector<RootInterval> got = isolate_roots(p, {tolerance});
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    const RootInterval& g = got[i];
    const Rational& r = expected[i].first;
    SCOPED_TRACE("root " + std::to_string(i) + " = " + str(r) + ", enclosure [" + str(g.lo) + ", " + str(g.hi) + "]");
    if (g.exact()) {
      EXPECT_EQ(g.lo, r);
    } else {
      EXPECT_LT(g.lo, r);
      EXPECT_LT(r, g.hi);
    }
    EXPECT_LE(Rational(g.hi - g.lo), Rational(tolerance));
    EXPECT_EQ(g.multiplicity, expected[i].second);
    EXPECT_EQ(g.sign_change(), expected[i].second % 2 == 1);
    if (i > 0) {
      EXPECT_LE(got[i - 1].hi, g.lo);
    }
  }
}

TEST(IsolateRoots, DyadicRootsAreFoundExactly) {
  const auto p = from_roots({{q(1, 4), 1}, {q(1, 2), 1}, {q(3, 4), 1}});
  expect_roots(p, {{q(1, 4), 1}, {q(1, 2), 1}, {q(3, 4), 1}});
  for (const RootInterval& r : isolate_roots(p)) EXPECT_TRUE(r.exact()) << str(r.lo);
}

TEST(IsolateRoots, NonDyadicRootsAreEnclosedWithinTheTolerance) {
  expect_roots(from_roots({{q(1, 3), 1}, {q(2, 3), 1}, {q(1, 5), 1}}), {{q(1, 5), 1}, {q(1, 3), 1}, {q(2, 3), 1}});
  expect_roots(from_roots({{q(1, 3), 1}}), {{q(1, 3), 1}}, 1e-3);
}

TEST(IsolateRoots, EndPointsAreExact) {
  expect_roots(from_roots({{q(0), 1}, {q(1), 1}, {q(1, 3), 1}}), {{q(0), 1}, {q(1, 3), 1}, {q(1), 1}});
  expect_roots(from_roots({{q(0), 2}, {q(2, 7), 1}}), {{q(0), 2}, {q(2, 7), 1}});
}

TEST(IsolateRoots, MultipleRootsCarryTheirMultiplicity) {
  // Non-dyadic double root: only the square-free route isolates it.
  expect_roots(from_roots({{q(1, 3), 2}, {q(7, 10), 1}}), {{q(1, 3), 2}, {q(7, 10), 1}});
  // Dyadic triple root, found by halving.
  expect_roots(from_roots({{q(1, 2), 3}, {q(1, 10), 2}}), {{q(1, 10), 2}, {q(1, 2), 3}});
  expect_roots(from_roots({{q(3, 7), 4}}, q(-2)), {{q(3, 7), 4}});
}

TEST(IsolateRoots, TouchingRootKeepsTheSignAndSimpleRootFlipsIt) {
  // -(t - 1/3)^2 (t - 7/10): positive before 1/3 (two negatives and a minus).
  const auto roots = isolate_roots(from_roots({{q(1, 3), 2}, {q(7, 10), 1}}, q(-1)));
  ASSERT_EQ(roots.size(), 2u);
  EXPECT_EQ(roots[0].sign_before, 1);
  EXPECT_EQ(roots[0].sign_after, 1);
  EXPECT_EQ(roots[1].sign_before, 1);
  EXPECT_EQ(roots[1].sign_after, -1);
}

TEST(IsolateRoots, SignsAtTheEndsDescribeThePolynomialBeyondThem) {
  // t (t - 1/3): left of 0 the product is positive, right of 0 negative.
  const auto roots = isolate_roots(from_roots({{q(0), 1}, {q(1, 3), 1}}));
  ASSERT_EQ(roots.size(), 2u);
  EXPECT_EQ(roots[0].sign_before, 1);
  EXPECT_EQ(roots[0].sign_after, -1);
  EXPECT_EQ(roots[1].sign_after, 1);
}

TEST(IsolateRoots, RootsOutsideTheIntervalAreIgnored) {
  expect_roots(from_roots({{q(-1), 1}, {q(2), 2}, {q(1, 5), 1}}), {{q(1, 5), 1}});
  // A double root just outside [0, 1].
  expect_roots(from_roots({{Rational(1) + q(1, 1000000000), 2}, {q(1, 3), 1}}), {{q(1, 3), 1}});
}

TEST(IsolateRoots, RootsCloserThanTheToleranceAreStillSeparated) {
  const Rational a = q(1, 3), b = a + q(1, 1000000000) * q(1, 1000000);  // 1e-15 apart
  expect_roots(from_roots({{a, 1}, {b, 1}, {q(9, 10), 1}}), {{a, 1}, {b, 1}, {q(9, 10), 1}});
  // And next to a double root, in the square-free route.
  expect_roots(from_roots({{a, 1}, {b, 2}}), {{a, 1}, {b, 2}});
}

TEST(IsolateRoots, ZeroAndConstantPolynomialsHaveNoIsolatedRoots) {
  EXPECT_TRUE(isolate_roots(Bernstein<Rational>{0, 0, 0}).empty());
  EXPECT_TRUE(is_zero(Bernstein<Rational>{0, 0, 0}));
  EXPECT_TRUE(isolate_roots(Bernstein<Rational>{3, 3, 3}).empty());
  EXPECT_FALSE(is_zero(Bernstein<Rational>{0, 0, 1}));
  EXPECT_EQ(sign_at_start(Bernstein<Rational>{0, 0, -2, 5}), -1);
}

TEST(IsolateRoots, DegreeElevationChangesNothing) {
  const auto p = from_roots({{q(1, 3), 2}, {q(5, 8), 1}});
  expect_roots(bernstein_elevate(bernstein_elevate(p)), {{q(1, 3), 2}, {q(5, 8), 1}});
}

// Random products of linear factors (seeded): every root inside [0, 1] is
// found with its multiplicity, and p evaluated exactly between consecutive
// enclosures has the signs the result claims.
TEST(IsolateRoots, RandomProductsOfFactors) {
  std::mt19937_64 rng(20240601);
  std::uniform_int_distribution<long> num(-200, 1200), mult(1, 3), count(1, 5);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<std::pair<Rational, int>> factors;
    const int k = static_cast<int>(count(rng));
    for (int i = 0; i < k; ++i) {
      const Rational r = q(num(rng), 1000);
      if (std::none_of(factors.begin(), factors.end(), [&](const auto& f) { return f.first == r; }))
        factors.push_back({r, static_cast<int>(mult(rng))});
    }
    const Bernstein<Rational> p = from_roots(factors, trial % 2 ? q(-3, 2) : q(5));
    std::vector<std::pair<Rational, int>> inside;
    for (const auto& f : factors)
      if (f.first >= 0 && f.first <= 1) inside.push_back(f);
    std::sort(inside.begin(), inside.end());
    SCOPED_TRACE("trial " + std::to_string(trial));
    expect_roots(p, inside);
    const auto roots = isolate_roots(p);
    for (std::size_t i = 0; i + 1 < roots.size(); ++i) {
      const Rational between = (roots[i].hi + roots[i + 1].lo) / 2;
      if (between == roots[i].hi) continue;  // touching enclosures: no room between
      EXPECT_EQ(sgn(bernstein_eval(p, between)), roots[i].sign_after) << "between roots " << i << " and " << i + 1;
      EXPECT_EQ(roots[i].sign_after, roots[i + 1].sign_before);
    }
  }
}

TEST(RationalToDouble, RoundsToNearestAndOutwards) {
  const Rational third = q(1, 3);
  EXPECT_EQ(nearest_double(third), 1.0 / 3.0);
  EXPECT_LT(Rational(double_below(third)), third);
  EXPECT_GT(Rational(double_above(third)), third);
  EXPECT_EQ(std::nextafter(double_below(third), 1.0), double_above(third));
  EXPECT_EQ(nearest_double(q(-1, 3)), -1.0 / 3.0);
  EXPECT_EQ(double_below(Rational(0.1)), 0.1);
  EXPECT_EQ(double_above(Rational(0.1)), 0.1);
}

}  // namespace
}  // namespace cmr
