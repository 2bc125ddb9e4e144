#include "bezierize/kcurve.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "spline/errors.hpp"

namespace cmr {

namespace {

/// Points whose largest coordinate is beyond 2^±this are solved at unit scale.
constexpr int kUnitScaleExponent = 256;
/// Consecutive points closer than this share of the extent are coincident.
constexpr double kCoincidentRelative = 1e-9;
/// Bisection steps for t_i: 2^-64 is below a double's resolution on [0, 1].
constexpr int kBisectionSteps = 64;
/// A solution whose equations miss by more than this share of the extent
/// means the linear system was (numerically) singular.
constexpr double kSolveResidualRelative = 1e-6;
/// Smallest relaxation step: the plain iteration can cycle on sharp turns;
/// halving the step whenever the residual fails to fall damps the cycle.
constexpr double kMinRelaxation = 1.0 / 16;

double area(Vec2 a, Vec2 b, Vec2 c) { return std::abs(det(b - a, c - a)) / 2; }

/// A tridiagonal system, cyclic when `cyclic`: row i is
/// a[i] x[i-1] + b[i] x[i] + c[i] x[i+1] = r[i] (indices mod n when cyclic).
struct Tridiagonal {
  std::vector<double> a, b, c;
  std::vector<Vec2> r;
  bool cyclic = false;
};

/// Gaussian elimination with partial pivoting (the scheme of LAPACK's gtsv,
/// one fill-in superdiagonal). False on a zero pivot.
bool solve_banded(std::vector<double> a, std::vector<double> b, std::vector<double> c, std::vector<Vec2> r,
                  std::vector<Vec2>& x) {
  const int n = static_cast<int>(b.size());
  std::vector<double> c2(n, 0.0);
  for (int i = 0; i + 1 < n; ++i) {
    const double sub = a[i + 1];
    if (std::abs(b[i]) >= std::abs(sub)) {
      if (b[i] == 0) return false;
      const double f = sub / b[i];
      b[i + 1] -= f * c[i];
      r[i + 1] -= f * r[i];
    } else {  // swap rows i and i+1
      const double f = b[i] / sub;
      b[i] = sub;
      const double next_b = b[i + 1];
      b[i + 1] = c[i] - f * next_b;
      if (i + 2 < n) {
        c2[i] = c[i + 1];
        c[i + 1] = -f * c[i + 1];
      }
      c[i] = next_b;
      std::swap(r[i], r[i + 1]);
      r[i + 1] -= f * r[i];
    }
  }
  if (b[n - 1] == 0) return false;
  x.assign(n, Vec2(0));
  for (int i = n - 1; i >= 0; --i) {
    Vec2 v = r[i];
    if (i + 1 < n) v -= c[i] * x[i + 1];
    if (i + 2 < n) v -= c2[i] * x[i + 2];
    x[i] = v / b[i];
  }
  return true;
}

/// Solves s (Sherman-Morrison for the corners of a cyclic system). False
/// when a pivot vanishes.
bool solve(const Tridiagonal& s, std::vector<Vec2>& x) {
  const int n = static_cast<int>(s.b.size());
  if (!s.cyclic || n < 3) return solve_banded(s.a, s.b, s.c, s.r, x);
  const double alpha = s.c[n - 1], beta = s.a[0];  // bottom-left and top-right corners
  const double gamma = s.b[0] != 0 ? -s.b[0] : -1.0;
  std::vector<double> b = s.b;
  b[0] -= gamma;
  b[n - 1] -= alpha * beta / gamma;
  std::vector<Vec2> y, z;
  std::vector<Vec2> u(n, Vec2(0));
  u[0] = Vec2(gamma);
  u[n - 1] = Vec2(alpha);
  if (!solve_banded(s.a, b, s.c, s.r, y) || !solve_banded(s.a, b, s.c, u, z)) return false;
  const double denominator = 1 + z[0].x + beta * z[n - 1].x / gamma;
  if (denominator == 0) return false;
  const Vec2 factor = (y[0] + beta * y[n - 1] / gamma) / denominator;
  x.resize(n);
  for (int i = 0; i < n; ++i) x[i] = y[i] - factor * z[i].x;
  return true;
}

/// Largest |row_i . x - r_i| of the system.
double solve_residual(const Tridiagonal& s, const std::vector<Vec2>& x) {
  const int n = static_cast<int>(x.size());
  double worst = 0;
  for (int i = 0; i < n; ++i) {
    Vec2 v = s.b[i] * x[i] - s.r[i];
    if (i > 0 || s.cyclic) v += s.a[i] * x[(i + n - 1) % n];
    if (i + 1 < n || s.cyclic) v += s.c[i] * x[(i + 1) % n];
    worst = std::max({worst, std::abs(v.x), std::abs(v.y)});
  }
  return worst;
}

void validate(std::span<const Vec2> points, const KCurveOptions& options) {
  if (!(options.tolerance > 0 && options.tolerance < 1))
    throw InputError("kcurve tolerance " + std::to_string(options.tolerance) + " is outside (0, 1)");
  if (options.max_iterations < 1)
    throw InputError("kcurve max_iterations " + std::to_string(options.max_iterations) + " is below 1");
  const int n = static_cast<int>(points.size());
  if (n < kKCurveMinPoints)
    throw InputError("a kappa-curve needs at least " + std::to_string(kKCurveMinPoints) + " points, got " +
                     std::to_string(n));
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(points[i].x) || !std::isfinite(points[i].y))
      throw InputError("points[" + std::to_string(i) + "] is not finite");
}

double extent_of(std::span<const Vec2> points) {
  Vec2 lo = points[0], hi = points[0];
  for (const Vec2& p : points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  return glm::length(hi - lo);
}

void check_spacing(std::span<const Vec2> points, bool closed, double extent) {
  const int n = static_cast<int>(points.size());
  for (int i = 0; i + 1 < n + (closed ? 1 : 0); ++i) {
    const int j = (i + 1) % n;
    if (glm::length(points[j] - points[i]) <= kCoincidentRelative * extent)
      throw InputError("points[" + std::to_string(i) + "] and points[" + std::to_string(j) +
                       "] coincide (consecutive points must differ" +
                       (closed && j == 0 ? "; do not repeat the first point to close the curve)" : ")"));
  }
}

/// The iteration's state. Open curves keep the fixed ends as c_{-1,1} = first
/// point with λ_{-1} = 0 and c_{N,1} = last point with λ_{N-1} = 1.
struct State {
  std::vector<Vec2> p;    ///< interpolated points, one per quadratic
  std::vector<Vec2> mid;  ///< c_{i,1}
  std::vector<double> lambda;  ///< λ_i: joint of quadratics i and i+1 (open: the last one is 1)
  std::vector<double> t;
  Vec2 first{0}, last{0};  ///< open ends
  bool closed = false;
  int n() const { return static_cast<int>(p.size()); }
  Vec2 mid_at(int i) const {
    if (closed) return mid[(i + n()) % n()];
    return i < 0 ? first : i >= n() ? last : mid[i];
  }
  double lambda_before(int i) const { return i > 0 ? lambda[i - 1] : closed ? lambda[n() - 1] : 0.0; }
  Vec2 start(int i) const { return (1 - lambda_before(i)) * mid_at(i - 1) + lambda_before(i) * mid[i]; }
  Vec2 end(int i) const { return (1 - lambda[i]) * mid[i] + lambda[i] * mid_at(i + 1); }
  std::array<Vec2, 3> quadratic(int i) const { return {start(i), mid[i], end(i)}; }
};

/// Step 2: λ_i from the areas of the current iterate; returns the largest change.
double update_lambda(State& s) {
  const int count = s.closed ? s.n() : s.n() - 1;
  std::vector<double> next = s.lambda;
  for (int i = 0; i < count; ++i) {
    const double a1 = area(s.start(i), s.mid[i], s.mid_at(i + 1));
    const double a2 = area(s.mid[i], s.mid_at(i + 1), s.end((i + 1) % s.n()));
    const double r1 = std::sqrt(a1), r2 = std::sqrt(a2);
    next[i] = r1 + r2 > 0 ? r1 / (r1 + r2) : 0.5;
  }
  double change = 0;
  for (int i = 0; i < count; ++i) change = std::max(change, std::abs(next[i] - s.lambda[i]));
  s.lambda = std::move(next);
  return change;
}

/// Step 3: the system for c_{i,1} given t_i and λ_i.
Tridiagonal middle_point_system(const State& s) {
  const int n = s.n();
  Tridiagonal m;
  m.cyclic = s.closed;
  m.a.resize(n);
  m.b.resize(n);
  m.c.resize(n);
  m.r = s.p;
  for (int i = 0; i < n; ++i) {
    const double t = s.t[i], u = 1 - t;
    const double lb = s.lambda_before(i), la = s.lambda[i];
    m.a[i] = u * u * (1 - lb);
    m.b[i] = u * u * lb + 2 * t * u + t * t * (1 - la);
    m.c[i] = t * t * la;
    if (!s.closed && i == 0) m.r[i] -= m.a[i] * s.first;
    if (!s.closed && i == n - 1) m.r[i] -= m.c[i] * s.last;
  }
  if (!s.closed) m.a[0] = m.c[n - 1] = 0;
  return m;
}

/// max_i |c_i(t*_i) - p_i| with t*_i from Eq. 7.
double interpolation_error(const State& s) {
  double worst = 0;
  for (int i = 0; i < s.n(); ++i) {
    const std::array<Vec2, 3> q = s.quadratic(i);
    const double t = quadratic_max_curvature_parameter(q), u = 1 - t;
    worst = std::max(worst, glm::length(u * u * q[0] + 2 * t * u * q[1] + t * t * q[2] - s.p[i]));
  }
  return worst;
}

}  // namespace

double kcurve_parameter(Vec2 c0, Vec2 p, Vec2 c2) {
  const Vec2 A = c0 - p, B = c2 - p;
  const double aa = dot(A, A), bb = dot(B, B), ab = dot(A, B);
  if (aa == 0) return 0;
  if (bb == 0) return 1;
  const auto f = [&](double t) {
    const double s = 1 - t;
    return t * t * t * bb - s * s * s * aa + t * s * (t - s) * ab;
  };
  double lo = 0, hi = 1;  // f(lo) < 0 < f(hi)
  for (int k = 0; k < kBisectionSteps && hi - lo > 0; ++k) {
    const double m = lo + (hi - lo) / 2;
    if (m <= lo || m >= hi) break;
    const double v = f(m);
    if (v == 0) return m;
    (v < 0 ? lo : hi) = m;
  }
  return lo + (hi - lo) / 2;
}

double quadratic_max_curvature_parameter(const std::array<Vec2, 3>& q) {
  const Vec2 d2 = q[0] - 2.0 * q[1] + q[2];
  const double denominator = dot(d2, d2);
  if (denominator == 0) return 0.5;
  return std::clamp(dot(q[0] - q[1], d2) / denominator, 0.0, 1.0);
}

KCurve kcurve(std::span<const Vec2> points, const KCurveOptions& options) {
  validate(points, options);
  // Far-scale points (1e154 or 1e-200): solved at unit scale, so that no
  // square or sum of squares overflows or underflows, and scaled back. The
  // scale is a power of 2, so both ways are exact (issue 26 D5).
  double largest = 0;
  for (const Vec2& p : points) largest = std::max({largest, std::abs(p.x), std::abs(p.y)});
  if (const int e = largest > 0 ? std::ilogb(largest) : 0; e > kUnitScaleExponent || e < -kUnitScaleExponent) {
    std::vector<Vec2> unit;
    for (const Vec2& p : points) unit.emplace_back(std::ldexp(p.x, -e), std::ldexp(p.y, -e));
    KCurve out = kcurve(unit, options);
    for (auto& q : out.quadratics)
      for (Vec2& c : q) c = Vec2(std::ldexp(c.x, e), std::ldexp(c.y, e));
    return out;
  }
  const double extent = extent_of(points);
  check_spacing(points, options.closed, extent);
  State s;
  s.closed = options.closed;
  if (s.closed) {
    s.p.assign(points.begin(), points.end());
  } else {
    s.p.assign(points.begin() + 1, points.end() - 1);
    s.first = points.front();
    s.last = points.back();
  }
  const int n = s.n();
  s.mid = s.p;
  s.lambda.assign(n, 0.5);
  if (!s.closed) s.lambda[n - 1] = 1;
  s.t.assign(n, 0.5);
  KCurve out;
  out.closed = s.closed;
  out.tolerance = options.tolerance;
  double relaxation = 1;  // the step towards the solved middle points
  for (int it = 1; it <= options.max_iterations; ++it) {
    const double lambda_change = update_lambda(s);
    for (int i = 0; i < n; ++i) s.t[i] = kcurve_parameter(s.start(i), s.p[i], s.end(i));
    const Tridiagonal system = middle_point_system(s);
    std::vector<Vec2> x;
    if (!solve(system, x) || !(solve_residual(system, x) <= kSolveResidualRelative * extent))
      throw InputError("the kappa-curve system is singular (iteration " + std::to_string(it) +
                       "); move the points further apart");
    for (int i = 0; i < n; ++i) s.mid[i] += relaxation * (x[i] - s.mid[i]);
    out.iterations = it;
    const double previous = out.residual;
    out.residual = std::max(interpolation_error(s) / extent, it > 1 ? lambda_change : 1.0);
    if (out.residual <= options.tolerance) break;
    if (it > 1 && out.residual >= previous) relaxation = std::max(relaxation / 2, kMinRelaxation);
  }
  for (int i = 0; i < n; ++i) {
    out.quadratics.push_back(s.quadratic(i));
    out.t_max.push_back(quadratic_max_curvature_parameter(out.quadratics.back()));
  }
  if (s.closed) out.quadratics.back()[2] = out.quadratics.front()[0];  // the same joint, bit for bit
  return out;
}

BSpline kcurve_quadratic_spline(const KCurve& curve) {
  CMR_CHECK(!curve.quadratics.empty());
  std::vector<Vec2> points{curve.quadratics.front()[0]};
  std::vector<double> knots{0, 0};
  for (std::size_t i = 0; i < curve.quadratics.size(); ++i) {
    points.push_back(curve.quadratics[i][1]);
    points.push_back(curve.quadratics[i][2]);
    knots.insert(knots.end(), 2, static_cast<double>(i + 1));
  }
  return BSpline::make(2, std::move(knots), std::move(points), curve.closed ? "kcurve-closed" : "kcurve");
}

namespace {

/// The cubic chain's pieces (each four points) and, per quadratic, the index
/// of its maximum among the chain's control points (-1 if not a handle pair).
struct Chain {
  std::vector<std::array<Vec2, 4>> pieces;
  std::vector<int> maxima;
};

std::array<Vec2, 4> elevate(Vec2 a, Vec2 m, Vec2 b) {
  return {a, (a + 2.0 * m) / 3.0, (2.0 * m + b) / 3.0, b};
}

Chain cubic_chain(const KCurve& curve) {
  CMR_CHECK(curve.quadratics.size() == curve.t_max.size() && !curve.quadratics.empty());
  Chain c;
  for (std::size_t i = 0; i < curve.quadratics.size(); ++i) {
    const auto& q = curve.quadratics[i];
    const double t = curve.t_max[i];
    const Vec2 l1 = glm::mix(q[0], q[1], t), r1 = glm::mix(q[1], q[2], t), mid = glm::mix(l1, r1, t);
    if (t > 0) c.pieces.push_back(elevate(q[0], l1, mid));
    c.maxima.push_back(t > 0 && t < 1 ? 3 * static_cast<int>(c.pieces.size()) : -1);
    if (t < 1) c.pieces.push_back(elevate(mid, r1, q[2]));
  }
  return c;
}

}  // namespace

BSpline kcurve_cubic_chain(const KCurve& curve) {
  const Chain c = cubic_chain(curve);
  std::vector<Vec2> points{c.pieces.front()[0]};
  std::vector<double> knots{0, 0, 0};
  for (std::size_t i = 0; i < c.pieces.size(); ++i) {
    points.insert(points.end(), c.pieces[i].begin() + 1, c.pieces[i].end());
    knots.insert(knots.end(), 3, static_cast<double>(i + 1));
  }
  return BSpline::make(3, std::move(knots), std::move(points),
                       curve.closed ? "kcurve-cubic-closed" : "kcurve-cubic");
}

std::vector<int> kcurve_cubic_maxima(const KCurve& curve) { return cubic_chain(curve).maxima; }

}  // namespace cmr
