#pragma once
// Internal to cmr::bezierize and the libraries above it: a library user
// includes `bezierize/analyze.hpp` (space curves:
// `bezierize/space_analyze.hpp`).
// Knot operations on polar-form B-splines (Ramshaw): insertion, removal,
// moving one knot, clamping, uniform knots, degree elevation and refinement.
// Every operation is const and returns a new, validated BSpline.
//
// One primitive. Insertion, clamping, refinement and elevation all write the
// same curve on a finer knot vector V (of degree d or d+1). In polar form the
// new control point i is G(V_i, ..., V_{i+d'-1}), where G is the blossom of
// the curve's piece on any non-empty span that point i influences (Ramshaw's
// consistency: all such pieces agree on that window). Every new span lies
// inside one old segment, so G is that segment's blossom f (degree d), or its
// degree-raised blossom F (below). A new point whose window equals an old
// point's window is that old point, copied bit for bit. A new point that
// influences no non-empty span (possible only at the ends, next to empty
// spans) does not change the curve; it gets the blossom of the nearest segment.
// `rewrite_on_knots` is this primitive, generic over the scalar so that the
// tests run it in exact rationals. A rational curve (weights) goes through it
// in homogeneous coordinates (w x, w y, w) and is projected back; removal is
// not offered for rational curves.
//
// Degree elevation. For a polynomial of degree d with blossom f,
//   F(x_1, ..., x_{d+1}) = 1/(d+1) * sum_{i=1..d+1} f(x_1, ..., x_{i-1}, x_{i+1}, ..., x_{d+1})
// is its blossom as a polynomial of degree d+1: F is symmetric (the sum runs
// over every omitted argument); it is affine in each x_j (x_j appears in d of
// the d+1 terms, each affine in it, and the remaining term does not depend on
// it); and on the diagonal F(t, ..., t) = (d+1)/(d+1) f(t, ..., t) = C(t). The
// blossom is unique, so F is it. The knot vector keeps each interior knot's
// continuity C^{d-k} by raising every knot value in the domain [a, b] (ends
// included) to multiplicity k+1; knots outside the domain stay as they are.
//
// Removal. Removing one copy of an interior knot u of multiplicity k from V
// gives W. The points of W whose windows do not hold u are kept; the d-k
// others are unknowns. Boehm insertion of u into W must give V back; solving
// those equations from the left is (by multi-affinity, induction over the
// points) the blossom f_L of the segment ending at u evaluated on the W
// windows, and from the right it is f_R of the segment starting at u. The
// first half of the unknowns is taken from f_L, the second half from f_R, a
// middle one (d-k odd) is their average (Tiller's scheme; exactly the old curve
// when u is removable, f_L = f_R). The new curve is then measured against the
// old one.
#include <algorithm>
#include <numeric>
#include <type_traits>
#include <vector>

#include "bezierize/extract.hpp"
#include "spline/blossom.hpp"
#include "spline/bspline.hpp"
#include "spline/limits.hpp"

namespace cmr {

/// A B-spline's data in scalar type S (double, or Rational in the tests),
/// without the validation of BSpline: the operations below keep it valid.
template <class S>
struct PolarSpline {
  int degree = 0;
  std::vector<S> knots;
  std::vector<Point<S>> points;
};

template <class S>
PolarSpline<S> polar_spline(const BSpline& s) {
  PolarSpline<S> p{s.degree(), std::vector<S>(s.knots().begin(), s.knots().end()), {}};
  for (const Vec2& q : s.points()) p.points.push_back(to_point<S>(q));
  return p;
}

/// Knot index j of a non-empty span [knots[j], knots[j+1]] of degree `degree`
/// with m points that holds [c, e] (c < e), within the domain; -1 if none.
template <class S>
int span_holding(const std::vector<S>& knots, int degree, int m, const S& c, const S& e) {
  const int j = static_cast<int>(std::upper_bound(knots.begin(), knots.end(), c) - knots.begin()) - 1;
  if (j < degree - 1 || j > m - 2 || !(knots[j + 1] >= e)) return -1;
  return j;
}

/// f(args) of `s`'s piece on span j, raised to `degree` >= s.degree by the
/// symmetric average above (applied degree - s.degree times). args has `degree` values.
template <class S>
Point<S> raised_blossom(const PolarSpline<S>& s, int j, std::vector<S> args, int degree) {
  if (degree == s.degree) return blossom_span(s.knots, s.points, s.degree, j, args.data());
  Point<S> sum = raised_blossom(s, j, std::vector<S>(args.begin() + 1, args.end()), degree - 1);
  for (int i = 1; i < degree; ++i) {
    std::vector<S> rest(args);
    rest.erase(rest.begin() + i);
    sum = sum + raised_blossom(s, j, std::move(rest), degree - 1);
  }
  const S inverse = S(1) / S(degree);
  return inverse * sum;
}

/// The old point whose window equals new window `w` (d values), or -1.
template <class S>
int same_window(const std::vector<S>& knots, int degree, const S* w) {
  const int lead = static_cast<int>(std::find_if(w, w + degree, [&](const S& x) { return x != w[0]; }) - w);
  const int q = static_cast<int>(std::upper_bound(knots.begin(), knots.end(), w[0]) - knots.begin()) - lead;
  if (q < 0 || q + degree > static_cast<int>(knots.size())) return -1;
  return std::equal(w, w + degree, knots.begin() + q) ? q : -1;
}

/// The curve of `s` written on knot vector `knots` of degree `degree`
/// (s.degree or more). Precondition (the callers' business): `knots` is a
/// refinement, i.e. the same domain, every new non-empty span inside one old
/// segment, and each interior knot's continuity at most the old one.
template <class S>
PolarSpline<S> rewrite_on_knots(const PolarSpline<S>& s, std::vector<S> knots, int degree) {
  const int m_old = static_cast<int>(s.points.size());
  const int m = static_cast<int>(knots.size()) - degree + 1;
  std::vector<int> segments;  // non-empty new spans in the domain
  for (int j = degree - 1; j <= m - 2; ++j)
    if (knots[j] < knots[j + 1]) segments.push_back(j);
  CMR_CHECK(!segments.empty());
  PolarSpline<S> out{degree, std::move(knots), {}};
  out.points.reserve(m);
  for (int i = 0; i < m; ++i) {
    const S* w = out.knots.data() + i;
    const int copy = degree == s.degree ? same_window(s.knots, degree, w) : -1;
    if (copy >= 0) {
      out.points.push_back(s.points[copy]);
      continue;
    }
    // Point i influences new spans i-1 .. i+degree-2: take the first segment there, else the nearest one.
    auto it = std::lower_bound(segments.begin(), segments.end(), i - 1);
    const int j = it == segments.end() ? segments.back() : *it;
    const int old = span_holding(s.knots, s.degree, m_old, out.knots[j], out.knots[j + 1]);
    CMR_CHECK(old >= 0);
    out.points.push_back(raised_blossom(s, old, std::vector<S>(w, w + degree), degree));
  }
  return out;
}

/// `knots` with u added `times` times (kept sorted).
template <class S>
std::vector<S> knots_with(std::vector<S> knots, const S& u, int times) {
  knots.insert(std::upper_bound(knots.begin(), knots.end(), u), times, u);
  return knots;
}

/// Knots for degree elevation: every value in [a, b] gains one copy.
template <class S>
std::vector<S> elevated_knots(const std::vector<S>& knots, const S& a, const S& b) {
  std::vector<S> out;
  for (std::size_t i = 0; i < knots.size(); ++i) {
    out.push_back(knots[i]);
    const bool last_copy = i + 1 == knots.size() || knots[i + 1] != knots[i];
    if (last_copy && knots[i] >= a && knots[i] <= b) out.push_back(knots[i]);
  }
  return out;
}

/// Clamped knots: a and b with multiplicity d, the knots strictly inside (a, b)
/// as they are, nothing outside.
template <class S>
std::vector<S> clamped_knots(const std::vector<S>& knots, int degree, const S& a, const S& b) {
  std::vector<S> out(degree, a);
  for (const S& u : knots)
    if (u > a && u < b) out.push_back(u);
  out.insert(out.end(), degree, b);
  return out;
}

/// Points of the spline on knots W = V minus one copy of the interior knot at
/// index r (the last copy of its run; r is a knot index of s). See "Removal".
template <class S>
PolarSpline<S> remove_knot_at(const PolarSpline<S>& s, int r) {
  const int d = s.degree, m = static_cast<int>(s.points.size());
  const S u = s.knots[r];
  const int first = static_cast<int>(std::lower_bound(s.knots.begin(), s.knots.end(), u) - s.knots.begin());
  const int k = r - first + 1;           // multiplicity of u in V
  const int left = first - 1, right = r;  // segments [.., u] and [u, ..] (knot indices)
  PolarSpline<S> out{d, s.knots, {}};
  out.knots.erase(out.knots.begin() + r);
  // W-points lo..hi are unknown (their W windows hold all k-1 copies of u and
  // more than the copies' neighbours on one side); the others are V's points.
  const int lo = first + k - d, hi = first - 1;
  for (int i = 0; i < m - 1; ++i) {
    if (i < lo) {
      out.points.push_back(s.points[i]);
    } else if (i > hi) {
      out.points.push_back(s.points[i + 1]);
    } else {
      const S* w = out.knots.data() + i;
      const int from_lo = i - lo, from_hi = hi - i;  // which known neighbour is nearer
      const Point<S> fl = blossom_span(s.knots, s.points, d, left, w);
      const Point<S> fr = blossom_span(s.knots, s.points, d, right, w);
      const S half = S(1) / S(2);
      if (from_lo < from_hi) out.points.push_back(fl);
      else if (from_hi < from_lo) out.points.push_back(fr);
      else out.points.push_back(half * (fl + fr));
    }
  }
  return out;
}

/// Refined knots: the midpoint of every non-empty span [a, b] of the domain
/// added once (a span whose midpoint rounds to one of its ends, two adjacent
/// doubles, is left as it is).
template <class S>
std::vector<S> refined_knots(const std::vector<S>& knots, int degree, int m) {
  std::vector<S> out;
  for (int j = 0; j < static_cast<int>(knots.size()); ++j) {
    out.push_back(knots[j]);
    if (j < degree - 1 || j > m - 2 || !(knots[j] < knots[j + 1])) continue;
    S mid;
    if constexpr (std::is_floating_point_v<S>) mid = std::midpoint(knots[j], knots[j + 1]);
    else mid = (knots[j] + knots[j + 1]) / S(2);
    if (knots[j] < mid && mid < knots[j + 1]) out.push_back(mid);
  }
  return out;
}

/// The same curve with knot u inserted `times` times (blossom, see above).
/// InputError when times < 1, u is not finite or outside the domain [a, b]
/// ("knot 9 lies outside the domain [2, 5]"), or u's multiplicity would pass
/// the degree ("knot 3 has multiplicity 1; inserting it 3 times makes 4, above
/// the degree 3").
[[nodiscard]] BSpline insert_knot(const BSpline& spline, double u, int times);

/// The result of remove_knot.
struct KnotRemoval {
  BSpline spline;
  /// Largest deviation between the old and the new curve, as an upper bound:
  /// on every interval between consecutive old knots of the domain, the
  /// difference of the two curves is a polynomial whose Bezier points D_k are
  /// the differences of the two curves' Bezier points there; by the convex
  /// hull property |C_old(t) - C_new(t)| <= max_k |D_k|. `distance` is the
  /// largest |D_k| over all intervals. It is 0 exactly when the curve is
  /// unchanged and never below the true deviation at the knots (D_0 and D_d
  /// are point differences), so a removal is never accepted that moves the
  /// curve by more than the tolerance (up to the rounding of the Bezier points).
  double distance = 0;
};
/// Removes one copy of the interior knot u (see "Removal"). `tolerance` is
/// absolute, in the units of the control points. InputError when
/// u is not a knot, not strictly inside the domain, the tolerance is negative
/// or NaN, or distance > tolerance: "removing knot 3 moves the curve by up to
/// 0.25, more than the tolerance 1e-09".
[[nodiscard]] KnotRemoval remove_knot(const BSpline& spline, double u, double tolerance);

/// The spline with knot `index` set to u and the same control points (the
/// curve changes). InputError when index is outside 0..K-1, and as
/// BSpline::make for order, multiplicity and finiteness
/// ("set knot 4 to 2.5: knots[4] (2.5) is smaller than knots[3] (3)").
[[nodiscard]] BSpline set_knot(const BSpline& spline, int index, double u);

/// The same curve on its domain [a, b] with a and b of multiplicity d (the
/// Bezier end conditions): a and b are inserted up to multiplicity d and the
/// knots outside [a, b] are dropped together with the points that only they
/// influenced.
[[nodiscard]] BSpline clamp(const BSpline& spline);

/// The same control points on the knots 0, 1, 2, ..., m+d-2. The curve
/// changes (it becomes a uniform B-spline on the domain [d-1, m-1]).
[[nodiscard]] BSpline make_uniform(const BSpline& spline);

/// The same curve at degree d+1 (see "Degree elevation"). InputError when
/// d+1 > kMaxDegree.
[[nodiscard]] BSpline elevate_degree(const BSpline& spline);

/// The same curve with a knot at the midpoint of every non-empty span.
[[nodiscard]] BSpline refine(const BSpline& spline);

/// The default removal tolerance of the command line, relative to the
/// spline's extent (the larger side of its control points' bounding box).
inline constexpr double kRemovalRelativeTolerance = 1e-9;
/// The larger side of the control points' bounding box (at least the
/// smallest positive double, so that relative tolerances stay positive).
double extent(const BSpline& spline);

}  // namespace cmr
