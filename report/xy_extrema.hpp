#pragma once
/// xy-extrema-at-nodes (report/gates.hpp): a node at every horizontal and
/// vertical tangent of an outline, the "points at extrema" rule of type
/// design (FontLab's FontAudit, RedArrow, FontForge's and MS Font
/// Validator's checks that fontbakery ran). A *node* is a joint whose knot
/// multiplicity is at least the degree (the curve passes through a control
/// point: an on-curve point), the notion of curvature-extrema-at-nodes:runs;
/// an open spline's ends are nodes too.
///
/// Certified by exact root isolation (numeric/roots.hpp). Segment i with
/// Bezier points P_0..P_n (exact rationals from the doubles,
/// segment_bezier_points<Rational>) is C(u) = sum P_k B_k^n(u), u in [0, 1]:
///
///   x'(u) = n sum_{k=0}^{n-1} (x_{k+1} - x_k) B_k^{n-1}(u)     (degree n-1)
///
/// and the same for y. A rational segment (homogeneous points (X_k, Y_k, W_k),
/// x = X / W) has x' = (X' W - X W') / W^2; W^2 > 0 away from a pole, so the
/// sign of x' is that of the numerator N_x = X' W - X W', formed exactly with
/// bernstein_product at degree (n-1) + n = 2n-1 (its true degree is at most
/// 2n-2: the t^{2n-1} terms cancel; the degree-elevated form has the same
/// roots and signs). Each root of x' (y') in the open segment at which it
/// changes sign (odd multiplicity) is an x (y) extremum of the outline: a
/// vertical (horizontal) tangent where the outline turns back. A root of even
/// multiplicity touches without turning (no extremum); a root at a segment's
/// end lies on a joint: fine at a node; at a joint that is no node (a
/// TrueType implied midpoint, C^1 there) it is an extremum when the signs on
/// the two sides differ. A straight segment (zero curvature) has none, nor
/// has an axis-parallel piece (x' or y' identically zero); a segment with a
/// pole is every gate's violation already (check_gates).
///
/// Tolerance (what a font's integer grid cannot avoid): an extremum's
/// *overshoot* is how far its coordinate lies beyond the nearer of its two
/// neighbours along the outline in that coordinate: the previous and the
/// next node or extremum of the same axis (between two such neighbours the
/// coordinate is monotone). An extremum whose overshoot is below the gate's
/// tolerance U (in the outline's units: font units for a font; default
/// kDefaultXyExtremumTolerance = 1, one unit of the integer grid) is
/// tolerated: an extremum a hair away from its node, or a handle off the
/// axis by a unit, pokes out by less than the grid can show. This is
/// FontAudit's "badness" (RedArrow's extremum_ignore_badness_below = 1 unit
/// per 1000 units per em: how far the extremum lies outside the box of the
/// segment's end nodes), measured against the neighbours rather than the box
/// so that a wiggle inside the box counts as well. The overshoot is measured
/// in double precision at the root's enclosure (a designer's tolerance, not
/// a certified fact); the extremum itself, its axis and its segment are
/// certified. `xy-extrema-at-nodes:0` reports every extremum.
///
/// The fix is a node inserted at the extremum: the segment split there by de
/// Casteljau's algorithm at the root's local parameter, which keeps the
/// outline the same curve. cmr says where and does not write it back (a
/// point inserted into a font's source is a new point, not a moved one).
#include <vector>

#include "numeric/bernstein.hpp"
#include "numeric/exact.hpp"
#include "report/gates.hpp"
#include "spline/bspline.hpp"

namespace cmr::report {

/// The derivative x'(u) (axis 0) or y'(u) (axis 1) of segment `segment` in
/// Bernstein form on u in [0, 1], exactly (a rational spline: its numerator
/// X' W - X W'; see the header comment). Empty or all zero when constant.
Bernstein<Rational> xy_derivative(const BSpline& spline, int segment, int axis);

/// One extremum of x or y strictly inside a segment (or on a joint that is
/// no node) with a sign change of the derivative.
struct XyExtremum {
  int axis = 0;          ///< 0: x extremum (vertical tangent, x' = 0); 1: y extremum (horizontal tangent)
  int kind = 0;          ///< +1 maximum, -1 minimum
  int segment = -1;      ///< inside this segment, or
  int joint = -1;        ///< on this joint (no node; index as GateViolation::joint)
  double t = 0;          ///< spline parameter (nearest double to the enclosure's middle)
  double local_t = 0;    ///< within the segment, in [0, 1]
  double local_lo = 0, local_hi = 0;  ///< the root's enclosure in the segment, rounded outwards
  Vec2 point{0, 0};      ///< the outline's point there (the node to add)
  double overshoot = 0;  ///< how far past the nearer neighbouring node or extremum of the axis
};

/// Every x and y extremum of the spline away from its nodes, in parameter
/// order (x before y at the same place). `report` supplies the segments'
/// straightness, poles and joints (report_spline's model of `report.spline`).
std::vector<XyExtremum> xy_extrema(const SplineReport& report);

/// The gate: the extrema whose overshoot is at least `tolerance`, each a
/// violation located by segment (or joint), t, and the point: "… add a node
/// at (x, y)".
std::vector<GateViolation> xy_extremum_violations(const SplineReport& report, double tolerance);

}  // namespace cmr::report
