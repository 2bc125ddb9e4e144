#include "spline/curvature.hpp"

#include <cmath>

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
  Vec2 q[3];
  double w[3];
  for (int k = 0; k < 3; ++k) {
    for (int i = 0; i < d; ++i) args[i] = i < d - k ? e : o;
    const glm::dvec3 h = homogeneous_blossom(spline, s, args.data());
    q[k] = Vec2(h.x, h.y) / h.z;
    w[k] = h.z;
  }
  // kappa at a Bezier end: (d-1)/d * det(q1-q0, q2-q1) / |q1-q0|^3, scaled by
  // the span length (which cancels in kappa, so work in the unit parameter);
  // a rational Bezier end adds the factor w0 w2 / w1^2 (1 for a polynomial).
  const Vec2 a = q[1] - q[0];
  const Vec2 b = q[2] - q[1];
  const double len = std::sqrt(dot(a, a));
  const double k = (d - 1.0) / d * (w[0] * w[2] / (w[1] * w[1])) * det(a, b) / (len * len * len);
  // At the end the polygon is read backwards, which flips the turning sense.
  return side == 0 ? k : -k;
}

}  // namespace cmr
