// De Casteljau halving at t = 1/2 of Bounded coefficients held as two double
// rows (values v[], bounds e[]) instead of an array of Bounded.
//
// bernstein_halve<Bounded> with HalfMean computes each new coefficient as
// (a + b).half() (bounded.hpp):
//     s = a.v + b.v,  f = a.e + b.e + U |s|,
//     (s, f) if s == 0 and f == 0 (an exact zero stays exact), else (0.5 s, 0.5 f + tiny).
// Here the same operations run on the same operands in the same order, with
// the exact-zero case a select instead of a branch, so the rows hold bit for
// bit what bernstein_halve<Bounded> gives (0.5 s = s when s is a zero of
// either sign; test HalveBounded.BitIdenticalToBernsteinHalve) and every bound
// derived for that arithmetic holds unchanged. Row-wise, the value and bound
// loops vectorise (the array of pairs interleaved them).
#pragma once
// Internal to cmr's libraries: a library user includes `bezierize/analyze.hpp`
// or `region/region.hpp`.

#include <cmath>

#include "numeric/bounded.hpp"

namespace cmr {

/// In: v[0..n), e[0..n) the coefficients. Out: v, e the left half, rv, re the
/// right half. wv, we: n doubles of work space each. With N > 0 (N == n),
/// the same operations in the same order with the sizes known at compile
/// time, so that the rows unroll into straight-line code (halve_bounded_rows
/// picks it for the common sizes).
template <int N = 0>
inline void halve_bounded_rows_n(double* v, double* e, int n, double* rv, double* re, double* wv, double* we) {
  if constexpr (N > 0) n = N;
  for (int i = 0; i < n; ++i) {
    wv[i] = v[i];
    we[i] = e[i];
  }
  rv[n - 1] = wv[n - 1];
  re[n - 1] = we[n - 1];
  for (int r = 1; r < n; ++r) {
    const int m = n - r;
    for (int i = 0; i < m; ++i) {
      const double s = wv[i] + wv[i + 1];
      const double f = we[i] + we[i + 1] + Bounded::kRound * std::fabs(s);
      const bool exact_zero = s == 0 && f == 0;
      wv[i] = 0.5 * s;
      we[i] = exact_zero ? f : 0.5 * f + Bounded::kTiny;
    }
    v[r] = wv[0];
    e[r] = we[0];
    rv[m - 1] = wv[m - 1];
    re[m - 1] = we[m - 1];
  }
}

inline void halve_bounded_rows(double* v, double* e, int n, double* rv, double* re, double* wv, double* we) {
  // Lambda's coefficients per piece, cubic 6, quartic 10 (degree 9's 30
  // unrolled were 7 % slower in its boundary zoom: more code than it saves).
  switch (n) {
    case 6: return halve_bounded_rows_n<6>(v, e, n, rv, re, wv, we);
    case 10: return halve_bounded_rows_n<10>(v, e, n, rv, re, wv, we);
    default: return halve_bounded_rows_n<0>(v, e, n, rv, re, wv, we);
  }
}

}  // namespace cmr
