#include "spline/curvature.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>

#include "spline/blossom.hpp"

namespace cmr {
namespace {

CurvatureSample from_derivatives(double t, Vec2 c, Vec2 d1, Vec2 d2, Vec2 d3) {
  CurvatureSample out;
  out.t = t;
  out.point = c;
  const double g = dot(d1, d1);
  out.eta = det(d1, d2);
  out.lambda = det(d1, d3) * g - 3.0 * out.eta * dot(d1, d2);
  out.kappa = out.eta / (g * std::sqrt(g));
  out.dkappa_ds = out.lambda / (g * g * g);
  return out;
}

double det3(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  return a.x * (b.y * c.z - b.z * c.y) - a.y * (b.x * c.z - b.z * c.x) + a.z * (b.x * c.y - b.y * c.x);
}

// The rational formulas of curvature.hpp from H, H', H'', H'''.
CurvatureSample from_homogeneous(double t, const glm::dvec3 H[4]) {
  CurvatureSample out;
  out.t = t;
  const double w = H[0].z, w1 = H[1].z, w2 = H[2].z;
  out.point = Vec2(H[0].x, H[0].y) / w;
  const Vec2 X(H[0].x, H[0].y), X1(H[1].x, H[1].y), X2(H[2].x, H[2].y);
  const Vec2 h = w * X1 - w1 * X;
  const Vec2 h1 = w * X2 - w2 * X;  // (W X' - W' X)' = W X'' - W'' X
  const double D = det3(H[0], H[1], H[2]);
  const double D1 = det3(H[0], H[1], H[3]);
  const double hh = dot(h, h);
  out.eta = D;
  out.lambda = (3 * w1 * D + w * D1) * hh - 3 * w * D * dot(h, h1);
  const double len = std::sqrt(hh);
  out.kappa = w * w * w * D / (hh * len);
  out.dkappa_ds = w * w * w * w * out.lambda / (hh * hh * hh);
  return out;
}

}  // namespace

CurvatureSample curvature_at(const BSpline& spline, double t) {
  if (spline.is_rational()) {
    glm::dvec3 H[4];
    for (int r = 0; r < 4; ++r) H[r] = r <= spline.degree() ? homogeneous_derivative(spline, t, r) : glm::dvec3(0.0);
    return from_homogeneous(t, H);
  }
  const Vec2 d3 = spline.degree() >= 3 ? derivative(spline, t, 3) : Vec2(0.0);
  return from_derivatives(t, evaluate(spline, t), derivative(spline, t, 1), derivative(spline, t, 2), d3);
}

double curvature(const BSpline& spline, double t) { return curvature_at(spline, t).kappa; }

double segment_end_curvature(const BSpline& spline, const Segment& s, int side) {
  // Bezier points of the segment near the chosen end: f(e^{d-k}, o^k), k = 0..2.
  const int d = spline.degree();
  const double e = side == 0 ? s.a : s.b;
  const double o = side == 0 ? s.b : s.a;
  std::vector<double> args(d, e);
  glm::dvec3 h[3];
  for (int k = 0; k < 3; ++k) {
    for (int i = 0; i < d; ++i) args[i] = i < d - k ? e : o;
    h[k] = homogeneous_blossom(spline, s, args.data());
  }
  // kappa at a Bezier end: (d-1)/d * A / |g|^3 in the unit parameter (the
  // span length cancels), g = w0 X1 - w1 X0 and A = w0^3 det3(H0, H1, H2)
  // for homogeneous points H_k = (X_k, w_k), any signs of w (cmr::end_terms,
  // bezierize/decide.hpp); for w = 1: g = q1 - q0, A = det(q1 - q0, q2 - q1).
  if (h[0].z > 0 && h[1].z > 0 && h[2].z > 0) {
    // Positive weights: the classical form, (w0 w2 / w1^2) det(a, b) / |a|^3
    // with a, b the legs of the projected points (1 for a polynomial).
    const Vec2 q0 = Vec2(h[0].x, h[0].y) / h[0].z, q1 = Vec2(h[1].x, h[1].y) / h[1].z,
               q2 = Vec2(h[2].x, h[2].y) / h[2].z;
    const Vec2 a = q1 - q0, b = q2 - q1;
    const double len = std::sqrt(dot(a, a));
    const double k = (d - 1.0) / d * (h[0].z * h[2].z / (h[1].z * h[1].z)) * det(a, b) / (len * len * len);
    return side == 0 ? k : -k;
  }
  const Vec2 x0(h[0].x, h[0].y), x1(h[1].x, h[1].y);
  const Vec2 g = h[0].z * x1 - h[1].z * x0;
  const double len = std::sqrt(dot(g, g));
  const double A = h[0].z * h[0].z * h[0].z * det3(h[0], h[1], h[2]);
  const double k = (d - 1.0) / d * A / (len * len * len);
  // At the end the polygon is read backwards, which flips the turning sense.
  return side == 0 ? k : -k;
}

CurveSampler::CurveSampler(const BSpline& spline) : spline_(&spline) {
  Vec2 lo(std::numeric_limits<double>::infinity()), hi(-lo);
  for (const Vec2& p : spline.points()) lo = glm::min(lo, p), hi = glm::max(hi, p);
  // Widened by the larger side (at least a relative 1e-9 of the coordinates,
  // so that rounding never puts a straight curve's points outside).
  const double big = std::max({std::fabs(lo.x), std::fabs(lo.y), std::fabs(hi.x), std::fabs(hi.y)});
  double margin = std::max({hi.x - lo.x, hi.y - lo.y, 1e-9 * big});
  if (!(margin > 0)) margin = 1;  // every point at the origin
  lo_ = lo - Vec2(margin);
  hi_ = hi + Vec2(margin);
}

bool CurveSampler::inside(Vec2 p) const {
  return std::isfinite(p.x) && std::isfinite(p.y) && p.x >= lo_.x && p.x <= hi_.x && p.y >= lo_.y && p.y <= hi_.y;
}

std::optional<Vec2> CurveSampler::at(double t) const {
  const Vec2 p = evaluate(*spline_, t);
  if (!inside(p)) return std::nullopt;
  return p;
}

bool CurveSampler::joins(double t0, double t1) const {
  if (!spline_->is_rational()) return true;
  const double w0 = homogeneous_derivative(*spline_, t0, 0).z, w1 = homogeneous_derivative(*spline_, t1, 0).z;
  return (w0 > 0 && w1 > 0) || (w0 < 0 && w1 < 0);
}

}  // namespace cmr
