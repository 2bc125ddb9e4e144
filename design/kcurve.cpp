#include "design/kcurve.hpp"
#include "design/kcurve_detail.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "bezierize/classify.hpp"
#include "spline/errors.hpp"
#include "spline/format.hpp"

namespace cmr {

using kcurve_detail::extent_of;
using kcurve_detail::kCoincidentRelative;

namespace {

/// Points whose largest coordinate is beyond 2^±this are solved at unit scale.
constexpr int kUnitScaleExponent = 256;
/// Bisection steps for t_i: 2^-64 is below a double's resolution on [0, 1].
constexpr int kBisectionSteps = 64;
/// A solution whose equations miss by more than this share of the extent
/// means the linear system was (numerically) singular.
constexpr double kSolveResidualRelative = 1e-6;
/// Smallest relaxation step: the plain iteration can cycle on sharp turns;
/// halving the step whenever the residual fails to fall damps the cycle.
constexpr double kMinRelaxation = 1.0 / 16;
/// Plain iterations before Newton steps start (the first ones move the
/// middle points from the input points into the basin of the fixed point).
constexpr int kPlainIterations = 8;
/// Newton steps up to this many interpolated points (its dense Jacobian
/// costs O(N^3) per step); more points use the damped plain iteration only.
constexpr int kNewtonMaxPoints = 64;
/// Forward-difference step of the Jacobian, relative to the unknowns' scale
/// (the extent for middle points, 1 for λ).
constexpr double kNewtonStep = 1e-7;
/// Iterations spent on the κ-curve proper before the published fixed point
/// is accepted (kcurve()).
constexpr int kStrictIterations = 300;
/// Plain iterations after a Newton step that did not lower |F|.
constexpr int kNewtonRetry = 4;
/// Newton pins t_i to 0 (1) where the plain step gives less than this (more
/// than 1 minus this): the point is then a joint (see kcurve()).
constexpr double kPinParameter = 1e-2;
/// The Newton step is halved at most this often before the plain step is taken.
constexpr int kLineSearchHalvings = 10;
/// The strict polish (polish_strict): steps per start, the defect it stops
/// at, and the Levenberg-Marquardt damping increases tried per step.
constexpr int kStrictPolishSteps = 300;
constexpr double kStrictPolishDefect = 1e-14;
constexpr int kLevenbergTries = 20;
/// The smooth system counts as solved (KCurve::unconstrained_t) below this defect.
constexpr double kUnconstrainedDefect = 1e-11;

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
  if (options.restarts < 0)
    throw InputError("kcurve restarts " + std::to_string(options.restarts) + " is below 0");
  if (options.max_iterations < 1)
    throw InputError("kcurve max_iterations " + std::to_string(options.max_iterations) + " is below 1");
  if (options.max_point_iterations < 0)
    throw InputError("kcurve max_point_iterations " + std::to_string(options.max_point_iterations) + " is below 0");
  if (!(options.time_limit >= 0))
    throw InputError("kcurve time_limit " + std::to_string(options.time_limit) + " is not a number of seconds >= 0");
  const int n = static_cast<int>(points.size());
  if (n < kKCurveMinPoints)
    throw InputError("a kappa-curve needs at least " + std::to_string(kKCurveMinPoints) + " points, got " +
                     std::to_string(n));
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(points[i].x) || !std::isfinite(points[i].y))
      throw InputError("points[" + std::to_string(i) + "] is not finite");
}

}  // namespace

namespace kcurve_detail {

double extent_of(std::span<const Vec2> points) {
  Vec2 lo = points[0], hi = points[0];
  for (const Vec2& p : points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  return glm::length(hi - lo);
}

}  // namespace kcurve_detail

namespace {


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

/// Collinear points (each within kCoincidentRelative of the extent from the
/// line through the first point and the one farthest from it): a closed
/// curve through them, or an open one through points out of order along the
/// line, would double back on itself, which is an InputError; open points in
/// order give the straight curve.
void check_collinear(std::span<const Vec2> points, bool closed, double extent) {
  const Vec2 origin = points[0];
  Vec2 far = origin;
  for (const Vec2& p : points)
    if (glm::length(p - origin) > glm::length(far - origin)) far = p;
  const Vec2 direction = glm::normalize(far - origin);  // the points are not all coincident (check_spacing)
  for (const Vec2& p : points)
    if (std::abs(det(direction, p - origin)) > kCoincidentRelative * extent) return;
  if (closed)
    throw InputError("the points are collinear: a closed kappa-curve through them would double back on itself");
  const int n = static_cast<int>(points.size());
  const double sense = dot(direction, points[1] - points[0]);
  for (int i = 0; i + 1 < n; ++i)
    if (dot(direction, points[i + 1] - points[i]) * sense <= 0)
      throw InputError("the points are collinear but points[" + std::to_string(i + 1) +
                       "] turns back along their line: the kappa-curve would double back on itself");
}

/// The iteration's state. Open curves keep the fixed ends as c_{-1,1} = first
/// point with λ_{-1} = 0 and c_{N,1} = last point with λ_{N-1} = 1.
struct State {
  std::vector<Vec2> p;    ///< interpolated points, one per quadratic
  std::vector<Vec2> mid;  ///< c_{i,1}
  std::vector<double> lambda;  ///< λ_i: joint of quadratics i and i+1 (open: the last one is 1)
  std::vector<double> t;
  /// Newton's active set: -1 pins t_i to 0, +1 to 1 (the point is a joint),
  /// 0 leaves it to step 1.
  std::vector<int> pin;
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

/// |c_i(t) - p_i| with t from Eq. 7 (`strict`: the point is the quadratic's
/// curvature maximum) or from step 1 on the quadratic as it is (the
/// published fixed point: with p_i on a joint, step 1's cubic has its root
/// at that end whatever the quadratic's maximum).
double point_error(const State& s, int i, bool strict) {
  const std::array<Vec2, 3> q = s.quadratic(i);
  // A straight quadratic (κ = 0 throughout, exactly) has no maximum to be at.
  const bool straight = det(q[1] - q[0], q[2] - q[0]) == 0;
  const double t = strict && !straight ? quadratic_max_curvature_parameter(q) : kcurve_parameter(q[0], s.p[i], q[2]);
  const double u = 1 - t;
  return glm::length(u * u * q[0] + 2 * t * u * q[1] + t * t * q[2] - s.p[i]);
}

double interpolation_error(const State& s, bool strict) {
  double worst = 0;
  for (int i = 0; i < s.n(); ++i) worst = std::max(worst, point_error(s, i, strict));
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

namespace {

/// One plain iteration (steps 2, (J), 1, 3) from s: the next iterate. False
/// when the linear system is singular (InputError is the caller's).
bool plain_step(const State& s, double extent, State& next) {
  next = s;
  update_lambda(next);
  for (int i = 0; i < next.n(); ++i)
    next.t[i] = next.pin[i] ? (next.pin[i] < 0 ? 0.0 : 1.0) : kcurve_parameter(next.start(i), next.p[i], next.end(i));
  const Tridiagonal system = middle_point_system(next);
  std::vector<Vec2> x;
  if (!solve(system, x) || !(solve_residual(system, x) <= kSolveResidualRelative * extent)) return false;
  next.mid = std::move(x);
  return true;
}

/// The unknowns of the iteration as one vector: the middle points, then the
/// free λ (open curves: λ_{N-1} = 1 is fixed).
int unknowns(const State& s) { return 2 * s.n() + (s.closed ? s.n() : s.n() - 1); }
std::vector<double> pack(const State& s) {
  std::vector<double> v;
  for (const Vec2& m : s.mid) v.push_back(m.x), v.push_back(m.y);
  for (int i = 0; i < (s.closed ? s.n() : s.n() - 1); ++i) v.push_back(s.lambda[i]);
  return v;
}
void unpack(const std::vector<double>& v, State& s) {
  for (int i = 0; i < s.n(); ++i) s.mid[i] = {v[2 * i], v[2 * i + 1]};
  for (int i = 0; i < (s.closed ? s.n() : s.n() - 1); ++i) s.lambda[i] = v[2 * s.n() + i];
}

/// F(x) = step(x) - x with the middle points scaled by 1/extent, so that
/// both kinds of unknown are of order 1; false on a singular system.
bool fixed_point_defect(const State& s, double extent, std::vector<double>& f) {
  State next;
  if (!plain_step(s, extent, next)) return false;
  const std::vector<double> a = pack(s), b = pack(next);
  f.resize(a.size());
  for (std::size_t k = 0; k < a.size(); ++k) f[k] = (b[k] - a[k]) / (k < 2 * s.mid.size() ? extent : 1.0);
  return true;
}

double norm(const std::vector<double>& v) {
  double sum = 0;
  for (double x : v) sum += x * x;
  return std::sqrt(sum);
}

/// Dense Gaussian elimination with partial pivoting; false when singular.
bool solve_dense(std::vector<double> a, std::vector<double> b, int n, std::vector<double>& x) {
  for (int c = 0; c < n; ++c) {
    int p = c;
    for (int r = c + 1; r < n; ++r)
      if (std::abs(a[r * n + c]) > std::abs(a[p * n + c])) p = r;
    if (!(std::abs(a[p * n + c]) > 0)) return false;
    if (p != c) {
      for (int k = 0; k < n; ++k) std::swap(a[c * n + k], a[p * n + k]);
      std::swap(b[c], b[p]);
    }
    for (int r = c + 1; r < n; ++r) {
      const double f = a[r * n + c] / a[c * n + c];
      if (f == 0) continue;
      for (int k = c; k < n; ++k) a[r * n + k] -= f * a[c * n + k];
      b[r] -= f * b[c];
    }
  }
  x.assign(n, 0);
  for (int r = n - 1; r >= 0; --r) {
    double v = b[r];
    for (int k = r + 1; k < n; ++k) v -= a[r * n + k] * x[k];
    x[r] = v / a[r * n + r];
  }
  return std::isfinite(norm(x));
}

/// One Newton step on F(x) = 0 with a backtracking line search on |F|:
/// the Jacobian by forward differences (kNewtonStep, scaled like F), the
/// step halved up to kLineSearchHalvings times until |F| falls. False (s
/// unchanged) when no trial lowers |F|.
bool newton_step(State& s, double extent, const std::vector<double>& f0) {
  const int m = unknowns(s);
  const std::vector<double> x0 = pack(s);
  auto scale = [&](int k) { return k < 2 * s.n() ? extent : 1.0; };
  std::vector<double> jac(static_cast<std::size_t>(m) * m), f;
  State trial = s;
  for (int k = 0; k < m; ++k) {
    std::vector<double> x = x0;
    const double h = kNewtonStep * scale(k);
    x[k] += h;
    unpack(x, trial);
    if (!fixed_point_defect(trial, extent, f)) return false;
    for (int r = 0; r < m; ++r) jac[r * m + k] = (f[r] - f0[r]) / (h / scale(k));
  }
  std::vector<double> minus_f(m), d;
  for (int r = 0; r < m; ++r) minus_f[r] = -f0[r];
  if (!solve_dense(jac, minus_f, m, d)) return false;
  const double f0_norm = norm(f0);
  double alpha = 1;
  for (int k = 0; k <= kLineSearchHalvings; ++k, alpha /= 2) {
    std::vector<double> x = x0;
    for (int j = 0; j < m; ++j) x[j] += alpha * d[j] * scale(j);
    bool valid = true;
    for (int i = 0; i < (s.closed ? s.n() : s.n() - 1); ++i) valid = valid && x[2 * s.n() + i] > 0 && x[2 * s.n() + i] < 1;
    if (!valid) continue;
    unpack(x, trial);
    if (fixed_point_defect(trial, extent, f) && norm(f) < (1 - 1e-4 * alpha) * f0_norm) {
      s = trial;
      return true;
    }
  }
  return false;
}

/// The residual of the header comment for state s: the interpolation error
/// at Eq. 7's maxima over the extent, and the change λ would make.
double residual_of(const State& s, double extent, bool strict) {
  State next = s;
  return std::max(interpolation_error(s, strict) / extent, update_lambda(next));
}

}  // namespace

namespace {

/// KCurveOptions::max_point_iterations and time_limit, spent as the solve
/// goes (iterations × points; the clock between steps).
struct Budget {
  long long point_iterations_left = 0;  ///< < 0: unlimited
  std::chrono::steady_clock::time_point deadline{};
  bool timed = false, spent = false;
  const std::atomic<bool>* cancel = nullptr;  ///< KCurveOptions::cancel
  /// Charges one iteration of `points` points; false (and spent) once the budget is gone.
  bool charge(int points) {
    if (spent) return false;
    if (point_iterations_left >= 0) {
      if (point_iterations_left < points) return !(spent = true);
      point_iterations_left -= points;
    }
    if (timed && std::chrono::steady_clock::now() > deadline) return !(spent = true);
    if (cancel != nullptr && cancel->load(std::memory_order_relaxed)) return !(spent = true);
    return true;
  }
};

/// Runs the iteration on s for at most max_iterations (added to
/// `iterations`) until residual_of(s, extent, strict) <= tolerance; returns
/// that residual. Throws InputError on a singular system.
double iterate(State& s, double extent, double tolerance, int max_iterations, bool strict, int& iterations,
               Budget& budget) {
  const int n = s.n();
  double residual = std::numeric_limits<double>::infinity();
  const bool newton = n <= kNewtonMaxPoints;
  std::vector<bool> unpinnable(n, false);
  int next_newton = 0;  // after a failed Newton step, plain steps until this iteration
  double relaxation = 1;  // the plain iteration's step towards the solved middle points
  for (int it = 1; it <= max_iterations; ++it) {
    if (!budget.charge(n)) {
      if (it == 1) residual = residual_of(s, extent, strict);
      break;
    }
    ++iterations;
    std::vector<double> f;
    if (newton && it > kPlainIterations) {
      // Points whose parameter is near an end are pinned there for the
      // Newton step: the iterate's t_i(A) has a kink at A = 0 (the point
      // on a joint), where Newton would stall.
      // A pin is wrong where Eq. 7's maximum is not at the pinned end (a
      // point on a joint whose quadratic peaks elsewhere is a fixed point of
      // the iteration but no κ-curve): then the point is not pinned again.
      for (int i = 0; i < n && strict; ++i)
        if (s.pin[i]) {
          const double t_max = quadratic_max_curvature_parameter(s.quadratic(i));
          if (s.pin[i] < 0 ? t_max > kPinParameter : t_max < 1 - kPinParameter) unpinnable[i] = true;
        }
      State probe;
      std::fill(s.pin.begin(), s.pin.end(), 0);
      if (plain_step(s, extent, probe))
        for (int i = 0; i < n; ++i)
          if (!unpinnable[i]) s.pin[i] = probe.t[i] < kPinParameter ? -1 : probe.t[i] > 1 - kPinParameter ? 1 : 0;
    }
    if (!fixed_point_defect(s, extent, f))
      throw InputError("the kappa-curve system is singular (iteration " + std::to_string(it) +
                       "); move the points further apart");
    // Newton on the fixed point once the plain iteration has had its first
    // steps; the damped plain step where Newton does not lower |F|.
    const bool try_newton = newton && it > kPlainIterations && it >= next_newton;
    if (try_newton && newton_step(s, extent, f)) {
      next_newton = it;
    } else {
      if (try_newton) next_newton = it + kNewtonRetry;
      std::fill(s.pin.begin(), s.pin.end(), 0);
      State next;
      if (!plain_step(s, extent, next))
        throw InputError("the kappa-curve system is singular (iteration " + std::to_string(it) +
                         "); move the points further apart");
      const double before = residual_of(s, extent, strict);
      for (int i = 0; i < n; ++i) s.mid[i] += relaxation * (next.mid[i] - s.mid[i]);
      s.lambda = next.lambda;
      if (residual_of(s, extent, strict) >= before) relaxation = std::max(relaxation / 2, kMinRelaxation);
      else relaxation = std::min(1.0, 2 * relaxation);
    }
    residual = residual_of(s, extent, strict);
    if (residual <= tolerance) break;
  }
  return residual;
}

/// The κ-curve proper as one smooth system (kcurve.hpp, "Polish"): the
/// unknowns are the middle points, the free λ and t_i; the equations are
/// c_i(t_i) = p_i (over the extent), λ_i = step 2's λ, and the vertex
/// condition c_i'(t_i)·c_i'' = 0 (over the extent squared). Unlike the fixed
/// point map, which takes t_i from step 1's cubic and so has a kink where a
/// point reaches a joint, this system is smooth there.
int strict_unknowns(const State& s) { return unknowns(s) + s.n(); }
std::vector<double> strict_pack(const State& s) {
  std::vector<double> v = pack(s);
  v.insert(v.end(), s.t.begin(), s.t.end());
  return v;
}
void strict_unpack(const std::vector<double>& v, State& s) {
  unpack(v, s);
  for (int i = 0; i < s.n(); ++i) s.t[i] = v[unknowns(s) + i];
}
double strict_scale(const State& s, int k, double extent) { return k < 2 * s.n() ? extent : 1.0; }
std::vector<double> strict_defect(const State& s, double extent) {
  std::vector<double> f;
  for (int i = 0; i < s.n(); ++i) {
    const std::array<Vec2, 3> q = s.quadratic(i);
    const double t = s.t[i], u = 1 - t;
    const Vec2 e = (u * u * q[0] + 2 * t * u * q[1] + t * t * q[2] - s.p[i]) / extent;
    f.push_back(e.x);
    f.push_back(e.y);
  }
  State next = s;
  update_lambda(next);
  for (int i = 0; i < (s.closed ? s.n() : s.n() - 1); ++i) f.push_back(s.lambda[i] - next.lambda[i]);
  for (int i = 0; i < s.n(); ++i) {
    const std::array<Vec2, 3> q = s.quadratic(i);
    const Vec2 d = q[0] - 2.0 * q[1] + q[2];
    f.push_back(dot(q[1] - q[0] + s.t[i] * d, d) / (extent * extent));
  }
  return f;
}

/// Central-difference Jacobian of strict_defect at s (columns scaled like
/// the unknowns: a column is d f / d(x_k / scale_k)).
std::vector<double> strict_jacobian(const State& s, double extent) {
  const int m = strict_unknowns(s);
  const std::vector<double> x0 = strict_pack(s);
  std::vector<double> jac(static_cast<std::size_t>(m) * m);
  State trial = s;
  for (int k = 0; k < m; ++k) {
    const double h = kNewtonStep * strict_scale(s, k, extent);
    std::vector<double> x = x0;
    x[k] = x0[k] + h;
    strict_unpack(x, trial);
    const std::vector<double> plus = strict_defect(trial, extent);
    x[k] = x0[k] - h;
    strict_unpack(x, trial);
    const std::vector<double> minus = strict_defect(trial, extent);
    for (int r = 0; r < m; ++r) jac[r * m + k] = (plus[r] - minus[r]) / (2 * kNewtonStep);
  }
  return jac;
}

/// λ strictly inside (0, 1) (a joint strictly between its middle points).
bool lambda_valid(const State& s) {
  for (int i = 0; i < (s.closed ? s.n() : s.n() - 1); ++i)
    if (!(s.lambda[i] > 0 && s.lambda[i] < 1)) return false;
  return true;
}

/// Solves strict_defect = 0 from s: Newton steps with a backtracking line
/// search, then, where a step does not lower |f|, Levenberg-Marquardt steps
/// (damped normal equations). Returns |f| at the end; s is the best iterate.
double strict_solve(State& s, double extent, int max_steps, Budget& budget) {
  const int m = strict_unknowns(s);
  std::vector<double> f = strict_defect(s, extent);
  double fn = norm(f), mu = 1e-3;
  for (int step = 0; step < max_steps && fn > kStrictPolishDefect; ++step) {
    if (!budget.charge(s.n())) break;
    const std::vector<double> jac = strict_jacobian(s, extent), x0 = strict_pack(s);
    auto try_step = [&](const std::vector<double>& d, double alpha) {
      std::vector<double> x = x0;
      for (int k = 0; k < m; ++k) x[k] += alpha * d[k] * strict_scale(s, k, extent);
      State trial = s;
      strict_unpack(x, trial);
      if (!lambda_valid(trial)) return false;
      std::vector<double> ft = strict_defect(trial, extent);
      const double ftn = norm(ft);
      if (!(ftn < (1 - 1e-4 * alpha) * fn)) return false;
      s = std::move(trial), f = std::move(ft), fn = ftn;
      return true;
    };
    std::vector<double> minus_f(m), d;
    for (int r = 0; r < m; ++r) minus_f[r] = -f[r];
    bool moved = false;
    if (solve_dense(jac, minus_f, m, d)) {
      double alpha = 1;
      for (int k = 0; k <= kLineSearchHalvings && !moved; ++k, alpha /= 2) moved = try_step(d, alpha);
    }
    if (moved) continue;
    // Levenberg-Marquardt: (J^T J + mu (1 + diag J^T J)) d = -J^T f.
    std::vector<double> normal(static_cast<std::size_t>(m) * m, 0.0), gradient(m, 0.0);
    for (int i = 0; i < m; ++i) {
      for (int j = 0; j < m; ++j) {
        double sum = 0;
        for (int r = 0; r < m; ++r) sum += jac[r * m + i] * jac[r * m + j];
        normal[i * m + j] = sum;
      }
      double sum = 0;
      for (int r = 0; r < m; ++r) sum += jac[r * m + i] * f[r];
      gradient[i] = -sum;
    }
    for (int tries = 0; tries < kLevenbergTries && !moved; ++tries, mu *= 4) {
      std::vector<double> damped = normal;
      for (int i = 0; i < m; ++i) damped[i * m + i] += mu * (1 + normal[i * m + i]);
      if (solve_dense(damped, gradient, m, d)) moved = try_step(d, 1);
    }
    if (!moved) break;
    mu = std::max(mu / 16, 1e-12);
  }
  return fn;
}

/// Polishes s to the κ-curve proper (every point at its quadratic's
/// maximum) where the iteration stopped at the published fixed point:
/// strict_solve from each of `starts` (t_i from step 1) in turn; the first
/// solution with every t_i in [0, 1], λ_i in (0, 1) and the strict residual
/// at most `tolerance` replaces s. False (s unchanged) when none is. Each
/// start's t is where its strict_solve starts.
bool polish_strict(State& s, const std::vector<State>& starts, double extent, double tolerance, Budget& budget) {
  if (s.n() > kNewtonMaxPoints) return false;
  for (State trial : starts) {
    std::fill(trial.pin.begin(), trial.pin.end(), 0);
    strict_solve(trial, extent, kStrictPolishSteps, budget);
    bool inside = lambda_valid(trial);
    for (double t : trial.t) inside = inside && t >= 0 && t <= 1;
    if (inside && residual_of(trial, extent, true) <= tolerance) {
      s = std::move(trial);
      return true;
    }
  }
  return false;
}

/// The curve's |κ| along quadratic i rises from its start (false: falls or
/// is flat) where Eq. 7's maximum is past the start.
bool rises_from_start(const State& s, int i) { return quadratic_max_curvature_parameter(s.quadratic(i)) > 0; }

/// The quadratics with a local maximum of the curve's |κ| at none of the
/// points: inside the quadratic (Eq. 7's t strictly inside (0, 1)) or on a
/// joint where |κ| rises on both sides, away from the points (within
/// `distance`). |κ| is continuous at every joint (step 2), so these are all
/// its local maxima but those at the points and the open curve's ends.
std::vector<int> stray_maxima_of(const State& s, const std::vector<Vec2>& points, double distance) {
  auto at_point = [&](Vec2 v) {
    for (const Vec2& p : points)
      if (glm::length(v - p) <= distance) return true;
    return false;
  };
  std::vector<int> out;
  const int n = s.n();
  for (int i = 0; i < n; ++i) {
    const std::array<Vec2, 3> q = s.quadratic(i);
    const double t = quadratic_max_curvature_parameter(q);
    bool stray = false;
    if (t > 0 && t < 1) {
      const double u = 1 - t;
      stray = !at_point(u * u * q[0] + 2 * t * u * q[1] + t * t * q[2]);
    } else if (t >= 1 && (s.closed || i + 1 < n)) {  // |κ| rises to the end: a maximum if it falls after
      stray = !rises_from_start(s, (i + 1) % n) && !at_point(q[2]);
    }
    if (stray) out.push_back(i);
  }
  return out;
}

}  // namespace

namespace {

/// Starts tried after the published one (λ = 1/2, c_{i,1} = p_i), in turn
/// (kcurve(), KCurveOptions::restarts): λ, and
/// c_{i,1} = p_i + push (p_i - (p_{i-1} + p_{i+1}) / 2).
struct AlternativeStart {
  double lambda, push;
};
constexpr AlternativeStart kAlternativeStarts[] = {{0.3, 0},    {0.7, 0},    {0.5, 0.5},  {0.2, 0},   {0.8, 0},
                                                   {0.5, -0.3}, {0.1, 0},    {0.9, 0},    {0.5, 1.0}, {0.3, 0.5},
                                                   {0.7, 0.5},  {0.3, -0.3}, {0.7, -0.3}, {0.5, 0.25}};
static_assert(std::size(kAlternativeStarts) == kKCurveRestarts);

/// The iteration from s (kcurve.hpp): first the κ-curve proper (each point
/// its quadratic's maximum) for kStrictIterations; where that does not
/// converge, the published fixed point, which may leave a point on a joint
/// while its quadratic peaks elsewhere, then polished towards the κ-curve
/// proper (polish_strict) from it, from where the strict iteration stopped,
/// and from the start. Fills out's residual, off_point_maxima and
/// stray_maxima and adds to out.iterations; s is the result. True when it converged.
bool solve_from(State& s, double extent, const KCurveOptions& options, const std::vector<Vec2>& points, KCurve& out,
                Budget& budget) {
  const int n = s.n();
  const State start = s;
  out.residual = iterate(s, extent, options.tolerance, std::min(options.max_iterations, kStrictIterations), true,
                         out.iterations, budget);
  if (out.residual > options.tolerance && options.max_iterations > kStrictIterations) {
    const State strict_attempt = s;
    s = start;
    out.residual = iterate(s, extent, options.tolerance, options.max_iterations - kStrictIterations, false,
                           out.iterations, budget);
    bool off = false;
    for (int i = 0; i < n; ++i) off = off || point_error(s, i, true) > options.tolerance * extent;
    if (off) {
      std::vector<State> starts{s, strict_attempt, start};
      for (State& from : starts)
        for (int i = 0; i < n; ++i) from.t[i] = kcurve_parameter(from.start(i), from.p[i], from.end(i));
      starts.push_back(start);  // t_i = 1/2
      if (polish_strict(s, starts, extent, options.tolerance, budget)) out.residual = residual_of(s, extent, true);
    }
  }
  out.budget_spent = budget.spent;
  out.off_point_maxima.clear();
  out.stray_maxima.clear();
  out.unconstrained_t.clear();
  for (int i = 0; i < n; ++i)
    if (point_error(s, i, true) > options.tolerance * extent) out.off_point_maxima.push_back(i);
  if (!out.off_point_maxima.empty()) {
    out.stray_maxima = stray_maxima_of(s, points, options.tolerance * extent);
    // Why: the smooth system solved from this answer with t free.
    State free = s;
    for (int i = 0; i < n; ++i) free.t[i] = kcurve_parameter(free.start(i), free.p[i], free.end(i));
    const bool solved =
        n <= kNewtonMaxPoints && strict_solve(free, extent, kStrictPolishSteps, budget) <= kUnconstrainedDefect;
    if (solved) out.unconstrained_t = free.t;
  }
  return out.converged();
}

}  // namespace

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
  check_collinear(points, options.closed, extent);
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
  s.pin.assign(n, 0);
  KCurve out;
  out.closed = s.closed;
  out.tolerance = options.tolerance;
  const std::vector<Vec2> all(points.begin(), points.end());
  // From the published start (λ = 1/2); where that is no κ-curve proper,
  // from the other starting λ in turn, keeping the best answer: a κ-curve
  // proper, else one whose maxima of |κ| are all at points, else the first.
  const State start = s;
  Budget budget;
  budget.point_iterations_left = options.max_point_iterations > 0 ? options.max_point_iterations : -1;
  budget.cancel = options.cancel;
  if (options.time_limit > 0) {
    budget.timed = true;
    budget.deadline = std::chrono::steady_clock::now() +
                      std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                          std::chrono::duration<double>(options.time_limit));
  }
  solve_from(s, extent, options, all, out, budget);
  auto rank = [](const KCurve& k) {
    if (!k.converged()) return 3;
    return k.off_point_maxima.empty() ? 0 : k.stray_maxima.empty() ? 1 : 2;
  };
  for (int r = 0; r < std::min(options.restarts, kKCurveRestarts); ++r) {
    if (rank(out) == 0 || !out.converged() || budget.spent) break;
    const AlternativeStart& alternative = kAlternativeStarts[r];
    State other = start;
    std::fill(other.lambda.begin(), other.lambda.end() - (other.closed ? 0 : 1), alternative.lambda);
    for (int i = 0; i < n; ++i)
      other.mid[i] = start.p[i] + alternative.push * (start.p[i] - (start.mid_at(i - 1) + start.mid_at(i + 1)) / 2.0);
    KCurve again = out;  // iterations add up
    try {
      solve_from(other, extent, options, all, again, budget);
    } catch (const InputError&) {  // a singular system from this start: the answer so far stands
      continue;
    }
    if (rank(again) < rank(out)) {
      s = std::move(other), out = std::move(again);
    } else {
      out.iterations = again.iterations;
    }
    out.budget_spent = budget.spent;  // restarts cut short: the best answer so far stands
  }
  for (int i = 0; i < n; ++i) {
    out.quadratics.push_back(s.quadratic(i));
    out.t_max.push_back(quadratic_max_curvature_parameter(out.quadratics.back()));
  }
  if (s.closed) out.quadratics.back()[2] = out.quadratics.front()[0];  // the same joint, bit for bit
  return out;
}

}  // namespace cmr
