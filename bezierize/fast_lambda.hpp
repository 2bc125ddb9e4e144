#pragma once
// Internal to cmr::bezierize and the libraries above it: a library user
// includes `bezierize/analyze.hpp` (space curves:
// `bezierize/space_analyze.hpp`).
// lambda and eta of a Bezier segment in plain double, with a rigorous
// a-priori error bound per coefficient: the classifier's first, cheapest try.
//
// The formulas are those of lambda.hpp. Every coefficient is a sum of products
// of the inputs (control point coordinates, exact) and constants (binomial
// ratios, rounded once). By the standard forward error bound for such
// expressions, |fl(E) - E| <= gamma_K * E_abs, where E_abs is the same
// expression evaluated on absolute values with every subtraction turned into
// an addition, and K bounds the number of roundings on any path from an input
// to the result; gamma_K = K u / (1 - K u). Here K <= 3m + 16 for hodograph
// degree m (2 for the hodograph, 2 for a det or dot, 1 + 1 for a weight and
// its rounding, m for the sum over pairs, 2 for a derivative, 1 + 1 + 1 for a
// product term, 2m + 1 for the product sum, 2 for the final combination),
// and we charge (3m + 20) u, which also covers the rounding of E_abs itself.
// E_abs is monotone in |q|, so it is bounded once per segment by its value
// with every |q| replaced by M, the largest coordinate of the abs-hodograph:
// S_k M^4 for xi, S_k M^2 for nu (S_k computed at compile time).
#include <array>
#include <cmath>

#include "numeric/scalar.hpp"
#include "spline/vec2.hpp"

namespace cmr {

inline constexpr int kFastMaxDegree = 15;

struct FastCoefficients {
  // Left uninitialised on purpose: fast_lambda_eta writes the first n_xi / n_nu.
  std::array<double, 4 * kFastMaxDegree - 6> xi, xi_err;
  std::array<double, 2 * kFastMaxDegree - 3> nu, nu_err;
  int n_xi = 0, n_nu = 0;
};

/// Fills xi (and nu) with values and error bounds. Degree 2..kFastMaxDegree.
void fast_lambda_eta(const Vec2* points, int degree, FastCoefficients& out);

}  // namespace cmr
