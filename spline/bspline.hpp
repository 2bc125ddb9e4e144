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
// cmr allows finite weights > 0 only: then W(t), a convex combination of
// positive weights on every span, is positive everywhere, so a rational curve
// has no pole (no `pole` class is needed; a zero or negative weight is refused
// at the edge with its index). Weights that are all equal describe the
// polynomial curve with the same points, and are dropped (is_rational() is
// false, the file is written without "weights").
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
  /// `weights`: empty (a polynomial curve) or one finite weight > 0 per point
  /// ("weights[2] (0) is not positive; ...").
  static BSpline make(int degree, std::vector<double> knots, std::vector<Vec2> points,
                      std::string name = {}, std::vector<double> weights = {});
  /// The Bezier curve of degree points.size()-1 as a B-spline (knots 0^n 1^n).
  static BSpline bezier(std::vector<Vec2> points, std::string name = {}, std::vector<double> weights = {});

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

  /// A copy with control point k replaced (no revalidation of knots needed;
  /// the point must be finite: throws InputError otherwise).
  [[nodiscard]] BSpline with_point(int k, Vec2 p) const;
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
