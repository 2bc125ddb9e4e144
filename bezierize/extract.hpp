#pragma once
// Internal to cmr::bezierize and the libraries above it: a library user
// includes `bezierize/analyze.hpp` (space curves:
// `bezierize/space_analyze.hpp`).
// Bezier form of B-spline segments, by blossoming (the primary route) and by
// repeated Boehm knot insertion (an independent route the tests compare with),
// and the affine influence of a control point on those Bezier points.
#include <type_traits>
#include <vector>

#include "numeric/exact.hpp"
#include "spline/blossom.hpp"
#include "spline/bspline.hpp"

namespace cmr {

struct BezierSegment {
  Segment segment;
  std::vector<Vec2> points;  ///< d+1 Bezier points of the segment, on [a, b] -> [0, 1]
  /// A rational segment's Bezier weights (points are then the projected
  /// homogeneous Bezier points, not finite where a weight is 0, which a span
  /// with a pole may have); empty for a polynomial spline.
  std::vector<double> weights;
};

/// Bezier points of span j = [a, b]: B_k = f(a^{d-k}, b^k), k = 0..d.
/// Generic so that the classifier can run it with error bounds or exactly.
template <class S, class P>
std::vector<P> bezier_points(const std::vector<S>& knots, const std::vector<P>& points, int degree, int span,
                             const S& a, const S& b) {
  std::vector<P> out;
  out.reserve(degree + 1);
  std::vector<S> args(degree);
  for (int k = 0; k <= degree; ++k) {
    for (int i = 0; i < degree; ++i) args[i] = i < degree - k ? a : b;
    out.push_back(blossom_span(knots, points, degree, span, args.data()));
  }
  return out;
}

/// What segment s depends on, in scalar type T: knots u_{j-d+1}..u_{j+d} and
/// control points P_{j-d+1}..P_{j+1} (j = s.span); in this window the segment is
/// span d-1. Per-segment work stays O(d) however long the spline is.
template <class T>
struct SegmentWindow {
  std::vector<T> knots;
  std::vector<Point<T>> points;
  int span = 0;
};

template <class T>
SegmentWindow<T> segment_window(const BSpline& spline, const Segment& s) {
  const int d = spline.degree(), first = s.span - d + 1;
  SegmentWindow<T> w;
  w.knots.assign(spline.knots().begin() + first, spline.knots().begin() + s.span + d + 1);
  for (int i = 0; i <= d; ++i) w.points.push_back(to_point<T>(spline.points()[first + i]));
  w.span = d - 1;
  return w;
}

/// True when segment s = [a, b]'s window has knots a^d b^d (both ends of
/// multiplicity d, as every piece of a chain of Bezier pieces: fonts, SVG).
/// Then control point k of the window is the blossom at (a^{d-k}, b^k), the
/// k-th Bezier point, exactly: blossoming computes the same points.
inline bool bezier_window(const BSpline& spline, const Segment& s) {
  const int d = spline.degree(), first = s.span - d + 1;
  const std::vector<double>& u = spline.knots();
  for (int i = 0; i < d; ++i)
    if (u[first + i] != s.a || u[s.span + 1 + i] != s.b) return false;
  return true;
}

/// Bezier points of segment s in scalar type T (exactly for T = Rational).
template <class T>
std::vector<Point<T>> segment_bezier_points(const BSpline& spline, const Segment& s) {
  const SegmentWindow<T> w = segment_window<T>(spline, s);
  // Exact: a Bezier window's control points are its Bezier points (the
  // rational blossom, d(d+1)/2 GMP affine steps per point, is skipped).
  if constexpr (std::is_same_v<T, Rational>)
    if (bezier_window(spline, s)) return w.points;
  return bezier_points(w.knots, w.points, spline.degree(), w.span, T(s.a), T(s.b));
}

/// The homogeneous control points (w x, w y, w) of segment s's window in
/// scalar type T ((x, y, 1) for a polynomial spline), exact for T = Rational;
/// the window's knots are those of segment_window.
template <class T>
std::vector<HPoint<T>> homogeneous_window_points(const BSpline& spline, const Segment& s) {
  const int d = spline.degree(), first = s.span - d + 1;
  std::vector<HPoint<T>> pts;
  for (int i = 0; i <= d; ++i) pts.push_back(to_hpoint<T>(spline.points()[first + i], spline.weight(first + i)));
  return pts;
}

/// Homogeneous Bezier points H_k = F(a^{d-k}, b^k) of segment s in scalar
/// type T, F the blossom of (w x, w y, w): the rational segment is
/// sum B_k^d (H_k.x, H_k.y) / sum B_k^d H_k.z.
template <class T>
std::vector<HPoint<T>> segment_homogeneous_points(const BSpline& spline, const Segment& s) {
  const int d = spline.degree(), first = s.span - d + 1;
  const std::vector<T> knots(spline.knots().begin() + first, spline.knots().begin() + s.span + d + 1);
  return bezier_points(knots, homogeneous_window_points<T>(spline, s), d, d - 1, T(s.a), T(s.b));
}

/// Every non-empty span in Bezier form, by blossoming.
std::vector<BezierSegment> bezier_segments(const BSpline& spline);
BezierSegment bezier_segment(const BSpline& spline, const Segment& s);

/// Boehm's algorithm: the same curve with knot u inserted once. u must lie in
/// the domain and its multiplicity stay <= degree (InputError otherwise).
/// Polynomial splines only (InputError for a rational one; knot_ops.hpp's
/// insert_knot handles both).
/// In polar form, with u in the non-empty span j, the new points are
/// P_i (i <= j-d+1), (1-a_i) P_{i-1} + a_i P_i with a_i = (u - u_{i-1})/(u_{i+d-1} - u_{i-1})
/// (j-d+2 <= i <= j+1), and P_{i-1} (i >= j+2).
[[nodiscard]] BSpline insert_knot(const BSpline& spline, double u);

/// Every non-empty span in Bezier form, by inserting each interior knot and
/// the domain ends until their multiplicity is d (independent of the blossom
/// extraction; used to cross-check it).
std::vector<BezierSegment> bezier_segments_by_insertion(const BSpline& spline);

/// How a control point (or a group moving rigidly with it) drives the Bezier
/// points of the segments it touches: B_i = B_i^0 + w_i (p - P_k) when the
/// group is translated by p - P_k. w is the blossom of the scalar data that is
/// 1 on the group and 0 elsewhere.
struct SegmentInfluence {
  int segment = 0;           ///< index among the non-empty spans
  std::vector<double> w;     ///< d+1 weights, in [0, 1]
};
/// Segments touched by `group` (control point indices, validated by the caller)
/// and their weights. Segments with all weights 0 are left out.
std::vector<SegmentInfluence> influence(const BSpline& spline, const std::vector<int>& group);

}  // namespace cmr
