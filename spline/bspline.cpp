#include "spline/bspline.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "spline/limits.hpp"
#include "spline/blossom.hpp"
#include "spline/errors.hpp"
#include "spline/format.hpp"

namespace cmr {
namespace {

std::string num(double v) { return format_number(v, 17); }

void check_finite_point(const Vec2& p, int i) {
  if (!std::isfinite(p.x)) throw InputError("points[" + std::to_string(i) + "][0] is not a finite number");
  if (!std::isfinite(p.y)) throw InputError("points[" + std::to_string(i) + "][1] is not a finite number");
}

}  // namespace

BSpline BSpline::make(int degree, std::vector<double> knots, std::vector<Vec2> points, std::string name,
                      std::vector<double> weights) {
  if (degree < 2) throw InputError("degree: must be at least 2 (got " + std::to_string(degree) + ")");
  if (degree > kMaxDegree)
    throw InputError("degree: at most " + std::to_string(kMaxDegree) + " is supported (got " + std::to_string(degree) + ")");
  const int m = static_cast<int>(points.size());
  if (m < degree + 1)
    throw InputError("points: a degree-" + std::to_string(degree) + " spline needs at least " +
                     std::to_string(degree + 1) + " control points (got " + std::to_string(m) + ")");
  const std::size_t want = static_cast<std::size_t>(m + degree - 1);
  if (knots.size() != want)
    throw InputError("knots: polar form needs points + degree - 1 = " + std::to_string(want) + " knots (got " +
                     std::to_string(knots.size()) + ")");
  for (int i = 0; i < m; ++i) check_finite_point(points[i], i);
  if (!weights.empty()) {
    if (weights.size() != points.size())
      throw InputError("weights: one weight per control point is needed: " + std::to_string(m) + " points, " +
                       std::to_string(weights.size()) + " weights");
    for (std::size_t i = 0; i < weights.size(); ++i)
      if (!std::isfinite(weights[i])) throw InputError("weights[" + std::to_string(i) + "] is not a finite number");
    if (std::all_of(weights.begin(), weights.end(), [](double w) { return w == 0; }))
      throw InputError("weights: every weight is 0; at least one must be non-zero");
    // All negative: -w gives the same curve (X / W = (-X) / (-W)); store it positive.
    if (std::all_of(weights.begin(), weights.end(), [](double w) { return w < 0; }))
      for (double& w : weights) w = -w;
    // Equal weights cancel: the same polynomial curve.
    if (std::all_of(weights.begin(), weights.end(), [&](double w) { return w == weights.front(); })) weights.clear();
  }
  for (std::size_t i = 0; i < knots.size(); ++i) {
    if (!std::isfinite(knots[i])) throw InputError("knots[" + std::to_string(i) + "] is not a finite number");
    if (i > 0 && knots[i] < knots[i - 1])
      throw InputError("knots[" + std::to_string(i) + "] (" + num(knots[i]) + ") is smaller than knots[" +
                       std::to_string(i - 1) + "] (" + num(knots[i - 1]) + ")");
  }
  for (std::size_t i = 0, run = 1; i < knots.size(); ++i, ++run) {
    if (i > 0 && knots[i] != knots[i - 1]) run = 1;
    if (static_cast<int>(run) > degree)
      throw InputError("knots[" + std::to_string(i) + "] (" + num(knots[i]) + ") has multiplicity above the degree " +
                       std::to_string(degree));
  }
  BSpline s;
  s.degree_ = degree;
  s.knots_ = std::move(knots);
  s.points_ = std::move(points);
  s.name_ = std::move(name);
  s.weights_ = std::move(weights);
  if (!s.weights_.empty())
    for (int i = 0; i < m; ++i) s.hpoints_.push_back(to_hpoint<double>(s.points_[i], s.weights_[i]));
  for (int j = degree - 1; j <= m - 2; ++j) {
    if (s.knots_[j] < s.knots_[j + 1])
      s.segments_.push_back({static_cast<int>(s.segments_.size()), j, s.knots_[j], s.knots_[j + 1]});
  }
  if (s.segments_.empty())
    throw InputError("knots: every span [knots[" + std::to_string(degree - 1) + "], knots[" + std::to_string(m - 1) +
                     "]] is empty; the curve has no segment");
  return s;
}

BSpline BSpline::bezier(std::vector<Vec2> points, std::string name, std::vector<double> weights) {
  const int n = static_cast<int>(points.size()) - 1;
  if (n < 2) throw InputError("points: a Bezier curve needs at least 3 control points (got " +
                              std::to_string(points.size()) + ")");
  std::vector<double> knots(2 * n, 0.0);
  std::fill(knots.begin() + n, knots.end(), 1.0);
  return make(n, std::move(knots), std::move(points), std::move(name), std::move(weights));
}

BSpline BSpline::make_closed(int degree, std::vector<double> knots, std::vector<Vec2> points, std::string name,
                             std::vector<double> weights) {
  if (degree < 2) throw InputError("degree: must be at least 2 (got " + std::to_string(degree) + ")");
  if (degree > kMaxDegree)
    throw InputError("degree: at most " + std::to_string(kMaxDegree) + " is supported (got " + std::to_string(degree) + ")");
  const int m = static_cast<int>(points.size());
  if (m < 2) throw InputError("points: a closed spline needs at least 2 control points (got " + std::to_string(m) + ")");
  if (knots.size() != static_cast<std::size_t>(m + 1))
    throw InputError("knots: a closed spline needs points + 1 = " + std::to_string(m + 1) +
                     " knots, one period u_0..u_m (got " + std::to_string(knots.size()) + ")");
  for (int i = 0; i < m; ++i) check_finite_point(points[i], i);
  for (std::size_t i = 0; i < knots.size(); ++i) {
    if (!std::isfinite(knots[i])) throw InputError("knots[" + std::to_string(i) + "] is not a finite number");
    if (i > 0 && knots[i] < knots[i - 1])
      throw InputError("knots[" + std::to_string(i) + "] (" + num(knots[i]) + ") is smaller than knots[" +
                       std::to_string(i - 1) + "] (" + num(knots[i - 1]) + ")");
  }
  const double T = knots[m] - knots[0];
  if (!(T > 0)) throw InputError("knots: the period knots[" + std::to_string(m) + "] - knots[0] must be positive");
  // Multiplicity counted cyclically: the run at u_m continues into the run at u_0.
  int head = 1, tail = 1;
  while (head < m && knots[head] == knots[0]) ++head;
  while (tail < m && knots[m - tail] == knots[m]) ++tail;
  if (head + tail - 1 > degree)
    throw InputError("knots[0] and knots[" + std::to_string(m) + "] (the seam) have multiplicity " +
                     std::to_string(head + tail - 1) + " together, above the degree " + std::to_string(degree));
  // Periodic extension ũ_i for i = -(d-1)..m+d-1, and the unrolled points.
  const int d = degree;
  auto ext = [&](int i) {
    const int q = (i >= 0 ? i / m : -((-i + m - 1) / m));
    return knots[i - q * m] + q * T;
  };
  std::vector<double> unrolled;
  for (int k = 0; k <= m + 2 * d - 2; ++k) unrolled.push_back(ext(k - d + 1));
  if (!weights.empty() && weights.size() != static_cast<std::size_t>(m))
    throw InputError("weights: one weight per control point is needed: " + std::to_string(m) + " points, " +
                     std::to_string(weights.size()) + " weights");
  std::vector<Vec2> q;
  std::vector<double> qw;
  for (int k = 0; k < m + d; ++k) {
    q.push_back(points[k % m]);
    if (!weights.empty()) qw.push_back(weights[k % m]);
  }
  BSpline s = make(degree, std::move(unrolled), std::move(q), std::move(name), std::move(qw));
  s.closed_ = true;
  s.period_points_ = m;
  return s;
}

std::vector<double> BSpline::period_knots() const {
  if (!closed_) return knots_;
  return {knots_.begin() + (degree_ - 1), knots_.begin() + (degree_ + period_points_)};
}

int BSpline::twin(int k) const {
  if (!closed_) return -1;
  if (k < degree_) return k + period_points_;
  if (k >= period_points_) return k - period_points_;
  return -1;
}

const Segment& BSpline::segment_at(double t) const {
  auto it = std::upper_bound(segments_.begin(), segments_.end(), t,
                             [](double v, const Segment& s) { return v < s.a; });
  if (it == segments_.begin()) return segments_.front();
  return *(it - 1);
}

int BSpline::multiplicity(double u) const {
  const auto [lo, hi] = std::equal_range(knots_.begin(), knots_.end(), u);  // knots are sorted
  return static_cast<int>(hi - lo);
}

BSpline BSpline::with_point(int k, Vec2 p) const {
  if (k < 0 || k >= point_count())
    throw InputError("point index " + std::to_string(k) + " is out of range 0.." + std::to_string(point_count() - 1));
  check_finite_point(p, k);
  BSpline s = *this;
  s.points_[k] = p;
  if (s.is_rational()) s.hpoints_[k] = to_hpoint<double>(p, s.weights_[k]);
  if (const int t = twin(k); t >= 0) {
    s.points_[t] = p;
    if (s.is_rational()) s.hpoints_[t] = to_hpoint<double>(p, s.weights_[t]);
  }
  return s;
}

BSpline BSpline::with_points(const std::vector<Vec2>& pts) const {
  if (static_cast<int>(pts.size()) != unique_point_count())
    throw InputError(std::to_string(pts.size()) + " points for a spline of " + std::to_string(unique_point_count()));
  BSpline s = *this;
  for (int k = 0; k < static_cast<int>(pts.size()); ++k) {
    check_finite_point(pts[k], k);
    for (const int at : {k, twin(k)}) {
      if (at < 0) continue;
      s.points_[at] = pts[k];
      if (s.is_rational()) s.hpoints_[at] = to_hpoint<double>(pts[k], s.weights_[at]);
    }
  }
  return s;
}

BSpline BSpline::reversed() const {
  std::vector<double> knots(knots_.rbegin(), knots_.rend());
  for (double& u : knots) u = -u;
  std::vector<Vec2> points(points_.rbegin(), points_.rend());
  // A closed spline's reversed unrolled form is again one: Q'_k = P_{(d-1-k) mod m}.
  BSpline s = make(degree_, std::move(knots), std::move(points), name_, {weights_.rbegin(), weights_.rend()});
  s.closed_ = closed_;
  s.period_points_ = period_points_;
  return s;
}

Vec2 blossom(const BSpline& spline, const Segment& s, const double* args) {
  if (spline.is_rational()) {
    const glm::dvec3 h = homogeneous_blossom(spline, s, args);
    return {h.x / h.z, h.y / h.z};
  }
  return blossom_span(spline.knots(), spline.points(), spline.degree(), s.span, args);
}

glm::dvec3 homogeneous_blossom(const BSpline& spline, const Segment& s, const double* args) {
  if (!spline.is_rational()) {
    const Vec2 p = blossom_span(spline.knots(), spline.points(), spline.degree(), s.span, args);
    return {p.x, p.y, 1.0};
  }
  return blossom_span(spline.knots(), spline.homogeneous_points(), spline.degree(), s.span, args);
}

namespace {

/// The r-th derivative of the piece of segment s at t, from the blossom of
/// the control values `points` (Cartesian or homogeneous).
template <class P>
P blossom_derivative(const BSpline& spline, const std::vector<P>& points, double t, int r) {
  const int d = spline.degree();
  CMR_CHECK(r >= 0 && r <= d);
  const Segment& s = spline.segment_at(t);
  std::vector<double> args(d, t);
  P sum(0.0);
  double binom = 1.0;  // C(r, i)
  for (int i = 0; i <= r; ++i) {
    // args = t^{d-r}, a^{r-i}, b^i
    for (int q = 0; q < r; ++q) args[d - r + q] = q < r - i ? s.a : s.b;
    const double sign = ((r - i) % 2 == 0) ? 1.0 : -1.0;
    sum += sign * binom * blossom_span(spline.knots(), points, d, s.span, args.data());
    binom = binom * (r - i) / (i + 1);
  }
  double scale = 1.0;
  for (int q = 0; q < r; ++q) scale *= static_cast<double>(d - q) / (s.b - s.a);
  return scale * sum;
}

}  // namespace

Vec2 evaluate(const BSpline& spline, double t) {
  const std::vector<double> args(spline.degree(), t);
  return blossom(spline, spline.segment_at(t), args.data());
}

glm::dvec3 homogeneous_derivative(const BSpline& spline, double t, int r) {
  if (!spline.is_rational()) {
    const Vec2 p = blossom_derivative(spline, spline.points(), t, r);
    return {p.x, p.y, r == 0 ? 1.0 : 0.0};
  }
  return blossom_derivative(spline, spline.homogeneous_points(), t, r);
}

Vec2 derivative(const BSpline& spline, double t, int r) {
  if (!spline.is_rational()) return blossom_derivative(spline, spline.points(), t, r);
  // C^(k) = (X^(k) - sum_{i=1..k} C(k,i) W^(i) C^(k-i)) / W, k = 0..r.
  std::vector<glm::dvec3> H;
  for (int k = 0; k <= r; ++k) H.push_back(homogeneous_derivative(spline, t, k));
  std::vector<Vec2> C;
  for (int k = 0; k <= r; ++k) {
    Vec2 x(H[k].x, H[k].y);
    double binom = 1.0;  // C(k, i)
    for (int i = 1; i <= k; ++i) {
      binom = binom * (k - i + 1) / i;
      x -= binom * H[i].z * C[k - i];
    }
    C.push_back(x / H[0].z);
  }
  return C[r];
}

}  // namespace cmr
