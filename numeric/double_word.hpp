#pragma once
// Internal to cmr's libraries: a library user includes `bezierize/analyze.hpp`
// or `region/region.hpp`.
// DoubleWord: a double-word number (hi + lo, about 106 bits) carrying a
// certified bound on its absolute error, the rules of Bounded
// (numeric/bounded.hpp) at double-double precision. It is the second
// filter of a joint's curvature (bezierize/analyze.cpp): where Tracked's
// 2^-40 relative bound is too loose (coordinates large beside the local
// differences, as on a long random walk), the double-word value usually
// still pins the exact value's truncation to a double, which is all the
// exact path reports (mpq_get_d truncates), so the printed number is the
// exact path's, byte for byte, without GMP.
//
// Every bound is a posteriori and elementary; nothing rests on a published
// double-word error constant. The value hi + lo is an exact real number;
// each operation computes its result from error-free transformations
// (TwoSum, and TwoProd through fma) plus a few ordinary double operations,
// and charges each of those with 2u times its computed magnitude (u = 2^-53:
// a rounded sum or product is within u of its computed value; the factor 2
// absorbs the roundings of the bound arithmetic itself, as Bounded's kRound
// does), the dropped term lo*lo by its magnitude, and kTiny per product for
// underflow. Division is checked by its residual: z ~ x / y is formed
// cheaply, then x - z y is computed with its own bound and
// |x/y - z| <= (|x - z y| + bound) / |y|. Input errors propagate as in
// Bounded. Every operation requires operands and results of magnitude in
// [2^-900, 2^900] or exact zeros (TwoSum and TwoProd are then exact);
// anything else makes the bound infinite, and a caller that sees it falls
// back to exact arithmetic.
#include <cmath>
#include <limits>
#include <optional>

#include "numeric/bounded.hpp"
#include "numeric/scalar.hpp"

namespace cmr {

struct DoubleWord {
  double hi = 0, lo = 0;  ///< the value hi + lo (|lo| <= ulp(hi) / 2 after every operation)
  double e = 0;           ///< bound on |exact - (hi + lo)|; infinity: no bound

  static constexpr double kRound = 0x1p-52;  ///< 2u per rounded double operation
  static constexpr double kTiny = 0x1p-1020;  ///< absolute slack for one product's underflow
  static constexpr double kMin = 0x1p-900, kMax = 0x1p900;  ///< magnitudes where TwoSum/TwoProd are exact
  /// Factor on every bound expression: it absorbs the (at most ~10) roundings
  /// of the bound arithmetic of one operation, each within u.
  static constexpr double kSlack = 1 + 0x1p-40;

  DoubleWord() = default;
  DoubleWord(double v) : hi(v), lo(0), e(in_range(v) ? 0 : kUnknown) {}  // NOLINT: inputs convert implicitly

  /// An upper bound of |hi + lo|.
  double magnitude() const { return std::fabs(hi) + std::fabs(lo); }
  bool bounded() const { return e < kUnknown; }

  friend DoubleWord operator-(const DoubleWord& a) { return {-a.hi, -a.lo, a.e}; }
  friend DoubleWord operator+(const DoubleWord& a, const DoubleWord& b) {
    DoubleWord z = add(a, b);
    z.e = finish(z, a.e + b.e + z.e);
    return z;
  }
  friend DoubleWord operator-(const DoubleWord& a, const DoubleWord& b) { return a + (-b); }
  friend DoubleWord operator*(const DoubleWord& a, const DoubleWord& b) {
    DoubleWord z = mul(a, b);
    z.e = finish(z, a.magnitude() * b.e + b.magnitude() * a.e + a.e * b.e + z.e);
    return z;
  }
  friend DoubleWord operator/(const DoubleWord& a, const DoubleWord& b) {
    // |b| >= margin > 0 for the exact divisor and for b's value itself.
    const double margin = std::fabs(b.hi) - std::fabs(b.lo) - b.e;
    if (!(margin > 0) || !a.bounded() || !b.bounded()) return unknown();
    const double q1 = a.hi / b.hi;
    const DoubleWord r = add(a, -mul(DoubleWord(q1), b));
    DoubleWord z = two_sum(q1, r.hi / b.hi);
    // The residual of z itself, with its rounding bound: |a/b - z| <= (|a - z b| + bound) / |b|.
    const DoubleWord zb = mul(z, b);
    const DoubleWord res = add(a, -zb);
    const double own = (res.magnitude() + res.e + zb.e) / margin * kSlack;
    // Input errors: |A/B - a/b| <= (ea + |a/b| eb) / (|B| margin), |a/b| <= |z| + own.
    const double in = (a.e + (z.magnitude() + own) * b.e) / margin * kSlack;
    z.e = finish(z, own + in);
    return z;
  }
  DoubleWord& operator+=(const DoubleWord& b) { return *this = *this + b; }
  DoubleWord& operator-=(const DoubleWord& b) { return *this = *this - b; }
  DoubleWord& operator*=(const DoubleWord& b) { return *this = *this * b; }

  DoubleWord half() const { return *this * DoubleWord(0.5); }

  /// The exact value's truncation toward zero to a double (what mpq_get_d
  /// returns for it), when the enclosure [hi + lo - e, hi + lo + e] lies
  /// inside one truncation cell and away from zero; nullopt otherwise.
  std::optional<double> truncated() const {
    if (!bounded() || hi == 0) return std::nullopt;
    // Work with the magnitude: H = |hi|, L = lo with hi's sign removed.
    const double H = std::fabs(hi), L = std::signbit(hi) ? -lo : lo;
    const double up = std::nextafter(H, kUnknown) - H;  // exact: powers of two apart
    const double down = H - std::nextafter(H, 0.0);
    // fl(x) < bound (1 - 2^-20) implies x < bound for the x <= 2 max(L, e) at hand.
    constexpr double kShrink = 1 - 0x1p-20;
    double t = 0;
    if (L >= e) {  // the enclosure is >= H: its truncation is H if it stays below H + up
      if (!(L + e < up * kShrink)) return std::nullopt;
      t = H;
    } else if (-L > e) {  // the enclosure is < H: its truncation is the double below H
      if (!(e - L < down * kShrink)) return std::nullopt;
      t = std::nextafter(H, 0.0);
    } else {
      return std::nullopt;  // H itself inside the enclosure
    }
    if (!(t >= kMin)) return std::nullopt;
    return std::signbit(hi) ? -t : t;
  }

  /// A number with no bound (every sign and truncation unknown).
  static DoubleWord unknown() { return {std::numeric_limits<double>::quiet_NaN(), 0, kUnknown}; }

 private:
  static constexpr double kUnknown = std::numeric_limits<double>::infinity();
  DoubleWord(double h, double l, double err) : hi(h), lo(l), e(err) {}
  static bool in_range(double v) { return v == 0 || (std::fabs(v) >= kMin && std::fabs(v) <= kMax); }

  // Error-free: s + t == a + b exactly (no overflow in range).
  static DoubleWord two_sum(double a, double b) {
    const double s = a + b, bb = s - a;
    return {s, (a - (s - bb)) + (b - bb), 0};
  }
  // The rounding bound of a result in .e, operands taken as exact.
  static DoubleWord add(const DoubleWord& a, const DoubleWord& b) {
    const DoubleWord s = two_sum(a.hi, b.hi), t = two_sum(a.lo, b.lo);
    const double c = s.lo + t.hi;  // rounded: within u |c|
    const DoubleWord v = two_sum(s.hi, c);
    const double w = v.lo + t.lo;  // rounded: within u |w|
    DoubleWord z = two_sum(v.hi, w);
    z.e = kRound * (std::fabs(c) + std::fabs(w));
    return z;
  }
  static DoubleWord mul(const DoubleWord& a, const DoubleWord& b) {
    const double p = a.hi * b.hi, pl = std::fma(a.hi, b.hi, -p);  // exact: |p| >= 2^-900 or an operand 0
    const double t1 = a.hi * b.lo, t2 = a.lo * b.hi, t3 = a.lo * b.lo;  // t3 dropped
    const double c = t1 + t2, c2 = pl + c;
    DoubleWord z = two_sum(p, c2);
    z.e = kRound * (std::fabs(t1) + std::fabs(t2) + std::fabs(c) + std::fabs(c2)) + 2 * std::fabs(t3) + 4 * kTiny;
    return z;
  }
  // The bound `err` (input errors plus this operation's roundings) charged
  // once more for its own arithmetic, or infinite outside the safe range.
  static double finish(const DoubleWord& z, double err) {
    if (!in_range(z.hi) || !std::isfinite(err)) return kUnknown;
    return err * kSlack;
  }
};

/// -1, 0, +1 where the bound decides it, else kSignUnknown (bounded.hpp).
inline int certain_sign(const DoubleWord& x) {
  if (!x.bounded()) return kSignUnknown;
  const double m = std::fabs(x.hi) - std::fabs(x.lo);
  if (m > x.e * DoubleWord::kSlack) return x.hi > 0 ? 1 : -1;
  if (x.hi == 0 && x.lo == 0 && x.e == 0) return 0;
  return kSignUnknown;
}

template <>
struct Scalar<DoubleWord> {
  static constexpr bool exact = false;
  static DoubleWord ratio(Int128 num, Int128 den) {
    constexpr Int128 kExactInt = Int128(1) << 53;
    if (num < kExactInt && den < kExactInt)
      return DoubleWord(static_cast<double>(num)) / DoubleWord(static_cast<double>(den));
    return DoubleWord::unknown();  // not exact in double: no filter needed for such degrees
  }
  static DoubleWord half(const DoubleWord& x) { return x.half(); }
  static int sign(const DoubleWord& x) { return certain_sign(x); }
};

}  // namespace cmr
