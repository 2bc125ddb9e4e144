#pragma once
/// Closed chains of Bezier pieces as one closed B-spline (BSpline::make_closed),
/// shared by the font and SVG importers.
///
/// A chain of pieces of degree d is listed as its control points in order:
/// each piece contributes its start node and its d-1 inner points; the next
/// piece's node ends it. With the polar labels of the closed form (point P_k
/// carries ũ_{k-d+1}..ũ_k), a piece on [a, b] needs labels a^d (node), a^{d-1}b,
/// ..., ab^{d-1} (inner), b^d (next node): u_k = u_{k-1} + 1 exactly at a
/// piece's first inner point and u_k = u_{k-1} elsewhere. Every piece then is
/// one unit-length span whose Bezier points are the listed points, and every
/// node has multiplicity d (C0; its G1-ness is the tangents').
///
/// TrueType's implied on-curve points are the other case: between two
/// off-curve points of a quadratic contour the node is their midpoint, which
/// is what a uniform quadratic B-spline gives at a simple knot. So in degree
/// 2 every off-curve point (an inner point) increments, explicit on-curve
/// points (nodes) do not, and two off-curve points in a row meet at a simple
/// knot: the implied midpoint, C1.
#include <vector>

namespace cmr::import {

/// u_0 = 0, u_k = u_{k-1} + (increments[k mod m] ? 1 : 0) for k = 1..m: the
/// m+1 period knots of make_closed for m control points.
inline std::vector<double> chain_knots(const std::vector<bool>& increments) {
  const std::size_t m = increments.size();
  std::vector<double> u(m + 1, 0.0);
  for (std::size_t k = 1; k <= m; ++k) u[k] = u[k - 1] + (increments[k % m] ? 1.0 : 0.0);
  return u;
}

}  // namespace cmr::import
