#pragma once
// Pointwise curvature of a planar curve C(t) (CAD&A 2024 §3, Eqs. 2, 3, 5).
//
//   kappa(t)    = det(C', C'') / |C'|^3            (signed: > 0 turns counter-clockwise)
//   dkappa/ds   = lambda(t) / |C'|^6
//   lambda(t)   = det(C', C''') (C'.C') - 3 det(C', C'') (C'.C'')
//               = eta' g - (3/2) eta g'            with eta = det(C', C''), g = C'.C'
//
// For a polynomial piece of degree n, eta has degree 2n-4 and lambda 4n-7
// (bezierize/lambda.hpp builds both in Bernstein form). These pointwise
// versions are the reference the Bernstein forms are tested against; they
// assume a regular curve (C' != 0), as the paper does.
#include "spline/bspline.hpp"

namespace cmr {

struct CurvatureSample {
  double t = 0;
  Vec2 point{0.0};
  double kappa = 0;      ///< signed curvature
  double dkappa_ds = 0;  ///< derivative of kappa with respect to arc length
  double lambda = 0;     ///< numerator of dkappa/ds (sign of dkappa/ds)
  double eta = 0;        ///< numerator of kappa (sign of kappa)
};

CurvatureSample curvature_at(const BSpline& spline, double t);
double curvature(const BSpline& spline, double t);

/// Curvature at the start (side = 0) or end (side = 1) of a segment, from that
/// segment's own polynomial, so that jumps at joints are visible. Plain
/// double, for plots: its sign can be wrong where the end legs are tiny
/// against the coordinates (a curve 1e-6 across at 1e8). Reported values
/// (joints, ranges) use cmr::certified_end_curvature (bezierize/analyze.hpp).
double segment_end_curvature(const BSpline& spline, const Segment& s, int side);

}  // namespace cmr
