// eval_poly (region/box_eval.hpp) against exact rational evaluation: the
// exact value of the polynomial (its double coefficients as rationals) at
// points of the box (corners, centre and random points, all exact) must lie
// in the returned enclosure [v - e, v + e]. Boxes of radius zero make the
// rounding part of the bound the whole bound, and polynomials expanded from
// (x - a)^3-like products near the box make the Taylor shift cancel.
#include "region/box_eval.hpp"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cstdint>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "numeric/exact.hpp"

namespace cmr::backend::box_eval {
namespace {

template <std::size_t K>
Rational exact_value(const std::array<double, K>& c, const Rational& x, const Rational& y) {
  Rational sum = 0;
  for (std::size_t m = 0; m < K; ++m) {
    Rational term = Rational(c[m]);
    for (int i = 0; i < kPoly3ExpX[m]; ++i) term *= x;
    for (int i = 0; i < kPoly3ExpY[m]; ++i) term *= y;
    sum += term;
  }
  return sum;
}

// A polynomial of the kind the region's pieces have: random coefficients of
// mixed magnitudes, or an expanded product that nearly vanishes at (a, b).
template <std::size_t K>
std::array<double, K> random_poly(std::mt19937_64& rng, int trial, double a, double b) {
  std::uniform_real_distribution<double> mant(-1, 1);
  std::uniform_int_distribution<int> expo(-30, 30);
  std::array<double, K> c{};
  if (K == kPoly3Terms && trial % 3 == 1) {
    // (x - a)^2 (y - b) + s (x - a) + t: cancels near (a, b).
    const double s = std::ldexp(mant(rng), -40), t = std::ldexp(mant(rng), -50);
    c[0] = -a * a * b - s * a + t;
    c[1] = 2 * a * b + s;           // x
    c[2] = a * a;                   // y
    c[3] = -b;                      // x^2
    c[4] = -2 * a;                  // xy
    c[7] = 1;                       // x^2 y
    return c;
  }
  for (std::size_t m = 0; m < K; ++m)
    c[m] = trial % 5 == 0 && m % 3 == 2 ? 0.0 : std::ldexp(mant(rng), trial % 2 ? expo(rng) / 10 : expo(rng));
  return c;
}

template <std::size_t K>
void check_enclosures(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::uniform_int_distribution<int> expo(-12, 2);
  int checked = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const double cx = std::ldexp(unit(rng), expo(rng)), cy = std::ldexp(unit(rng), expo(rng));
    // Radii: zero (the rounding bound alone), tiny, or a fair part of the centre.
    const int kind = trial % 4;
    const double rx = kind == 0 ? 0.0 : std::ldexp(std::fabs(unit(rng)), kind == 1 ? -40 : expo(rng) - 2);
    const double ry = kind == 0 ? 0.0 : std::ldexp(std::fabs(unit(rng)), kind == 1 ? -40 : expo(rng) - 2);
    const auto c = random_poly<K>(rng, trial, cx + rx * unit(rng), cy + ry * unit(rng));
    const Monomials box(cx, cy, rx, ry);
    const Bounded b = eval_poly(c, box);
    ASSERT_TRUE(std::isfinite(b.v) && std::isfinite(b.e) && b.e >= 0) << "trial " << trial;
    const Rational v(b.v), e(b.e);
    for (int p = 0; p < 12; ++p) {
      // Corners, the centre, then random points: u, w in [-1, 1] exactly.
      const double u = p < 4 ? (p & 1 ? 1.0 : -1.0) : p == 4 ? 0.0 : unit(rng);
      const double w = p < 4 ? (p & 2 ? 1.0 : -1.0) : p == 4 ? 0.0 : unit(rng);
      const Rational x = Rational(cx) + Rational(rx) * Rational(u), y = Rational(cy) + Rational(ry) * Rational(w);
      const Rational exact = exact_value(c, x, y);
      const Rational dist = abs(exact - v);
      ASSERT_LE(dist, e) << "K " << K << " trial " << trial << " point " << p << ": centre (" << cx << ", " << cy
                         << ") radii (" << rx << ", " << ry << "), value " << b.v << " +- " << b.e
                         << ", exact " << exact.get_d();
      ++checked;
      if (kind == 0) break;  // a point: one position
    }
    // The point form at the centre encloses the exact value there too.
    const Bounded pt = eval_poly(c, Monomials(cx, cy));
    ASSERT_LE(abs(exact_value(c, Rational(cx), Rational(cy)) - Rational(pt.v)), Rational(pt.e)) << "trial " << trial;
  }
  EXPECT_GT(checked, 600);
}

TEST(BoxEval, CubicBoxEnclosesExactValues) { check_enclosures<kPoly3Terms>(0xB0C5E7A1); }
TEST(BoxEval, AffineBoxEnclosesExactValues) { check_enclosures<3>(0x5EED0003); }

// The bound is not vacuous: at a zero-radius box it is the rounding bound,
// a few units of the magnitudes involved, and the value is the exact one
// when everything is exactly representable.
TEST(BoxEval, BoundIsTightOnExactData) {
  std::array<double, kPoly3Terms> c{};
  for (int m = 0; m < kPoly3Terms; ++m) c[m] = m + 1;
  const Bounded b = eval_poly(c, Monomials(0.5, 0.25, 0, 0));
  const double exact = exact_value(c, Rational(0.5), Rational(0.25)).get_d();
  EXPECT_EQ(b.v, exact);
  EXPECT_LT(b.e, 1e-13);
  // A box: the bound covers the variation and is no more than the sum of the
  // Taylor terms' magnitudes (with slack).
  const Bounded w = eval_poly(c, Monomials(0.5, 0.25, 0.125, 0.0625));
  EXPECT_GT(w.e, 0.125);   // the x term alone varies by 2 * 0.125 around the centre
  EXPECT_LT(w.e, 10.0);
}

// Structural zeros stay exact: an all-zero polynomial evaluates to 0 +- 0.
TEST(BoxEval, ZeroPolynomialIsExact) {
  const std::array<double, kPoly3Terms> c{};
  const Bounded b = eval_poly(c, Monomials(0.3, -0.7, 0.1, 0.2));
  EXPECT_EQ(b.v, 0.0);
  EXPECT_EQ(b.e, 0.0);
}

// eval_polys gives each polynomial eval_poly's value and bound bit for bit,
// at every SIMD level this CPU has, for 1 to 9 polynomials at once (whole
// groups of four and two, and the rest), all-zero polynomials among them
// (exact zeros) and rows read through arbitrary pointers (the block proof's
// ends and a piece's inner coefficients). The comparison is of bits, so a
// lane that rounds once differently (a fused multiply-add, another order)
// fails it.
TEST(BoxEval, ManyAtOnceIsEvalPolyBitForBit) {
  std::mt19937_64 rng(0xE7A1F0B5);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::uniform_int_distribution<int> expo(-12, 2);
  int compared = 0;
  for (const SimdLevel level : {SimdLevel::scalar, SimdLevel::sse2, SimdLevel::avx2}) {
    if (!simd_available(level)) continue;
    for (int trial = 0; trial < 300; ++trial) {
      const double cx = std::ldexp(unit(rng), expo(rng)), cy = std::ldexp(unit(rng), expo(rng));
      const double rx = trial % 7 == 0 ? 0.0 : std::ldexp(std::fabs(unit(rng)), expo(rng) - 2);
      const double ry = std::ldexp(std::fabs(unit(rng)), expo(rng) - 2);
      const Monomials box(cx, cy, rx, ry);
      const int count = 1 + trial % 9;
      std::vector<std::array<double, kPoly3Terms>> polys(static_cast<std::size_t>(count) * 2);
      for (auto& c : polys) c = random_poly<kPoly3Terms>(rng, trial, cx, cy);
      if (trial % 4 == 3) polys[static_cast<std::size_t>(trial) % polys.size()] = {};
      // Every other polynomial of the vector, in reverse: rows at arbitrary places.
      std::vector<const std::array<double, kPoly3Terms>*> rows;
      for (int i = count - 1; i >= 0; --i) rows.push_back(&polys[static_cast<std::size_t>(2 * i)]);
      std::vector<Bounded> out(static_cast<std::size_t>(count));
      eval_polys(level, rows.data(), count, box, out.data());
      for (int i = 0; i < count; ++i) {
        const Bounded want = eval_poly(*rows[static_cast<std::size_t>(i)], box);
        const Bounded got = out[static_cast<std::size_t>(i)];
        ASSERT_EQ(std::bit_cast<std::uint64_t>(got.v), std::bit_cast<std::uint64_t>(want.v))
            << simd_name(level) << " trial " << trial << " polynomial " << i;
        ASSERT_EQ(std::bit_cast<std::uint64_t>(got.e), std::bit_cast<std::uint64_t>(want.e))
            << simd_name(level) << " trial " << trial << " polynomial " << i;
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 1500);
}

}  // namespace
}  // namespace cmr::backend::box_eval
