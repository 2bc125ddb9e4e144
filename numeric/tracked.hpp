#pragma once
// Internal to cmr's libraries: a library user includes `bezierize/analyze.hpp`
// or `region/region.hpp`.
// Tracked: a double with a certified error bound (the rules of Bounded,
// numeric/bounded.hpp) that stays *exactly zero* while every operation so
// far was exact. Font outlines and many CAD inputs are small dyadic numbers
// (integer font units, integer knots, implied midpoints): the blossom, the
// end terms and the quadratic eta/lambda of such data are exact in double,
// and an exact 0 (a straight segment, a line's zero curvature, a C0 node's
// parallel tangents) is then *known* to be 0 without GMP. Bounded cannot say
// that: it charges a rounding to every operation, so an exact zero only ever
// comes out as "uncertain" and sends the decision to rational arithmetic.
//
// Exactness of one operation on exact operands is tested with error-free
// transformations: a + b by TwoSum (the rounding error is representable, so
// err == 0 is exact), a * b by fma(a, b, -r) == 0, a / b by fma(r, b, -a) ==
// 0 (the remainder of a rounded quotient is representable). Underflow is
// excluded by requiring results (and dividends) of magnitude >= 2^-900 or an
// exact 0, and overflow by finiteness; anything else is charged as Bounded
// charges it. So e == 0 implies v is the exact value, and otherwise
// |exact - v| <= e as for Bounded (the bound of an exact operation is 0,
// never larger than Bounded's, and the rules are monotone in the operands'
// bounds: v is always computed by the same double operations as Bounded's,
// only e differs). A Tracked converts to the Bounded with the same v and e,
// which every Bounded consumer (certain_sign, the piece rules) reads as is.
#include <cmath>
#include <limits>
#include <vector>

#include "numeric/bounded.hpp"
#include "numeric/scalar.hpp"

namespace cmr {

struct Tracked {
  double v = 0;  ///< value
  double e = 0;  ///< bound on |exact - v|; 0: v is exact

  Tracked() = default;
  Tracked(double value) : v(value), e(0) {}  // NOLINT(google-explicit-constructor): inputs convert implicitly
  Tracked(double value, double err) : v(value), e(err) {}
  Bounded bounded() const { return {v, e}; }
  bool exact() const { return e == 0; }

  static constexpr double kSafe = 0x1p-900;  ///< below this magnitude an operation is not called exact

  friend Tracked operator+(Tracked a, Tracked b) {
    const double r = a.v + b.v;
    if (a.e == 0 && b.e == 0 && std::isfinite(r)) {
      const double bb = r - a.v;
      if ((a.v - (r - bb)) + (b.v - bb) == 0) return {r, 0};  // TwoSum: the rounding error is 0
    }
    return {r, a.e + b.e + Bounded::kRound * std::fabs(r)};
  }
  friend Tracked operator-(Tracked a) { return {-a.v, a.e}; }
  friend Tracked operator-(Tracked a, Tracked b) { return a + (-b); }
  friend Tracked operator*(Tracked a, Tracked b) {
    const double r = a.v * b.v;
    if (a.e == 0 && b.e == 0) {
      if (r == 0 ? (a.v == 0 || b.v == 0) : (std::fabs(r) >= kSafe && std::isfinite(r) && std::fma(a.v, b.v, -r) == 0))
        return {r, 0};
    }
    return {r, std::fabs(a.v) * b.e + std::fabs(b.v) * a.e + a.e * b.e + Bounded::kRound * std::fabs(r) +
                   Bounded::kTiny};
  }
  friend Tracked operator/(Tracked a, Tracked b) {
    const double r = a.v / b.v;
    if (a.e == 0 && b.e == 0 && b.v != 0) {
      if (a.v == 0) return {0.0, 0};
      if (std::isfinite(r) && std::fabs(r) >= kSafe && std::fabs(a.v) >= kSafe && std::fma(-r, b.v, a.v) == 0)
        return {r, 0};
    }
    const double margin = std::fabs(b.v) - b.e;
    if (!(margin > 0)) return {r, std::numeric_limits<double>::infinity()};
    return {r, (a.e + std::fabs(r) * b.e) / margin + Bounded::kRound * std::fabs(r) + Bounded::kTiny};
  }
  Tracked& operator+=(Tracked b) { return *this = *this + b; }
  Tracked& operator-=(Tracked b) { return *this = *this - b; }
  Tracked& operator*=(Tracked b) { return *this = *this * b; }

  Tracked half() const {
    if (v == 0 && e == 0) return *this;
    if (e == 0 && std::fabs(v) >= kSafe) return {0.5 * v, 0};  // exact in binary
    return {0.5 * v, 0.5 * e + Bounded::kTiny};
  }
};

inline int certain_sign(const Tracked& x) { return certain_sign(x.bounded()); }

template <>
struct Scalar<Tracked> {
  static constexpr bool exact = false;
  static Tracked ratio(Int128 num, Int128 den) {
    // Binomial ratios: num and den below 2^53 are exact doubles.
    constexpr Int128 kExactInt = Int128(1) << 53;
    if (num < kExactInt && den < kExactInt)
      return Tracked(static_cast<double>(num)) / Tracked(static_cast<double>(den));
    const double v = static_cast<double>(num) / static_cast<double>(den);
    return {v, 4 * Bounded::kRound * v};
  }
  static Tracked half(const Tracked& x) { return x.half(); }
  static int sign(const Tracked& x) { return certain_sign(x); }
};

/// Bernstein coefficients as Bounded (same values and bounds).
template <class C>
std::vector<Bounded> to_bounded(const C& c) {
  std::vector<Bounded> out;
  out.reserve(c.size());
  for (const Tracked& x : c) out.push_back(x.bounded());
  return out;
}

/// True when every coefficient is exactly 0 (the zero polynomial, certainly).
template <class C>
bool certainly_zero(const C& c) {
  for (const Tracked& x : c)
    if (!(x.v == 0 && x.e == 0)) return false;
  return true;
}

}  // namespace cmr
