#pragma once
// Shared test helpers: seeded random splines and an independent Cox-de Boor
// evaluator (the reference the blossom is checked against).
#include <cmath>
#include <random>
#include <vector>

#include "spline/bspline.hpp"

namespace cmr::test {

/// Cox-de Boor recursion on the conventional knot vector t_0..t_{m+d}
/// (t_{i+1} = u_i; the two extra end knots do not affect the domain).
inline Vec2 cox_de_boor(const BSpline& s, double x) {
  const int d = s.degree(), m = s.point_count();
  std::vector<double> t(m + d + 1);
  for (int i = 0; i < m + d - 1; ++i) t[i + 1] = s.knots()[i];
  t[0] = t[1];
  t[m + d] = t[m + d - 1];
  // Find span k with t_k <= x < t_{k+1}, d <= k <= m-1 (last non-empty for the end).
  int k = d;
  for (int i = d; i <= m - 1; ++i)
    if (t[i] < t[i + 1] && t[i] <= x) k = i;
  // N_{i,0} on span k, raised to degree d (only the d+1 non-zero functions).
  std::vector<double> N(d + 1, 0.0);
  N[d] = 1.0;  // N_{k,0}
  for (int p = 1; p <= d; ++p) {
    for (int r = d - p; r <= d; ++r) {
      const int i = k - d + r;  // basis index
      double v = 0;
      const double l = t[i + p] - t[i];
      if (l > 0) v += (x - t[i]) / l * N[r];
      if (r + 1 <= d) {
        const double rr = t[i + p + 1] - t[i + 1];
        if (rr > 0) v += (t[i + p + 1] - x) / rr * N[r + 1];
      }
      N[r] = v;
    }
  }
  Vec2 c(0.0);
  for (int r = 0; r <= d; ++r) c += N[r] * s.points()[k - d + r];
  return c;
}

/// A single polynomial curve written as a B-spline with the given polar knots:
/// P_i = f(u_i..u_{i+d-1}) where f is the blossom of the Bezier curve `bezier`
/// reparametrised so that [0, 1] maps onto the new domain.
inline BSpline polynomial_as_bspline(const BSpline& bezier, std::vector<double> knots) {
  const int d = bezier.degree();
  const int m = static_cast<int>(knots.size()) - d + 1;
  const double lo = knots[d - 1], hi = knots[m - 1];
  std::vector<Vec2> P;
  std::vector<double> args(d);
  for (int i = 0; i < m; ++i) {
    for (int k = 0; k < d; ++k) args[k] = (knots[i + k] - lo) / (hi - lo);
    P.push_back(blossom(bezier, bezier.segments()[0], args.data()));
  }
  return BSpline::make(d, std::move(knots), std::move(P));
}

/// Planar "class A" Bezier curve: legs v, Mv, M^2 v, ... with M a rotation by
/// `angle` and a scaling by `scale`. Clockwise for angle < 0; its |curvature|
/// shrinks along the curve when scale > 1.
inline BSpline class_a_bezier(int degree, double angle, double scale) {
  std::vector<Vec2> P = {Vec2(0, 0)};
  Vec2 v(1, 0);
  for (int i = 0; i < degree; ++i) {
    P.push_back(P.back() + v);
    const double c = std::cos(angle), s = std::sin(angle);
    v = scale * Vec2(c * v.x - s * v.y, s * v.x + c * v.y);
  }
  return BSpline::bezier(std::move(P));
}

inline std::vector<Vec2> random_points(std::mt19937_64& rng, int count, double scale = 1.0) {
  std::uniform_real_distribution<double> u(-scale, scale);
  std::vector<Vec2> p(count);
  for (Vec2& q : p) q = Vec2(u(rng), u(rng));
  return p;
}

}  // namespace cmr::test
