#pragma once
/// The gate g3-at-smooth-nodes[:tol] (report/gates.hpp), planar and space.
///
/// G3 at a smooth joint (the joints g2-at-smooth-nodes judges: G1, no zero
/// tangent, finite curvature on both sides) means G2 and, on both sides,
/// equal arc-length derivative of curvature dkappa/ds, and for a space curve
/// also equal torsion tau.
///
/// Derivation. With P', P'', P''' the derivatives of a segment at its end
/// in its own parameter (dkappa/ds and tau do not depend on the
/// parametrisation, so the segment's local u in [0, 1] serves):
///   planar (signed):  kappa = c / |P'|^3,  c = det(P', P''),
///     dkappa/ds = (1/|P'|) d/du [c |P'|^-3]
///               = (det(P', P''') |P'|^2 - 3 c (P' . P'')) / |P'|^6
///     (c' = det(P', P''') as det(P'', P'') = 0): the paper's lambda / |P'|^6;
///   space (|kappa|):  kappa = |c| / |P'|^3,  c = P' x P'',  c' = P' x P''',
///     dkappa/ds = ((c . c') |P'|^2 - 3 |c|^2 (P' . P'')) / (|c| |P'|^6)
///               = lambda3 / (2 |c| |P'|^6)  (undefined where kappa = 0);
///   tau = det(P', P'', P''') / |c|^2 (SpaceJoint::tau_left / tau_right).
/// End derivatives of a degree-n Bezier piece from its homogeneous points
/// H_k = (w x, w y, w z, w) (w = 1 for a polynomial spline):
///   H^(k)(0) = n!/(n-k)! Delta^k H_0,  H^(k)(1) = n!/(n-k)! Nabla^k H_n
///   (0 for k > n: a quadratic's P''' is 0), so only the first / last four
///   points matter; the Cartesian derivatives of P = H / w by Leibniz,
///   P^(k) = (H^(k) - sum_{i=1..k} C(k, i) w^(i) P^(k-i)) / w.
/// Everything is exact (GMP rationals from the exact Bezier points) up to one
/// rounding (planar), or one rounding and a square root (space: the square
/// of dkappa/ds is a rational). Degree as the polynomials: for a
/// polynomial spline of degree n the numerator of dkappa/ds is a polynomial
/// of degree 4n - 6 in u (lambda's), evaluated here only at u = 0 and 1.
///
/// Comparison: relative, as g2's, |a - b| <= tol * scale, where the scale has
/// a floor of the same units so that two values that are both zero up to
/// rounding (a circle arc's dkappa/ds, a planar curve's tau) agree:
///   dkappa/ds: scale = max(|a|, |b|, kappa^2),   tau: scale = max(|a|, |b|, kappa),
/// kappa = the larger |kappa| of the two sides (dkappa/ds / kappa^2 and
/// tau / kappa are dimensionless). A side where dkappa/ds or tau is not
/// defined (kappa = 0 in 3D, a pole) is not compared.
#include <vector>

#include "report/gates.hpp"
#include "spline/bspline.hpp"
#include "spline/space.hpp"

namespace cmr {
struct SpaceAnalysis;
}

namespace cmr::report {

struct SplineReport;

/// dkappa/ds (signed, as the planar kappa) of a planar spline at the start
/// (side 0) or end (side 1) of segment s, rational or not; NaN at a zero
/// tangent or a pole.
double planar_end_kappa_slope(const BSpline& spline, const Segment& s, int side);
/// dkappa/ds of |kappa| of a space spline at the start (side 0) or end
/// (side 1) of segment s, rational or not; NaN where kappa = 0, at a zero
/// tangent or a pole.
double space_end_kappa_slope(const SpaceSpline& spline, const Segment& s, int side);

/// True when a and b agree within tol relative to max(|a|, |b|, floor).
bool g3_agree(double a, double b, double tol, double floor);

/// g3-at-smooth-nodes:tol on a planar report (its joints: corners exempt).
std::vector<GateViolation> g3_violations(const SplineReport& report, double tol);
/// g3-at-smooth-nodes:tol on a space analysis (its joints and seam: a joint
/// that is not G1, or has a zero tangent, is exempt).
std::vector<GateViolation> space_g3_violations(const SpaceSpline& spline, const SpaceAnalysis& analysis, double tol);

}  // namespace cmr::report
