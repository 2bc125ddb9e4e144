#pragma once
// Planar B-spline curves in polar form (Ramshaw), the value type all of cmr
// works on. A BSpline that exists is valid: BSpline::make checks everything
// once, at the edge, and inner code trusts it.
//
// Polar-form knots: degree d >= 2, m >= d+1 control points, m+d-1 knots
// u_0..u_{m+d-2}, non-decreasing, finite, each value repeated at most d times,
// and at least one non-empty span. Spans are [u_j, u_{j+1}] for j = d-1..m-2;
// the non-empty ones are the curve's segments, numbered 0..N-1 in order.
// Knots are compared exactly: an empty span is one whose two knots are the
// same double, and that exactness is the point (no knot tolerance is needed
// because nothing here decides equality of computed knots).
//
// Examples: cubic, 6 points, [0,1,2,3,4,5,6,7] has segments [2,3],[3,4],[4,5];
// [0,0,0,1,2,3,3,3] has [0,1],[1,2],[2,3]. A Bezier curve of degree n is the
// B-spline with knots 0^n 1^n.
//
// Rational curves (NURBS). Optional weights w_i, one per control point, make
// the curve C(t) = X(t) / W(t) with the homogeneous B-spline
// H(t) = (X, W) whose control points are (w_i x_i, w_i y_i, w_i): the blossom
// (the one primitive) runs on (w x, w y, w) and the result is projected.
// Weights may be any finite numbers, not all 0 (InputError otherwise). Then
// W(t) = sum_i w_i N_i(t), the homogeneous weight coordinate, is a continuous
// piecewise polynomial that may be negative or vanish:
//  * W != 0 on a span: the curve there is X / W, finite and smooth, whatever
//    W's sign (x / w = (-x) / (-w)); the curvature is W^3 D / |h|^3
//    (bezierize/rational_lambda.hpp), so its sign is sign(W) sign(D).
//  * W = 0 somewhere in a closed span (a root inside, or at a knot, or W == 0
//    on the span): the curve passes through infinity there, a *pole*
//    (bezierize/analyze.hpp: segment_pole, SegmentShape::pole). Pole spans are
//    reported, never divided by: no monotone curvature is claimed for them.
//  * A weight of 0 makes the point's homogeneous point (0 x, 0 y, 0) = 0: the
//    point has no influence on the curve (its x, y are kept in the file but do
//    not enter H). Points at infinity given as directions are not supported.
// W is continuous, so between a span where W > 0 and one where W < 0 there is
// always a pole. If every weight is negative, all are negated at make(): the
// same curve ((-X) / (-W) = X / W), stored with positive weights. Other
// weight sets are kept as given (mixed signs are not normalised).
// Weights that are all equal describe the polynomial curve with the same
// points, and are dropped (is_rational() is false, the file is written
// without "weights").
#include <string>
#include <vector>

#include "spline/vec2.hpp"

namespace cmr {

/// A non-empty span [a, b] = [u_j, u_{j+1}] of a B-spline.
struct Segment {
  int index = 0;  ///< position among the non-empty spans, 0..N-1
  int span = 0;   ///< knot index j (d-1 <= j <= m-2)
  double a = 0, b = 0;
};

class BSpline {
 public:
  /// Validates and builds. Throws InputError naming the field and index, e.g.
  /// "knots[4] (2.5) is smaller than knots[3] (3)".
  /// `weights`: empty (a polynomial curve) or one finite weight per point,
  /// not all 0 ("weights[2] is not a finite number"); all negative ones are
  /// negated (the same curve, see above).
  static BSpline make(int degree, std::vector<double> knots, std::vector<Vec2> points,
                      std::string name = {}, std::vector<double> weights = {});
  /// The Bezier curve of degree points.size()-1 as a B-spline (knots 0^n 1^n).
  static BSpline bezier(std::vector<Vec2> points, std::string name = {}, std::vector<double> weights = {});
  /// A closed (periodic) B-spline: m >= 2 control points P_0..P_{m-1} and the
  /// m+1 knots u_0 <= ... <= u_m of one period T = u_m - u_0 > 0, span i being
  /// [u_i, u_{i+1}]; each knot's multiplicity, counted cyclically (u_0 and u_m
  /// are the same knot), is at most the degree. Stored unrolled, so that every
  /// algorithm for open splines runs on it unchanged: the points are
  /// Q_k = P_{k mod m}, k = 0..m+d-1, and the polar knots t_k = ũ_{k-d+1},
  /// k = 0..m+2d-2, with ũ the periodic extension (ũ_{i+m} = ũ_i + T). The
  /// unrolled spans d-1..m+d-2 are [u_0,u_1]..[u_{m-1},u_m]: the segments cover
  /// one period exactly, segment i uses P_i..P_{i+d} (mod m), and the curve
  /// ends where it starts with the continuity its knot gives there. The seam
  /// (the joint at u_0 ≡ u_m, between the last segment and segment 0) is a
  /// joint like every other one to code that asks closed() (the report's
  /// joints and events, the type-design gates). InputError as make() does,
  /// with the period's indices. `weights`: empty, or one per P_i (as make()).
  static BSpline make_closed(int degree, std::vector<double> knots, std::vector<Vec2> points, std::string name = {},
                             std::vector<double> weights = {});

  int degree() const { return degree_; }
  const std::vector<double>& knots() const { return knots_; }
  const std::vector<Vec2>& points() const { return points_; }
  const std::string& name() const { return name_; }
  /// Whether the curve is rational (has weights that are not all equal).
  bool is_rational() const { return !weights_.empty(); }
  /// The weights, one per point; empty for a polynomial curve.
  const std::vector<double>& weights() const { return weights_; }
  /// Weight of point i (1 for a polynomial curve).
  double weight(int i) const { return weights_.empty() ? 1.0 : weights_[i]; }
  /// (w x, w y, w) of every point, rounded once per coordinate (for double
  /// evaluation; exact code builds them from points() and weights()).
  const std::vector<glm::dvec3>& homogeneous_points() const { return hpoints_; }
  int point_count() const { return static_cast<int>(points_.size()); }

  /// The non-empty spans, in order.
  const std::vector<Segment>& segments() const { return segments_; }
  int segment_count() const { return static_cast<int>(segments_.size()); }
  /// Parameter domain [u_{d-1}, u_{m-1}].
  double domain_begin() const { return segments_.front().a; }
  double domain_end() const { return segments_.back().b; }
  /// The segment containing t (clamped to the domain; a knot belongs to the
  /// segment on its right, the domain end to the last segment).
  const Segment& segment_at(double t) const;
  /// Multiplicity of the knot value u (exact comparison).
  int multiplicity(double u) const;

  /// Closed (make_closed): points() and knots() are the unrolled form.
  bool closed() const { return closed_; }
  /// m: the distinct control points (point_count() for an open spline; for a
  /// closed one the first m of points(), the others repeat P_0..P_{d-1}).
  int unique_point_count() const { return closed_ ? period_points_ : point_count(); }
  /// Closed: u_0..u_m of one period (as given to make_closed); open: knots().
  std::vector<double> period_knots() const;
  /// The other index holding the same control point in the unrolled form
  /// (k < d: k + m; k >= m: k - m), or -1 (open splines, and points without one).
  int twin(int k) const;

  /// A copy with control point k replaced (no revalidation of knots needed;
  /// the point must be finite: throws InputError otherwise). On a closed
  /// spline its twin moves with it, so the copy stays closed.
  [[nodiscard]] BSpline with_point(int k, Vec2 p) const;
  /// A copy with every distinct control point replaced at once: `pts` holds
  /// unique_point_count() points (each finite, as with_point's; throws
  /// InputError otherwise), a closed spline's twins following them. One
  /// copy, where a with_point per point would copy the spline each time.
  [[nodiscard]] BSpline with_points(const std::vector<Vec2>& pts) const;
  /// The same curve traversed backwards: knots u -> -u reversed, points reversed.
  [[nodiscard]] BSpline reversed() const;

 private:
  BSpline() = default;
  int degree_ = 0;
  std::vector<double> knots_;
  std::vector<Vec2> points_;
  std::vector<Segment> segments_;
  std::string name_;
  std::vector<double> weights_;
  std::vector<glm::dvec3> hpoints_;
  bool closed_ = false;
  int period_points_ = 0;  ///< m, closed splines only
};

/// f(args[0..d-1]) on segment s: the blossom of the piece of `spline` there.
Vec2 blossom(const BSpline& spline, const Segment& s, const double* args);

/// The homogeneous blossom (w x, w y, w) on segment s; (x, y, 1) for a
/// polynomial curve.
glm::dvec3 homogeneous_blossom(const BSpline& spline, const Segment& s, const double* args);
/// The r-th derivative of the homogeneous curve H(t), 0 <= r <= d.
glm::dvec3 homogeneous_derivative(const BSpline& spline, double t, int r);

/// C(t): the blossom on the diagonal (projected for a rational curve).
Vec2 evaluate(const BSpline& spline, double t);
/// The r-th derivative C^(r)(t), 0 <= r <= d, from the blossom (see blossom.hpp).
/// For a rational curve, from H = W C by Leibniz' rule:
/// C^(r) = (X^(r) - sum_{i=1..r} C(r,i) W^(i) C^(r-i)) / W.
Vec2 derivative(const BSpline& spline, double t, int r);

}  // namespace cmr
