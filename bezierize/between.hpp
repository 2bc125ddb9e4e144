#pragma once
// Internal to cmr::bezierize and the libraries above it: a library user
// includes `bezierize/analyze.hpp` (space curves:
// `bezierize/space_analyze.hpp`).
/// Certified curvature monotonicity (and inflection freedom) of a planar
/// polynomial Bezier piece at every location between two masters (issue 37,
/// gates curvature-between-masters and extrema-between-masters).
///
/// Setting. Two masters A_0..A_n and B_0..B_n (same degree n >= 2) of one
/// piece; between them every control point moves affinely in the axis
/// parameter s in [0, 1]:
///     P_i(s) = (1 - s) A_i + s B_i.
///
/// Derivation. With Q = dP/dt (lambda.hpp):
///   eta(t, s)    = det(P', P'')                              degree 2n-4 in t,
///   lambda(t, s) = det(P', P''') (P'.P') - 3 det(P', P'') (P'.P'')
///                = eta' g - (3/2) eta g',  g = P'.P'       degree 4n-7 in t
/// (lambda.hpp: both products have exact degree 4n-7). In s: every control
/// point of P(., s), hence of P', P'', P''', is a polynomial of degree 1 in s;
/// eta and g are quadratic forms of the control points (det and dot of two
/// hodograph points), so each of eta's Bernstein coefficients in t is a
/// polynomial of degree <= 2 in s, and lambda = eta' g - (3/2) eta g', a sum
/// of products of two such quadratic forms, has Bernstein coefficients in t
/// of degree <= 4 in s. So
///   lambda(t, s) = sum_{i=0}^{4n-7} sum_{j=0}^{4} c_ij B_i^{4n-7}(t) B_j^4(s),
///   eta(t, s)    = sum_{i=0}^{2n-4} sum_{j=0}^{2} e_ij B_i^{2n-4}(t) B_j^2(s),
/// the tensor-product Bernstein form on [0, 1]^2.
///
/// Computation (one formula, reused). For s_k = k/d, k = 0..d (d = 4 for
/// lambda, 2 for eta), the t-coefficients xi(s_k) are lambda_bernstein
/// (eta_bernstein) of the instance P(s_k); each coefficient row in s is then
/// the degree-d polynomial through those d+1 values, converted to Bernstein
/// form by the inverse of the collocation matrix M_kj = B_j^d(k/d)
/// (c_ij = sum_k (M^-1)_jk xi_i(s_k)). In double with a certified error bound
/// (numeric/bounded.hpp: the instance points, lambda's coefficients and the
/// interpolation all carry their bound), and in exact rationals (GMP) where
/// the bound does not decide. tests/bezierize/between_exact.py recomputes
/// c_ij independently (bivariate monomials in fractions).
///
/// Certificate. Cells [t0, t1] x [s0, s1] are dyadic boxes reached by halving
/// (de Casteljau at 1/2 in t or in s). On a cell the coefficients of the
/// restriction are the cell's tensor coefficients; for any fixed s in
/// [s0, s1] the t-coefficients of lambda(., s) on [t0, t1] are convex
/// combinations of them. So:
///   * every coefficient of a cell >= 0 (<= 0): lambda(., s) >= 0 (<= 0) on
///     [t0, t1] for every s in [s0, s1];
///   * an s-interval is certified monotone when its t-cells (halving in t
///     down to max_depth, Algorithm 1's tree) are all >= 0 or all <= 0 (cells
///     identically 0 agree with both). Then for every s in it lambda(., s)
///     has no sign change on [0, 1], and Algorithm 1 at that s with the same
///     max_depth answers increasing, decreasing or constant (its pieces at
///     the cells' levels have coefficients of one sign);
///   * an s-interval that is not certified is halved in s down to s_depth.
/// Signs are read from the bounded coefficients when the bound decides
/// (counted in cells_float) and from the exact coefficients otherwise
/// (cells_exact). Phase 1 certifies s-intervals left to right and stops at
/// the first one of level s_depth that is not certified: its left end is
/// s_lower. Phase 2 looks for a witness with the exact single-piece
/// classifier (Algorithm 1 of classify.hpp / algorithms.hpp on lambda of
/// the exact instance P(s); bounded first, rationals where the bound does
/// not decide): at s_lower, then s_lower + 2^(k - s_depth) for k = 0, 1, ...
/// up to s = 1, then by bisection between the last s that did not fail and
/// the first that did, down to 2^-s_depth; the smallest failing s is checked
/// once more in rationals and reported.
/// Algorithm 1's "not monotone" is a certain sign change of lambda(., s) on
/// [0, 1] (its pieces are of one sign and not zero), i.e. a curvature
/// extremum strictly inside the instance.
/// Common factor (lambda only). Where an instance between has lambda == 0
/// for every t (a straight instance, where the direction of monotonicity
/// flips), no s-interval around it can be certified. So when the certificate on lambda
/// does not cover [0, 1], h(s) = gcd over Q[s] of the rows c_i.(s) is
/// computed exactly; when deg h >= 1 the certificate is rerun on
/// mu = lambda / h (exact, then rounded with its bound): lambda(., s) =
/// h(s) mu(., s) has no sign change wherever mu(., s) has none.
///
/// Inflections: the same on eta with Algorithm 2's rules: a cell is
/// certified when every coefficient is > 0 (< 0); the witness is Algorithm 2
/// answering "inflection present" (eta(., s) <= 0 somewhere where it is
/// > 0 elsewhere, or 0 at an end).
///
/// extrema-between-masters (curvature-extrema-at-nodes at every location):
/// an extremum leaves its node exactly when some instance has an extremum
/// strictly inside a piece, so the gate is monotone_between on every piece of
/// the contour. node_lambda_between adds, for one node, the signs of lambda
/// at the node on both sides for all s (whether the node stays a maximum or
/// a minimum of the curvature).
#include <cstdint>
#include <string>
#include <vector>

#include "spline/limits.hpp"
#include "spline/vec2.hpp"

namespace cmr {

struct BetweenOptions {
  int max_depth = kDefaultDepth;  ///< D of Algorithms 1 and 2: deepest halving in t (0..kMaxDepth)
  int s_depth = 24;               ///< deepest halving in s (0..48): s-intervals of 2^-s_depth
  std::int64_t max_cells = std::int64_t{1} << 21;  ///< budget of (t, s) cells; spent: undecided
};

/// What monotone_between / inflection_free_between certify.
struct BetweenVerdict {
  enum class Kind : std::uint8_t {
    holds_throughout,  ///< PROOF: for every real s in [0, 1] the property holds at P(s)
    fails,             ///< s_first_fail is an exact witness where it does not
    undecided,         ///< neither (depth or cell budget exhausted, or the only failures are at
                       ///< s no dyadic point hits, e.g. a single straight instance at s = 8/15
                       ///< for inflections); s_lower still holds
  };
  Kind kind = Kind::undecided;
  /// Every real s in [0, s_lower) is certified (the property holds at P(s));
  /// 1 when kind == holds_throughout (then [0, 1] all). With kind == fails
  /// the infimum of the failing s lies in [s_lower, s_first_fail].
  double s_lower = 0;
  /// kind == fails: the smallest s tried that fails, a dyadic rational (an
  /// exact double), checked in exact rational arithmetic: Algorithm 1 says
  /// "not monotone" (Algorithm 2: "inflection present") on the exact
  /// instance P(s) with max_depth. -1 otherwise.
  double s_first_fail = -1;
  /// kind == fails: a parameter t in [0, 1] within 1e-12 of a sign change
  /// of lambda(., s_first_fail) (of eta for inflections): the instance's
  /// curvature extremum (inflection) strictly inside. -1 otherwise.
  double t_witness = -1;
  /// holds_throughout for lambda: +1 curvature increasing at every s, -1
  /// decreasing at every s, 0 when both occur (then lambda(., s) == 0 for
  /// some s between: a constant-curvature instance). For eta: the sign of
  /// the curvature. 0 otherwise.
  int direction = 0;
  /// (t, s) cells decided with the floating-point bound, and by the exact
  /// path (the share decided each way).
  std::int64_t cells_float = 0, cells_exact = 0;
  /// s-intervals where the exact single-piece classifier was run.
  int witnesses_tried = 0;
};

const char* to_string(BetweenVerdict::Kind k);

/// Curvature monotone at every instance between the masters (lambda).
/// InputError (one line) when the masters differ in size, have fewer than 3
/// or more than kMaxDegree + 1 points, or a coordinate is not finite, or the
/// options are out of range.
BetweenVerdict monotone_between(const std::vector<Vec2>& masterA, const std::vector<Vec2>& masterB,
                                const BetweenOptions& options = {});
/// No inflection at any instance between the masters (eta).
BetweenVerdict inflection_free_between(const std::vector<Vec2>& masterA, const std::vector<Vec2>& masterB,
                                       const BetweenOptions& options = {});

/// lambda at a node for every s: L ends at the node (t = 1), R starts there
/// (t = 0); LA, LB and RA, RB are the two pieces at the two masters. lambda
/// at the node is a polynomial of degree <= 4 in s (the tensor's last t row
/// on the left, the first on the right); its roots in [0, 1] are isolated
/// exactly (roots.hpp).
struct NodeBetween {
  /// Sign of lambda_L(1, s) (lambda_R(0, s)) for every s in [0, 1] when it
  /// is the same non-zero sign throughout; 0 when it vanishes somewhere.
  int left_sign = 0, right_sign = 0;
  /// The smallest s in [0, 1] where lambda_L(1, s) (lambda_R(0, s)) is 0,
  /// within 1e-12; -1 when it never is.
  double left_zero_s = -1, right_zero_s = -1;
  /// Both sides keep one non-zero sign for every s: the node is a curvature
  /// maximum (left +, right -) or minimum (left -, right +) at every
  /// instance or at none (same signs), as at the masters.
  bool pattern_kept() const { return left_sign != 0 && right_sign != 0; }
};
NodeBetween node_lambda_between(const std::vector<Vec2>& LA, const std::vector<Vec2>& LB,
                                const std::vector<Vec2>& RA, const std::vector<Vec2>& RB);

/// The tensor coefficients themselves (tests, tools): row-major, index
/// i * (deg_s + 1) + j for B_i(t) B_j(s); exact as canonical rationals
/// ("num/den", GMP's and Python's Fraction's form), and the bounded double
/// value with its error bound.
struct BetweenTensor {
  int deg_t = 0, deg_s = 0;
  std::vector<std::string> exact;
  std::vector<double> value, error;
};
BetweenTensor lambda_between_tensor(const std::vector<Vec2>& masterA, const std::vector<Vec2>& masterB);
BetweenTensor eta_between_tensor(const std::vector<Vec2>& masterA, const std::vector<Vec2>& masterB);

}  // namespace cmr
