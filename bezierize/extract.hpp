#pragma once
// Internal to cmr::bezierize and the libraries above it: a library user
// includes `bezierize/analyze.hpp` (space curves:
// `bezierize/space_analyze.hpp`).
// Bezier form of B-spline segments, by blossoming (the primary route) and by
// repeated Boehm knot insertion (an independent route the tests compare with),
// and the affine influence of a control point on those Bezier points.
#include <cmath>
#include <optional>
#include <type_traits>
#include <vector>

#include "numeric/exact.hpp"
#include "numeric/tracked.hpp"
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

namespace extract_detail {

/// A coordinate the blossom of a Bezier span hands on unchanged (see
/// bezier_span_points): finite, not -0.0 (1 * -0.0 + 0 * y is +0.0 for
/// y >= 0), and for Tracked exact and 0 or of magnitude >= Tracked::kSafe
/// (1 * x is called exact there only).
template <class S>
bool passes_through(const S& x) {
  if constexpr (std::is_same_v<S, double>) {
    return std::isfinite(x) && !(x == 0 && std::signbit(x));
  } else if constexpr (std::is_same_v<S, Tracked>) {
    return x.e == 0 && std::isfinite(x.v) && (x.v == 0 ? !std::signbit(x.v) : std::fabs(x.v) >= Tracked::kSafe);
  } else {
    return true;  // Rational: exact arithmetic, one zero
  }
}

template <class S>
bool same_knot(const S& x, const S& y) {
  if constexpr (std::is_same_v<S, Tracked>) return x.e == 0 && y.e == 0 && x.v == y.v;
  else return x == y;
}

}  // namespace extract_detail

/// Bezier points of span j = [a, b] without evaluating the blossom, where
/// they are the span's control points bit for bit (values and Tracked
/// bounds); nullopt elsewhere (the caller blossoms).
///
/// A Bezier span: u_{j-d+1} = .. = u_j = a and u_{j+1} = .. = u_{j+d} = b
/// (every span of a font contour, of a Bezier curve, of a clamped spline's
/// span between two full knots). Then P_{j-d+1+k} = f(u_{j-d+1+k}, ..,
/// u_{j+k}) = f(a^{d-k}, b^k) = B_k. blossom_span computes the same value:
/// every denominator there is hi - lo = b - a = w, every numerator t - lo
/// and hi - t is 0 or w, so alpha and 1 - alpha are exactly 0 and 1 (0 / w
/// = 0, w / w = 1 for finite w != 0), and each step 1 * x + 0 * y (or
/// 0 * x + 1 * y) returns x (y) exactly unless it is -0.0. In Tracked
/// (numeric/tracked.hpp) each of those operations is also called exact, so
/// the bound stays 0, when a and b are exact, w = b - a is exact (TwoSum)
/// and >= kSafe, and every coordinate is exact and 0 or >= kSafe in
/// magnitude (passes_through). In rationals the arithmetic is exact. Not
/// for Bounded, which charges a rounding to every operation (the blossom's
/// bounds are not 0). Derivation checked by tests/bezierize/extract_test.cpp
/// (BezierSpanPoints.*) against blossom_span bit for bit.
template <class S, class P>
std::optional<std::vector<P>> bezier_span_points(const std::vector<S>& knots, const std::vector<P>& points, int d,
                                                 int j, const S& a, const S& b) {
  constexpr bool two_d = std::is_same_v<P, Vec2> || std::is_same_v<P, Vec2T<S>>;
  if constexpr (!two_d || !(std::is_same_v<S, double> || std::is_same_v<S, Tracked> || std::is_same_v<S, Rational>)) {
    return std::nullopt;
  } else {
    if (!extract_detail::same_knot(a, knots[j]) || !extract_detail::same_knot(b, knots[j + 1])) return std::nullopt;
    for (int i = j - d + 1; i < j; ++i)
      if (!extract_detail::same_knot(knots[i], a)) return std::nullopt;
    for (int i = j + 2; i <= j + d; ++i)
      if (!extract_detail::same_knot(knots[i], b)) return std::nullopt;
    if constexpr (std::is_same_v<S, double>) {
      const double w = b - a;
      if (!(std::isfinite(w) && w > 0)) return std::nullopt;
    } else if constexpr (std::is_same_v<S, Tracked>) {
      const Tracked w = b - a;
      if (w.e != 0 || !(w.v >= Tracked::kSafe) || !std::isfinite(w.v)) return std::nullopt;
    } else {
      if (!(b > a)) return std::nullopt;
    }
    std::vector<P> out(points.begin() + (j - d + 1), points.begin() + (j + 2));
    for (const P& p : out)
      if (!extract_detail::passes_through<S>(p.x) || !extract_detail::passes_through<S>(p.y)) return std::nullopt;
    return out;
  }
}

/// Bezier points of span j = [a, b]: B_k = f(a^{d-k}, b^k), k = 0..d.
/// Generic so that the classifier can run it with error bounds or exactly.
/// A Bezier span's are its control points (bezier_span_points: the same
/// values, taken without the blossom's O(d^3) operations).
template <class S, class P>
std::vector<P> bezier_points(const std::vector<S>& knots, const std::vector<P>& points, int degree, int span,
                             const S& a, const S& b) {
  if (std::optional<std::vector<P>> same = bezier_span_points(knots, points, degree, span, a, b)) return *same;
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
