#pragma once
// Internal to cmr's libraries: a library user includes `bezierize/analyze.hpp`
// or `region/region.hpp`.
// Exact rational arithmetic (GMP) for the classifier's fallback path. Every
// double is a dyadic rational, so the exact value of any expression of +, -,
// *, / on double inputs is an mpq_class. Sign tests on it are exact.
#include <gmpxx.h>

namespace cmr {

using Rational = mpq_class;

inline int certain_sign(const Rational& x) { return sgn(x); }
inline Rational half(const Rational& x) { return Rational(x / 2); }

}  // namespace cmr
