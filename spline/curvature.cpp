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

}  // namespace

CurvatureSample curvature_at(const BSpline& spline, double t) {
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
  for (int k = 0; k < 3; ++k) {
    for (int i = 0; i < d; ++i) args[i] = i < d - k ? e : o;
    q[k] = blossom(spline, s, args.data());
  }
  // kappa at a Bezier end: (d-1)/d * det(q1-q0, q2-q1) / |q1-q0|^3, scaled by
  // the span length (which cancels in kappa, so work in the unit parameter).
  const Vec2 a = q[1] - q[0];
  const Vec2 b = q[2] - q[1];
  const double len = std::sqrt(dot(a, a));
  const double k = (d - 1.0) / d * det(a, b) / (len * len * len);
  // At the end the polygon is read backwards, which flips the turning sense.
  return side == 0 ? k : -k;
}

}  // namespace cmr
