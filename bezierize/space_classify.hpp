#pragma once
// Internal (scalar types): the certified classification of one space segment
// from the control points of its window, shared by analyze_space
// (space_analyze.cpp) and the plane regions (space_region.cpp), which hand in
// moved points. Algorithm 1 runs on lambda3 (space_lambda.hpp) through the one
// decision core (decide.hpp: BernsteinSource, traverse, MonotonicityFold via
// algorithm1): first with error bounds (Bounded), then, where a sign that
// matters is uncertain, exactly (Rational). The same for torsion on
// T = N'|c|^2 - N(|c|^2)'.
#include <optional>
#include <vector>

#include "bezierize/algorithms.hpp"
#include "bezierize/space_lambda.hpp"
#include "spline/blossom.hpp"
#include "spline/space.hpp"

namespace cmr {

/// What segment s depends on: knots u_{j-d+1}..u_{j+d} (segment = span d-1
/// of the window) and the d+1 control points P_{j-d+1}..P_{j+1}.
struct SpaceWindow {
  int degree = 0;
  int first = 0;  ///< index of the window's first control point in the spline
  std::vector<double> knots;
  double a = 0, b = 0;
};

inline SpaceWindow space_window(const SpaceSpline& spline, const Segment& s) {
  const int d = spline.degree();
  SpaceWindow w;
  w.degree = d;
  w.first = s.span - d + 1;
  w.knots.assign(spline.knots().begin() + w.first, spline.knots().begin() + s.span + d + 1);
  w.a = s.a;
  w.b = s.b;
  return w;
}

template <class T>
std::vector<Point3<T>> space_window_points(const SpaceSpline& spline, const SpaceWindow& w) {
  std::vector<Point3<T>> pts;
  for (int i = 0; i <= w.degree; ++i) {
    const Vec3& p = spline.points()[static_cast<std::size_t>(w.first + i)];
    pts.push_back(Point3<T>{T(p.x), T(p.y), T(p.z)});
  }
  return pts;
}

/// The window's homogeneous points (w x, w y, w z, w) of a rational spline,
/// in scalar T (exact for Rational: each a product of two doubles).
template <class T>
HPoint3<T> to_hpoint3(const Point3<T>& p, double weight) {
  const T w(weight);
  return HPoint3<T>{p.x * w, p.y * w, p.z * w, w};
}

template <class T>
std::vector<HPoint3<T>> space_window_hpoints(const SpaceSpline& spline, const SpaceWindow& w) {
  std::vector<HPoint3<T>> pts;
  for (int i = 0; i <= w.degree; ++i) {
    const Vec3& p = spline.points()[static_cast<std::size_t>(w.first + i)];
    pts.push_back(to_hpoint3<T>(Point3<T>{T(p.x), T(p.y), T(p.z)}, spline.weight(w.first + i)));
  }
  return pts;
}

/// Bezier points B_k = f(a^{d-k}, b^k) of the window's segment, in scalar T
/// (exact for Rational); P is Point3<T> or, for a rational spline, HPoint3<T>.
template <class T, class P>
std::vector<P> space_window_bezier_of(const SpaceWindow& w, const std::vector<P>& pts) {
  const std::vector<T> knots(w.knots.begin(), w.knots.end());
  const int d = w.degree;
  std::vector<P> out;
  std::vector<T> args(d);
  for (int k = 0; k <= d; ++k) {
    for (int i = 0; i < d; ++i) args[i] = T(i < d - k ? w.a : w.b);
    out.push_back(blossom_span(knots, pts, d, d - 1, args.data()));
  }
  return out;
}
template <class T>
std::vector<Point3<T>> space_window_bezier(const SpaceWindow& w, const std::vector<Point3<T>>& pts) {
  return space_window_bezier_of<T>(w, pts);
}
template <class T>
std::vector<HPoint3<T>> space_window_bezier(const SpaceWindow& w, const std::vector<HPoint3<T>>& pts) {
  return space_window_bezier_of<T>(w, pts);
}

/// Cartesian points and weights of homogeneous ones (exact for Rational; W > 0).
template <class T>
void split_homogeneous(const std::vector<HPoint3<T>>& H, std::vector<Point3<T>>& P, std::vector<T>& w) {
  for (const HPoint3<T>& h : H) {
    P.push_back(Point3<T>{T(h.x / h.w), T(h.y / h.w), T(h.z / h.w)});
    w.push_back(h.w);
  }
}

/// Algorithm 1 on lambda3 (curvature) or on T (torsion) of one segment, given
/// its window points by two makers (Bounded first; Rational only when needed).
struct SpaceDecision {
  MonotonicityResult result;
  bool exact_used = false;
};

enum class SpaceQuantity { curvature, torsion };

template <class T, class P>
Bernstein<T> space_quantity_bernstein(const std::vector<P>& B, SpaceQuantity q) {
  if (q == SpaceQuantity::curvature) return lambda3_bernstein<T>(B);
  Bernstein<T> t = torsion_sign_bernstein<T>(B);
  if (t.empty()) t.assign(1, T(0));  // a quadratic: tau == 0, constant
  return t;
}

template <class MakeBounded, class MakeExact>
SpaceDecision space_decide(const SpaceWindow& w, SpaceQuantity q, int max_depth, MakeBounded make_bounded,
                           MakeExact make_exact) {
  SpaceDecision d;
  const auto bounded = algorithm1(space_quantity_bernstein<Bounded>(space_window_bezier<Bounded>(w, make_bounded()), q),
                                  max_depth);
  if (bounded) {
    d.result = *bounded;
    return d;
  }
  const auto exact = algorithm1(space_quantity_bernstein<Rational>(space_window_bezier<Rational>(w, make_exact()), q),
                                max_depth);
  CMR_CHECK(exact.has_value());
  d.result = *exact;
  d.exact_used = true;
  return d;
}

}  // namespace cmr
