#pragma once
// Internal to cmr's libraries: a library user includes `bezierize/analyze.hpp`
// or `region/region.hpp`.
// A double carrying a rigorous bound on its absolute error: the certified
// floating-point path of the classifier.
//
// Every operation returns fl(result) and a bound e with |exact - value| <= e,
// where "exact" is the same expression evaluated in exact arithmetic on the
// exact inputs. Rules (u = 2^-53, the unit roundoff; we charge U = 2u per
// rounding, which leaves a factor-2 slack for the rounding of the bound
// arithmetic itself over chains shorter than 2^40 operations):
//   a +- b : e = ea + eb + U|v|
//   a * b  : e = |a|eb + |b|ea + ea eb + U|v| + tiny     (tiny covers underflow)
//   a / b  : e = (ea + |v| eb) / (|b| - eb) + U|v| + tiny, infinite if |b| <= eb
// A sign is certain when |v| > e, and a value with bound 0 is exact (so an
// exact zero is known to be zero); otherwise the caller falls back to exact
// rational arithmetic. NaN and infinity make the bound non-finite and every
// sign uncertain, which sends the computation to the exact path.
#include <cmath>
#include <limits>

namespace cmr {

struct Bounded {
  static constexpr double kRound = 0x1p-52;    // U: 2u per rounding
  static constexpr double kTiny = 0x1p-1020;   // absolute slack for underflow

  double v = 0;  ///< value
  double e = 0;  ///< bound on |exact - v|

  Bounded() = default;
  /// An exact double (an input: a control point coordinate, a knot).
  Bounded(double value) : v(value), e(0) {}  // NOLINT(google-explicit-constructor): inputs convert implicitly
  Bounded(double value, double err) : v(value), e(err) {}

  friend Bounded operator+(Bounded a, Bounded b) {
    const double r = a.v + b.v;
    return {r, a.e + b.e + kRound * std::fabs(r)};
  }
  friend Bounded operator-(Bounded a, Bounded b) {
    const double r = a.v - b.v;
    return {r, a.e + b.e + kRound * std::fabs(r)};
  }
  friend Bounded operator-(Bounded a) { return {-a.v, a.e}; }
  friend Bounded operator*(Bounded a, Bounded b) {
    const double r = a.v * b.v;
    return {r, std::fabs(a.v) * b.e + std::fabs(b.v) * a.e + a.e * b.e + kRound * std::fabs(r) + kTiny};
  }
  friend Bounded operator/(Bounded a, Bounded b) {
    const double r = a.v / b.v;
    const double margin = std::fabs(b.v) - b.e;
    if (!(margin > 0)) return {r, std::numeric_limits<double>::infinity()};
    return {r, (a.e + std::fabs(r) * b.e) / margin + kRound * std::fabs(r) + kTiny};
  }
  Bounded& operator+=(Bounded b) { return *this = *this + b; }
  Bounded& operator-=(Bounded b) { return *this = *this - b; }
  Bounded& operator*=(Bounded b) { return *this = *this * b; }

  /// Exactly halving is exact in binary (barring underflow, covered by kTiny).
  Bounded half() const {
    if (v == 0 && e == 0) return *this;  // an exact zero stays exact
    return {0.5 * v, 0.5 * e + kTiny};
  }
};

/// -1, 0, +1, or kSignUnknown when the bound straddles zero.
inline constexpr int kSignUnknown = 2;
inline int certain_sign(const Bounded& x) {
  // The comparison is exact; e already includes every rounding (see above).
  if (std::fabs(x.v) > x.e) return x.v > 0 ? 1 : -1;  // false for NaN: unknown
  if (x.e == 0 && x.v == 0) return 0;                  // an exact zero (a bound of 0 means exact)
  return kSignUnknown;
}

}  // namespace cmr
