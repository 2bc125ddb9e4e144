#pragma once
// Internal to cmr::region and the libraries above it: a library user includes
// `region/region.hpp` (space curves: `region/space_region.hpp`).
// The rounded piece polynomials of a region entry (region_setup.hpp,
// RegionEntry::xi and ::nu): the Bernstein coefficients of every subdivision
// piece of xi (or nu) down to a level, each a polynomial in the displacement
// (dx, dy) whose monomial coefficients are rounded to double.
//
// Why not halve the exact Poly3 coefficients (mpq) directly: every mid-point
// of de Casteljau's halving is a GMP rational operation with its own gcd and
// allocations, n1^2 / 2 of them per monomial per halving, and that made the
// setup grow as n^2.9 with the degree n (issue 23). Here each monomial's
// coefficients of the root are brought to one denominator D once; halving
// then only adds integers (a mid-point's 1/2 is kept in the denominator:
// level L is over D 2^(L (n1-1))), in fixed-width two's complement, and
// each coefficient is divided and rounded once at the end. The values are
// the same rationals, so the rounded doubles are the same bit for bit
// (tests/region/region_pieces_test.cpp checks it against the exact
// halving, the method this replaces).
#include <array>
#include <cstddef>
#include <vector>

#include "numeric/bernstein.hpp"
#include "numeric/exact.hpp"
#include "numeric/poly3.hpp"
#include "spline/vec2.hpp"

namespace cmr::backend {

/// Every subdivision piece of `root` down to `levels` (>= 0), in heap order
/// (piece 2^L - 1 + j is [j, j+1] / 2^L), root.size() coefficients each:
/// out[p * root.size() + k][m] is monomial m (poly3.hpp order) of
/// coefficient k of piece p, the exact value rounded as Rational::get_d
/// rounds it (toward zero). A coefficient whose K monomials are not all
/// zero but all round to zero gets a NaN as monomial 0 (the sign is then
/// never certain: such a pixel goes exact rather than reading a structural
/// zero). K = 10 (xi) or 3 (nu: every monomial of degree >= 1 beyond dx, dy
/// must be zero; an internal error otherwise).
template <std::size_t K>
std::vector<std::array<double, K>> rounded_pieces(const Bernstein<Poly3>& root, int levels);

extern template std::vector<std::array<double, 10>> rounded_pieces<10>(const Bernstein<Poly3>&, int);
extern template std::vector<std::array<double, 3>> rounded_pieces<3>(const Bernstein<Poly3>&, int);

/// The rounded pieces of a moved polynomial entry.
struct MovedPieces {
  std::vector<std::array<double, 10>> xi;  ///< rounded_pieces<10>(lambda_bernstein<Poly3>(B), levels)
  std::vector<std::array<double, 3>> nu;   ///< rounded_pieces<3>(eta_bernstein<Poly3>(B), levels)
};

/// xi = lambda and nu = eta (lambda.hpp) of the Bezier points
/// B_i = base_i + weight_i (dx, dy), i = 0..n (n >= 2), as polynomials in
/// (dx, dy), and their pieces down to `levels`, rounded: the values of the
/// comment on each member, computed in integers. With D0 a common
/// denominator of the base points and weights and a_i, b_i, w_i the
/// integers D0 (B0_{i+1} - B0_i) and D0 (w_{i+1} - w_i), the hodograph is
/// q_i = (n / D0) (a_i + w_i dx, b_i + w_i dy), and on binomially scaled
/// coefficients (F_k = C(p, k) f_k at degree p) every step of lambda.hpp is
/// integer: C(2m-2,k) nu_k and C(2m,k) g_k are sums of integer det and dot
/// terms, the scaled derivative of f is (k+1) F_{k+1} - (p-k) F_k, a product
/// is the convolution of the scaled factors, and
///   xi_k = n^4 (2 (eta' g)~_k - 3 (eta g')~_k) / (2 C(4n-7, k) D0^4),
///   nu_k = n^2 Nu_k / (C(2n-4, k) D0^2).
/// No gcd is taken: the pieces are rounded from these exact values
/// (round_pieces), so they equal the Poly3 path bit for bit.
MovedPieces moved_pieces(const std::vector<Point<Rational>>& base, const std::vector<Rational>& weight, int levels);

}  // namespace cmr::backend
