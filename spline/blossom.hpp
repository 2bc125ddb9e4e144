#pragma once
// The blossom (polar form) of a B-spline: the one primitive of cmr.
//
// Polar-form knots (Ramshaw 1989): a degree-d B-spline with m control points has
// knots u_0..u_{m+d-2} and P_i = f(u_i, ..., u_{i+d-1}), where f is the
// symmetric multi-affine blossom of the curve's piece on the span at hand.
// Span j is [u_j, u_{j+1}] for j = d-1 .. m-2; it is influenced by the d+1
// points P_{j-d+1} .. P_{j+1}.
//
// Everything else is the blossom evaluated at particular arguments:
//   evaluation          C(t)            = f(t, ..., t)
//   Bezier extraction   B_k of [a, b]   = f(a^{d-k}, b^k)
//   derivatives         C^(r)(t)        = d!/(d-r)!/(b-a)^r * sum_i (-1)^{r-i} C(r,i) f(t^{d-r}, a^{r-i}, b^i)
//   influence weights   the blossom of the scalar data e_k (1 at point k).
//
// blossom_span is templated over the point type P and the scalar type S so the
// same code runs in double, with error bounds, and in exact rationals.
#include <vector>

#include "spline/errors.hpp"

namespace cmr {

/// Evaluates f(args[0], ..., args[d-1]) on span j (knot index, d-1 <= j <= m-2).
/// `knots` are the polar knots (size m+d-1), `points` the m control values.
/// Precondition: span j is non-empty (u_j < u_{j+1}); then every
/// denominator u_{i+d-r} - u_{i-1} below spans [u_j, u_{j+1}] and is positive.
/// Works for any args (not only inside the span): the blossom is polynomial.
template <class P, class S>
P blossom_span(const std::vector<S>& knots, const std::vector<P>& points, int degree, int j,
               const S* args) {
  const int d = degree;
  // work[i] holds f(args[0..r), u_{j-d+1+i+?}...) at level r; index i = 0..d maps
  // to control point j-d+1+i.
  std::vector<P> work(points.begin() + (j - d + 1), points.begin() + (j + 2));
  for (int r = 1; r <= d; ++r) {
    const S& t = args[r - 1];
    // After level r, work[i] (i = r..d) = f(t_1..t_r, u_{g}, .., u_{g+d-1-r}) with
    // g = j-d+1+i; combines work[i-1] (has u_{g-1}) and work[i] (has u_{g+d-r}).
    for (int i = d; i >= r; --i) {
      const int g = j - d + 1 + i;
      const S& lo = knots[g - 1];
      const S& hi = knots[g + d - r];
      const S alpha = (t - lo) / (hi - lo);
      const S one_minus = (hi - t) / (hi - lo);
      work[i] = one_minus * work[i - 1] + alpha * work[i];
    }
  }
  return work[d];
}

}  // namespace cmr
