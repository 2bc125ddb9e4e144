#include "bezierize/extract.hpp"

#include <algorithm>

#include "spline/errors.hpp"

namespace cmr {

BezierSegment bezier_segment(const BSpline& spline, const Segment& s) {
  if (!spline.is_rational()) return {s, bezier_points(spline.knots(), spline.points(), spline.degree(), s.span, s.a, s.b), {}};
  BezierSegment out{s, {}, {}};
  for (const glm::dvec3& h : bezier_points(spline.knots(), spline.homogeneous_points(), spline.degree(), s.span, s.a, s.b)) {
    out.points.push_back(Vec2(h.x, h.y) / h.z);
    out.weights.push_back(h.z);
  }
  return out;
}

std::vector<BezierSegment> bezier_segments(const BSpline& spline) {
  std::vector<BezierSegment> out;
  out.reserve(spline.segments().size());
  for (const Segment& s : spline.segments()) out.push_back(bezier_segment(spline, s));
  return out;
}

BSpline insert_knot(const BSpline& spline, double u) {
  if (!(u >= spline.domain_begin() && u <= spline.domain_end()))
    throw InputError("knot " + std::to_string(u) + " lies outside the domain");
  if (spline.is_rational()) throw InputError("Boehm insertion (extract.hpp) is for polynomial splines");
  const int d = spline.degree();
  if (spline.multiplicity(u) >= d)
    throw InputError("knot " + std::to_string(u) + " already has multiplicity " + std::to_string(d));
  const std::vector<double>& U = spline.knots();
  const std::vector<Vec2>& P = spline.points();
  const int m = spline.point_count();
  const int j = spline.segment_at(u).span;
  std::vector<Vec2> Q;
  Q.reserve(m + 1);
  for (int i = 0; i <= m; ++i) {
    if (i <= j - d + 1) {
      Q.push_back(P[i]);
    } else if (i >= j + 2) {
      Q.push_back(P[i - 1]);
    } else {
      const double lo = U[i - 1], hi = U[i + d - 1];
      const double a = (u - lo) / (hi - lo);
      Q.push_back((hi - u) / (hi - lo) * P[i - 1] + a * P[i]);
    }
  }
  std::vector<double> V = U;
  V.insert(std::upper_bound(V.begin(), V.end(), u), u);
  return BSpline::make(d, std::move(V), std::move(Q), spline.name());
}

std::vector<BezierSegment> bezier_segments_by_insertion(const BSpline& spline) {
  const int d = spline.degree();
  std::vector<double> values;
  for (const Segment& s : spline.segments()) {
    values.push_back(s.a);
    values.push_back(s.b);
  }
  values.erase(std::unique(values.begin(), values.end()), values.end());
  BSpline refined = spline;
  for (double v : values)
    while (refined.multiplicity(v) < d) refined = insert_knot(refined, v);
  // Now each segment [a, b] has a^d followed by b^d in the knot sequence, and
  // the point whose polar window starts at the first a^d is f(a^d) = B_0.
  std::vector<BezierSegment> out;
  const std::vector<double>& V = refined.knots();
  for (const Segment& s : spline.segments()) {
    const int first = static_cast<int>(std::lower_bound(V.begin(), V.end(), s.a) - V.begin());
    // Window of point i is V[i..i+d-1]; B_0 = f(a^d) is the point whose window is a^d.
    // lower_bound finds the first a; the a-run has length d, so i = first.
    std::vector<Vec2> pts(refined.points().begin() + first, refined.points().begin() + first + d + 1);
    out.push_back({s, std::move(pts), {}});
  }
  return out;
}

std::vector<SegmentInfluence> influence(const BSpline& spline, const std::vector<int>& group) {
  const int d = spline.degree();
  std::vector<double> e(spline.point_count(), 0.0);
  for (int k : group) {
    CMR_CHECK(k >= 0 && k < spline.point_count());
    e[k] = 1.0;
  }
  std::vector<SegmentInfluence> out;
  for (const Segment& s : spline.segments()) {
    const int first = s.span - d + 1;  // segment uses points first..first+d
    bool touched = false;
    for (int k : group) touched = touched || (k >= first && k <= first + d);
    if (!touched) continue;
    out.push_back({s.index, bezier_points(spline.knots(), e, d, s.span, s.a, s.b)});
  }
  return out;
}

}  // namespace cmr
