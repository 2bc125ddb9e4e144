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
//
// Rational curves C = X / W (W != 0: no pole, see bspline.hpp), with the
// homogeneous curve H = (X, Y, W):
//   C' = h / W^2,  h = W X' - W' X           (a 2-vector)
//   det(C', C'') = D / W^3,  D = det(H, H', H'')   (3x3)
//   kappa       = W^3 D / |h|^3
//   dkappa/dt   = W^2 lambda / |h|^5,
//   lambda      = (3 W' D + W D') (h.h) - 3 W D (h.h'),  D' = det(H, H', H'''),
//                 h' = W X'' - W'' X
// so sign(dkappa/ds) = sign(lambda) and sign(kappa) = sign(W) sign(D);
// dkappa/ds = (dkappa/dt) / |C'| = W^4 lambda / |h|^6. For W = 1 these are
// the polynomial formulas (D = eta, h = C', h.h' = g'/2).
#include <optional>

#include "spline/bspline.hpp"

namespace cmr {

struct CurvatureSample {
  double t = 0;
  Vec2 point{0.0};
  double kappa = 0;      ///< signed curvature
  double dkappa_ds = 0;  ///< derivative of kappa with respect to arc length
  double lambda = 0;     ///< numerator of dkappa/ds (sign of dkappa/ds)
  double eta = 0;        ///< numerator of kappa (sign of kappa): D for a rational curve
};

CurvatureSample curvature_at(const BSpline& spline, double t);
double curvature(const BSpline& spline, double t);

/// Curvature at the start (side = 0) or end (side = 1) of a segment, from that
/// segment's own polynomial, so that jumps at joints are visible. Plain
/// double, for plots: its sign can be wrong where the end legs are tiny
/// against the coordinates (a curve 1e-6 across at 1e8). Reported values
/// (joints, ranges) use cmr::certified_end_curvature (bezierize/analyze.hpp).
double segment_end_curvature(const BSpline& spline, const Segment& s, int side);

/// Points of the curve for pictures, safe near a pole (bspline.hpp: W = 0
/// sends the rational curve to infinity). A point is drawn when it is finite
/// and inside the box of the control points widened on every side by the
/// box's larger side (at least 1e-9 of the largest coordinate): a polynomial curve, and a rational one with weights > 0, lie
/// in the control points' convex hull, so for them every point is drawn and
/// nothing changes; near a pole the curve leaves the box and is cut there.
/// Two drawn samples are joined by a line only when W has the same sign at
/// both (no pole between them that the box missed).
class CurveSampler {
 public:
  explicit CurveSampler(const BSpline& spline);
  /// C(t) when it can be drawn, else nullopt.
  std::optional<Vec2> at(double t) const;
  /// Whether a line may join the drawn samples at t0 and t1.
  bool joins(double t0, double t1) const;
  /// Whether p lies in the drawing box (finite and inside).
  bool inside(Vec2 p) const;

 private:
  const BSpline* spline_;
  Vec2 lo_, hi_;
};

}  // namespace cmr
