#pragma once
// Internal to cmr::region and the libraries above it: a library user includes
// `region/region.hpp` (space curves: `region/space_region.hpp`).
// The certified evaluation of one piece coefficient polynomial (poly3.hpp,
// degree 3 or 1 in the displacement) at one pixel's displacement or over a
// box of them: the value with a rigorous bound on its distance to the exact
// value of the polynomial (its rounded coefficients' exact rational values
// at the exact displacement, as region_setup.hpp's error model states).
// Shared by the CPU region backend's pixels and block proofs (region.cpp, block.cpp);
// tested against exact rational evaluation (tests/region/box_eval_test.cpp).
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "numeric/bounded.hpp"
#include "numeric/poly3.hpp"
#include "region/pixel_simd.hpp"
#include "region/region_setup.hpp"

namespace cmr::backend::box_eval {

// The monomials of poly3.hpp at the displacement of one pixel (a point), or
// over the displacements of a block of pixels (a box c + [-r, r]).
//
// Point: P = sum c_m mu_m is evaluated directly; its error is at most
// kPolyErrorUnits u sum |c_m| |mu_m| (see region.hpp for the count).
// Box: P is expanded around the centre, P(c + h) = sum_st D_st h_x^s h_y^t
// with Taylor coefficients D_st = sum_m c_m T[st][m],
// T[st][m] = C(a_m, s) C(b_m, t) c_x^(a_m - s) c_y^(b_m - t); then over the box
//     |P - D_00| <= sum_{st != 00} |D_st| r_x^s r_y^t,
// and each D_st carries its rounding, kPolyErrorUnits u sum |c_m| |T[st][m]|.
// Expanding at the centre avoids the cancellation that makes a term-by-term
// interval bound useless away from the moved point.
// The (st, m) pairs with T[st][m] possibly non-zero (s <= a_m, t <= b_m),
// listed by m: fixed at compile time, so the box evaluation below unrolls
// into straight-line code.
struct PairTable {
  uint8_t st[35], m[35];
  uint8_t ex[35], ey[35];  // a_m - s, b_m - t: the centre's powers in T[st][m]
  double binom[35];        // C(a_m, s) C(b_m, t)
};
constexpr PairTable pair_table() {
  PairTable t{};
  int n = 0;
  for (int m = 0; m < kPoly3Terms; ++m)
    for (int st = 0; st < kPoly3Terms; ++st)
      if (kPoly3ExpX[st] <= kPoly3ExpX[m] && kPoly3ExpY[st] <= kPoly3ExpY[m]) {
        t.st[n] = static_cast<uint8_t>(st);
        t.m[n] = static_cast<uint8_t>(m);
        t.ex[n] = static_cast<uint8_t>(kPoly3ExpX[m] - kPoly3ExpX[st]);
        t.ey[n] = static_cast<uint8_t>(kPoly3ExpY[m] - kPoly3ExpY[st]);
        constexpr int binom[4][4] = {{1, 0, 0, 0}, {1, 1, 0, 0}, {1, 2, 1, 0}, {1, 3, 3, 1}};
        t.binom[n] = binom[kPoly3ExpX[m]][kPoly3ExpX[st]] * binom[kPoly3ExpY[m]][kPoly3ExpY[st]];
        ++n;
      }
  return t;
}
inline constexpr PairTable kPairTable = pair_table();

struct Monomials {
  // T[st][m] is non-zero only for s <= a_m and t <= b_m: 35 pairs, listed by m.
  static constexpr int kPairs = 35;
  bool point = true;
  double v[kPoly3Terms];                // point: mu_m
  double a[kPoly3Terms];                // point: |mu_m|
  double tv[kPairs], at[kPairs];        // box: T[st][m] and |T[st][m]| of kPairTable's pairs, in its order
  double rpow[kPoly3Terms];             // box: r_x^s r_y^t, rounded up
  double rw[kPoly3Terms];               // box: rpow[st] (1 + 8 U) for st >= 1 (the weight of |D_st|)
  double g[kPoly3Terms];                // box: G_m = sum over m's pairs of |T[st][m]| w_st (see eval_poly)
  Monomials(double dx, double dy) {
    const double x2 = dx * dx, xy = dx * dy, y2 = dy * dy;
    const double m[kPoly3Terms] = {1, dx, dy, x2, xy, y2, x2 * dx, x2 * dy, y2 * dx, y2 * dy};
    for (int i = 0; i < kPoly3Terms; ++i) {
      v[i] = m[i];
      a[i] = std::fabs(m[i]);
    }
  }
  Monomials(double cx, double cy, double rx, double ry) : point(false) {
    // Straight-line code: every pair's factors are compile-time constants
    // (kPairTable), so the loops unroll and nothing reads the table at run
    // time (once per block, this was a fifth of the block proof's own time).
    const double px[4] = {1, cx, cx * cx, cx * cx * cx}, py[4] = {1, cy, cy * cy, cy * cy * cy};
#pragma GCC unroll 35
    for (int k = 0; k < kPairs; ++k) {
      // C(a_m, s) C(b_m, t) (an exact small integer) c_x^(a_m - s) c_y^(b_m - t), in the same order as ever.
      tv[k] = kPairTable.binom[k] * px[kPairTable.ex[k]] * py[kPairTable.ey[k]];
      at[k] = std::fabs(tv[k]);
    }
    const double up = 1 + 8 * Bounded::kRound;
    const double xu = rx * up, yu = ry * up;
#pragma GCC unroll 10
    for (int st = 0; st < kPoly3Terms; ++st) {
      double r = 1;
#pragma GCC unroll 3
      for (int k = 0; k < kPoly3ExpX[st]; ++k) r *= xu;
#pragma GCC unroll 3
      for (int k = 0; k < kPoly3ExpY[st]; ++k) r *= yu;
      rpow[st] = r;
      rw[st] = r * (1 + 8 * Bounded::kRound);
    }
    // w_0 = 1, w_st = rpow[st] (1 + 8 U): the weights of the rounding bounds in eval_poly.
#pragma GCC unroll 10
    for (int m = 0; m < kPoly3Terms; ++m) g[m] = 0;
#pragma GCC unroll 35
    for (int k = 0; k < kPairs; ++k) g[kPairTable.m[k]] += at[k] * (kPairTable.st[k] == 0 ? 1.0 : rw[kPairTable.st[k]]);
  }
};

template <std::size_t K>
Bounded eval_poly(const std::array<double, K>& c, const Monomials& m) {
  // prepare_region guarantees that only an exactly zero polynomial rounds to
  // all zeros: structural zeros (the same for every position) stay exact.
  bool zero = true;
  for (std::size_t i = 0; i < K; ++i) zero = zero && c[i] == 0;
  if (zero) return {0.0, 0.0};
  const double units = kPolyErrorUnits * 0.5 * Bounded::kRound;
  if (m.point) {
    double val = 0, mag = 0;
    for (std::size_t i = 0; i < K; ++i) {
      val += c[i] * m.v[i];
      mag += std::fabs(c[i]) * m.a[i];
    }
    return {val, units * mag + 16 * Bounded::kTiny};
  }
  // The bound of the header comment over the box, with w_0 = 1 and
  // w_st = rpow[st] (1 + 8 U) >= r_x^s r_y^t (rpow rounded up; the 8 U cover
  // the rounding of the products |D_st| w_st and of the sum of at most 10
  // non-negative terms, at most 11 u = 5.5 U):
  //     err = units sum_st mag_st w_st + sum_{st != 00} |D_st| w_st + 16 tiny,
  //     mag_st = sum_m |c_m| |T[st][m]|.
  // The rounding part is regrouped by monomial (the same real number):
  //     sum_st mag_st w_st = sum_m |c_m| G_m,  G_m = sum_{(st, m) pairs} |T[st][m]| w_st,
  // with G_m computed once per box (Monomials), so a coefficient costs 10
  // multiply-adds for it instead of 35. Computing G_m (at most 6 products
  // summed) and then sum_m |c_m| G_m (10 products summed) in double takes at
  // most 19 roundings of non-negative terms, a relative error below 19 u =
  // 9.5 U; the factor (1 + 32 U) covers it, and the product with `units`
  // (one more rounding) stays inside the 24 units' slack as before. The D_st
  // are computed as before (bit for bit the same D_00, the same values).
  double d[kPoly3Terms] = {};
  // Pairs are listed by m, and only m < K carry coefficients (K = 3: 5 pairs).
  constexpr int pairs = K == kPoly3Terms ? Monomials::kPairs : 5;
  static_assert(K == kPoly3Terms || K == 3, "polynomials of degree 3 or 1");
#pragma GCC unroll 35
  for (int k = 0; k < pairs; ++k) d[kPairTable.st[k]] += c[kPairTable.m[k]] * m.tv[k];
  double mag = 0;
  for (std::size_t i = 0; i < K; ++i) mag += std::fabs(c[i]) * m.g[i];
  double err = units * (1 + 32 * Bounded::kRound) * mag + 16 * Bounded::kTiny;
  for (std::size_t st = 1; st < K; ++st) err += std::fabs(d[st]) * m.rw[st];
  return {d[0], err};
}

/// eval_poly of the `count` polynomials *c[0], ..., *c[count - 1] of degree 3
/// at once, bit for bit: out[i] is eval_poly(*c[i], m). Over a box at the
/// AVX2 level four polynomials share each instruction (two at SSE2), one per
/// lane, each lane doing eval_poly's operations in its order; a point, or
/// the scalar level, evaluates them one by one (region/box_simd.cpp).
void eval_polys(SimdLevel level, const std::array<double, kPoly3Terms>* const* c, int count, const Monomials& m,
                Bounded* out);

}  // namespace cmr::backend::box_eval
