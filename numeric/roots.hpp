#pragma once
// Internal to cmr's libraries: a library user includes `bezierize/analyze.hpp`
// or `region/region.hpp`.
// Certified real roots of Bernstein polynomials with exact coefficients: where
// a segment's curvature has its extrema (roots of lambda) and its inflections
// (roots of eta), CAD&A 2024 §3, found with certainty rather than by sampling.
//
// Method, on p(t) = sum c_i B_i^n(t), t in [0, 1], c_i rational:
//  1. Isolation. p is halved at t = 1/2 (de Casteljau, exact) until every piece
//     has 0 sign variations among its coefficients (no root inside) or 1
//     (exactly one root inside, and it is simple): Descartes' rule of signs in
//     Bernstein form, which counts the roots in the open piece with
//     multiplicity. The ends 0, 1 and every halving point are tested exactly,
//     so a root there is found exactly; its multiplicity is the order of the
//     first derivative that does not vanish there.
//  2. Multiple roots inside a piece keep its variation count at 2 or more; when
//     halving goes deeper than 48 levels, p is split instead into its
//     square-free factors (Yun's algorithm over Q), p = c f_1 f_2^2 ... f_k^k,
//     and each f_i is isolated alone: its roots are those of p of
//     multiplicity exactly i.
//  3. Refinement. Each isolated root is bisected on exact signs (evaluated in
//     double with a certified error bound, numeric/bounded.hpp, and in
//     rationals where that bound does not decide) until its enclosure is at
//     most `tolerance` wide.
// Sign tests on coefficients and values are exact comparisons with zero by
// design: that is what makes the counts certain.
#include <vector>

#include "numeric/bernstein.hpp"
#include "numeric/exact.hpp"

namespace cmr {

struct RootOptions {
  /// Widest enclosure returned, relative to the interval [0, 1] (so, for a
  /// segment's lambda or eta, relative to the segment's parameter length).
  /// Must lie in (0, 1].
  double tolerance = 1e-12;
};

/// One distinct root of p in [0, 1].
struct RootInterval {
  Rational lo, hi;       ///< the root is lo when lo == hi, else strictly inside (lo, hi)
  int multiplicity = 1;  ///< exact
  int sign_before = 0;   ///< sign of p just left of the root (of the polynomial, so also defined left of 0)
  int sign_after = 0;    ///< sign of p just right of the root
  bool exact() const { return lo == hi; }
  /// Odd multiplicity: p changes sign here; even: p touches zero.
  bool sign_change() const { return sign_before != sign_after; }
};

/// True when every coefficient is zero (or there are none).
bool is_zero(const Bernstein<Rational>& p);

/// Sign of p just right of t = 0: the sign of its first non-zero coefficient
/// (near 0, p(t) ~ c_j C(n,j) t^j). 0 for the zero polynomial.
int sign_at_start(const Bernstein<Rational>& p);

/// The distinct roots of p in the closed interval [0, 1], ascending, each with
/// an enclosure no wider than options.tolerance, its multiplicity and the signs
/// of p on either side. A root at 0, at 1 or at a dyadic rational reached by
/// halving is returned exactly. The zero polynomial has no isolated roots: the
/// result is empty (tell it apart with is_zero).
std::vector<RootInterval> isolate_roots(const Bernstein<Rational>& p, const RootOptions& options = {});

/// The double nearest to x (ties to even), and the largest double <= x and the
/// smallest double >= x (outward rounding of an enclosure).
double nearest_double(const Rational& x);
double double_below(const Rational& x);
double double_above(const Rational& x);

}  // namespace cmr
