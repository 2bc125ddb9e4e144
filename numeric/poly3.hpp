#pragma once
// Internal to cmr's libraries: a library user includes `bezierize/analyze.hpp`
// or `region/region.hpp`.
// Exact bivariate polynomials of total degree <= 3 in the displacement
// (dx, dy) of the moved control point, used as a scalar type by the generic
// lambda/eta code: running lambda_bernstein<Poly3> on Bezier points
// B_i = B0_i + w_i (dx, dy) yields each xi_k as a polynomial in (dx, dy).
//
// Why degree 3 is enough: the hodograph is affine in (dx, dy) with the same
// direction for x and y, so det(q_i, q_j) loses its quadratic term
// (det(d, d) = 0) and eta is affine; g = P'.P' is quadratic; lambda =
// eta' g - (3/2) eta g' is cubic. A product whose degree would exceed 3 is an
// internal error (CMR_CHECK), never a silent truncation.
#include <array>

#include "numeric/scalar.hpp"
#include "spline/errors.hpp"

namespace cmr {

/// Monomials in the order 1, x, y, x^2, xy, y^2, x^3, x^2 y, x y^2, y^3.
inline constexpr int kPoly3Terms = 10;
inline constexpr int kPoly3ExpX[kPoly3Terms] = {0, 1, 0, 2, 1, 0, 3, 2, 1, 0};
inline constexpr int kPoly3ExpY[kPoly3Terms] = {0, 0, 1, 0, 1, 2, 0, 1, 2, 3};

constexpr int poly3_index(int ex, int ey) {
  const int deg = ex + ey;
  return deg * (deg + 1) / 2 + ey;
}

struct Poly3 {
  std::array<Rational, kPoly3Terms> c;  ///< coefficients, all zero by default

  Poly3() = default;
  Poly3(int v) { c[0] = v; }              // NOLINT(google-explicit-constructor): generic code writes T(0)
  Poly3(const Rational& v) { c[0] = v; }  // NOLINT(google-explicit-constructor)
  static Poly3 x() { Poly3 p; p.c[1] = 1; return p; }
  static Poly3 y() { Poly3 p; p.c[2] = 1; return p; }

  friend Poly3 operator+(const Poly3& a, const Poly3& b) {
    Poly3 r;
    for (int i = 0; i < kPoly3Terms; ++i) r.c[i] = a.c[i] + b.c[i];
    return r;
  }
  friend Poly3 operator-(const Poly3& a, const Poly3& b) {
    Poly3 r;
    for (int i = 0; i < kPoly3Terms; ++i) r.c[i] = a.c[i] - b.c[i];
    return r;
  }
  friend Poly3 operator-(const Poly3& a) { return Poly3() - a; }
  friend Poly3 operator*(const Poly3& a, const Poly3& b) {
    Poly3 r;
    for (int i = 0; i < kPoly3Terms; ++i) {
      if (sgn(a.c[i]) == 0) continue;
      for (int j = 0; j < kPoly3Terms; ++j) {
        if (sgn(b.c[j]) == 0) continue;
        const int ex = kPoly3ExpX[i] + kPoly3ExpX[j], ey = kPoly3ExpY[i] + kPoly3ExpY[j];
        CMR_CHECK(ex + ey <= 3);
        r.c[poly3_index(ex, ey)] += a.c[i] * b.c[j];
      }
    }
    return r;
  }
  Poly3& operator+=(const Poly3& b) { return *this = *this + b; }
};

template <>
struct Scalar<Poly3> {
  static constexpr bool exact = false;  // exact, but without ==: bernstein_reduce skips its check
  static Poly3 ratio(Int128 num, Int128 den) { return Poly3(Scalar<Rational>::ratio(num, den)); }
};

}  // namespace cmr
