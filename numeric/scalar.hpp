#pragma once
// Internal to cmr's libraries: a library user includes `bezierize/analyze.hpp`
// or `region/region.hpp`.
// What the generic algorithms need from a scalar type beyond + - * /:
// exact integer ratios (binomial weights), halving, and a sign decision.
//   double   : plain floating point (pointwise reference, tests)
//   Bounded  : double with a certified error bound (numeric/bounded.hpp)
//   Rational : exact (GMP), the fallback that makes every decision exact
/// Marks translation units that see the internal scalar types (GMP, __int128);
/// tests/region/public_headers_test.cpp checks the public headers do not.
#define CMR_INTERNAL_SCALAR_TYPES 1
#include <cstdint>
#include <string>

#include "numeric/bounded.hpp"
#include "numeric/exact.hpp"

namespace cmr {

__extension__ typedef unsigned __int128 Int128;

/// Binomial coefficient C(n, k), exact for n <= 120 (fits 128 bits).
Int128 binomial(int n, int k);

template <class T>
struct Scalar;

template <>
struct Scalar<double> {
  static constexpr bool exact = false;
  static double ratio(Int128 num, Int128 den) {
    return static_cast<double>(num) / static_cast<double>(den);
  }
  static double half(double x) { return 0.5 * x; }
  static int sign(double x) { return (x > 0) - (x < 0); }
};

template <>
struct Scalar<Bounded> {
  static constexpr bool exact = false;
  // num and den are rounded once each to double, then divided: three
  // roundings, charged as 4 U |v|.
  static Bounded ratio(Int128 num, Int128 den) {
    const double v = static_cast<double>(num) / static_cast<double>(den);
    return {v, 4 * Bounded::kRound * v};
  }
  static Bounded half(const Bounded& x) { return x.half(); }
  static int sign(const Bounded& x) { return certain_sign(x); }
};

mpz_class to_mpz(Int128 v);

template <>
struct Scalar<Rational> {
  static constexpr bool exact = true;
  static Rational ratio(Int128 num, Int128 den) {
    Rational r(to_mpz(num), to_mpz(den));
    r.canonicalize();
    return r;
  }
  static Rational half(const Rational& x) { return cmr::half(x); }
  static int sign(const Rational& x) { return sgn(x); }
};

}  // namespace cmr
