#include "bezierize/knot_ops.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <string>

#include <glm/common.hpp>

#include "spline/errors.hpp"

namespace cmr {
namespace {

/// The shortest text that reads back as v.
std::string num(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

std::string domain_text(const BSpline& s) {
  return "[" + num(s.domain_begin()) + ", " + num(s.domain_end()) + "]";
}

void check_finite_knot(double u) {
  if (!std::isfinite(u)) throw InputError("knot value " + num(u) + " is not a finite number");
}

BSpline to_bspline(PolarSpline<double> p, const BSpline& like) {
  return BSpline::make(p.degree, std::move(p.knots), std::move(p.points), like.name());
}

BSpline rewrite(const BSpline& s, std::vector<double> knots, int degree) {
  if (!s.is_rational()) return to_bspline(rewrite_on_knots(polar_spline<double>(s), std::move(knots), degree), s);
  // A rational curve is rewritten in homogeneous coordinates: the same
  // primitive on the points (w x, w y) and on the weights (carried as (w, 0)),
  // then projected back. New weights are convex combinations (averages, for
  // elevation) of the old ones: positive weights stay positive; with weights
  // of mixed sign (bspline.hpp) a new weight can be 0. Its homogeneous point
  // (W x, W y, W) is then 0 when the curve allows it (any point, here the
  // origin, gives that), or a point at infinity, which the (x, y, w) form
  // cannot hold: an InputError naming it.
  PolarSpline<double> xy{s.degree(), s.knots(), {}}, w{s.degree(), s.knots(), {}};
  for (int i = 0; i < s.point_count(); ++i) {
    xy.points.push_back(s.weight(i) * s.points()[i]);
    w.points.push_back(Vec2(s.weight(i), 0.0));
  }
  PolarSpline<double> rxy = rewrite_on_knots(xy, knots, degree);
  const PolarSpline<double> rw = rewrite_on_knots(w, std::move(knots), degree);
  std::vector<double> weights;
  for (std::size_t i = 0; i < rxy.points.size(); ++i) {
    weights.push_back(rw.points[i].x);
    if (rw.points[i].x != 0) {
      rxy.points[i] /= rw.points[i].x;
    } else if (rxy.points[i] != Vec2(0.0)) {
      throw InputError("control point " + std::to_string(i) +
                       " of the result would have weight 0 and lie at infinity (its homogeneous point is not 0); "
                       "cmr's (x, y, w) points cannot hold it");
    }
  }
  return BSpline::make(degree, std::move(rxy.knots), std::move(rxy.points), s.name(), std::move(weights));
}

/// Upper bound of |old(t) - new(t)| over the domain (see KnotRemoval::distance).
/// Every segment of `fine` lies inside one segment of `coarse`.
double deviation_bound(const BSpline& fine, const BSpline& coarse) {
  double worst = 0;
  for (const Segment& s : fine.segments()) {
    const Segment& c = coarse.segment_at(s.a);
    const auto p = bezier_points(fine.knots(), fine.points(), fine.degree(), s.span, s.a, s.b);
    const auto q = bezier_points(coarse.knots(), coarse.points(), coarse.degree(), c.span, s.a, s.b);
    for (std::size_t k = 0; k < p.size(); ++k) worst = std::max(worst, std::hypot(p[k].x - q[k].x, p[k].y - q[k].y));
  }
  return worst;
}

}  // namespace

BSpline insert_knot(const BSpline& spline, double u, int times) {
  check_finite_knot(u);
  const int d = spline.degree();
  if (times < 1) throw InputError("insert: times must be at least 1 (got " + std::to_string(times) + ")");
  if (u < spline.domain_begin() || u > spline.domain_end())
    throw InputError("knot " + num(u) + " lies outside the domain " + domain_text(spline));
  const int k = spline.multiplicity(u);
  if (k + times > d)
    throw InputError("knot " + num(u) + " has multiplicity " + std::to_string(k) + "; inserting it " +
                     std::to_string(times) + " times makes " + std::to_string(k + times) + ", above the degree " +
                     std::to_string(d));
  return rewrite(spline, knots_with(spline.knots(), u, times), d);
}

KnotRemoval remove_knot(const BSpline& spline, double u, double tolerance) {
  check_finite_knot(u);
  if (spline.is_rational())
    throw InputError("remove: knot removal is not supported for rational curves (the file has weights)");
  if (!(tolerance >= 0)) throw InputError("remove: the tolerance must be zero or more (got " + num(tolerance) + ")");
  const std::vector<double>& V = spline.knots();
  const auto last = std::upper_bound(V.begin(), V.end(), u);
  if (last == V.begin() || *(last - 1) != u) throw InputError("knot " + num(u) + " is not in the knot vector");
  if (!(u > spline.domain_begin() && u < spline.domain_end()))
    throw InputError("knot " + num(u) + " is not inside the domain " + domain_text(spline) +
                     "; only interior knots can be removed");
  const int r = static_cast<int>(last - V.begin()) - 1;
  KnotRemoval out{to_bspline(remove_knot_at(polar_spline<double>(spline), r), spline), 0};
  out.distance = deviation_bound(spline, out.spline);
  if (out.distance > tolerance)
    throw InputError("removing knot " + num(u) + " moves the curve by up to " + num(out.distance) +
                     ", more than the tolerance " + num(tolerance));
  return out;
}

BSpline set_knot(const BSpline& spline, int index, double u) {
  const int count = static_cast<int>(spline.knots().size());
  if (index < 0 || index >= count)
    throw InputError("knot index " + std::to_string(index) + " is out of range 0.." + std::to_string(count - 1));
  check_finite_knot(u);
  std::vector<double> knots = spline.knots();
  knots[index] = u;
  try {
    return BSpline::make(spline.degree(), std::move(knots), spline.points(), spline.name(), spline.weights());
  } catch (const InputError& e) {
    throw InputError("set knot " + std::to_string(index) + " to " + num(u) + ": " + e.what());
  }
}

BSpline clamp(const BSpline& spline) {
  return rewrite(spline,
                 clamped_knots(spline.knots(), spline.degree(), spline.domain_begin(), spline.domain_end()),
                 spline.degree());
}

BSpline make_uniform(const BSpline& spline) {
  std::vector<double> knots(spline.knots().size());
  std::iota(knots.begin(), knots.end(), 0.0);
  return BSpline::make(spline.degree(), std::move(knots), spline.points(), spline.name(), spline.weights());
}

BSpline elevate_degree(const BSpline& spline) {
  const int d = spline.degree();
  if (d + 1 > kMaxDegree)
    throw InputError("elevate: degree " + std::to_string(d) + " cannot be raised; " + std::to_string(kMaxDegree) +
                     " is the highest degree supported");
  return rewrite(spline, elevated_knots(spline.knots(), spline.domain_begin(), spline.domain_end()), d + 1);
}

BSpline refine(const BSpline& spline) {
  return rewrite(spline, refined_knots(spline.knots(), spline.degree(), spline.point_count()), spline.degree());
}

double extent(const BSpline& spline) {
  Vec2 lo = spline.points().front(), hi = lo;
  for (const Vec2& p : spline.points()) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  return std::max({hi.x - lo.x, hi.y - lo.y, std::numeric_limits<double>::min()});
}

}  // namespace cmr
