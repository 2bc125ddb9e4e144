#include "report/g3.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "numeric/exact.hpp"
#include "bezierize/extract.hpp"
#include "bezierize/space_analyze.hpp"
#include "bezierize/space_classify.hpp"
#include "report/report.hpp"
#include "spline/format.hpp"

namespace cmr::report {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

using H4 = std::array<Rational, 4>;  // (w x, w y, w z, w)
using V3 = std::array<Rational, 3>;

/// P', P'', P''' (Cartesian, in the piece's own u in [0, 1]) at u = 0
/// (at_end false) or u = 1 of the Bezier piece with homogeneous points H;
/// nothing where w = 0 there (a pole).
std::optional<std::array<V3, 3>> end_derivatives(const std::vector<H4>& H, bool at_end) {
  const int n = static_cast<int>(H.size()) - 1;
  const auto point = [&](int i) -> const H4& { return H[static_cast<std::size_t>(at_end ? n - i : i)]; };
  // h[k] = H^(k) at the end: n!/(n-k)! times the k-th forward difference
  // from the end (read backwards at u = 1: (-1)^k Nabla^k = Delta^k of the
  // reversed points, so the sign (-1)^k is put back).
  std::array<H4, 4> h;
  for (int k = 0; k <= 3; ++k) {
    H4 diff{};
    if (k <= n) {
      Rational falling = 1;
      for (int i = 0; i < k; ++i) falling *= n - i;
      int binom = 1;  // C(k, i)
      for (int i = 0; i <= k; ++i) {
        const int sign = ((k - i) % 2 == 0) ? 1 : -1;  // Delta^k H_0 = sum (-1)^(k-i) C(k, i) H_i
        for (int c = 0; c < 4; ++c) diff[c] += Rational(sign * binom) * point(i)[c];
        binom = binom * (k - i) / (i + 1);
      }
      const Rational f = (at_end && k % 2 == 1) ? Rational(-falling) : falling;
      for (int c = 0; c < 4; ++c) diff[c] *= f;
    }
    h[static_cast<std::size_t>(k)] = diff;
  }
  const Rational& w = h[0][3];
  if (sgn(w) == 0) return std::nullopt;
  // Leibniz on H = w P: P^(k) = (H^(k) - sum_{i=1..k} C(k, i) w^(i) P^(k-i)) / w.
  std::array<V3, 4> p;
  static constexpr int kBinom[4][4] = {{1, 0, 0, 0}, {1, 1, 0, 0}, {1, 2, 1, 0}, {1, 3, 3, 1}};
  for (int k = 0; k <= 3; ++k)
    for (int c = 0; c < 3; ++c) {
      Rational v = h[static_cast<std::size_t>(k)][static_cast<std::size_t>(c)];
      for (int i = 1; i <= k; ++i)
        v -= Rational(kBinom[k][i]) * h[static_cast<std::size_t>(i)][3] *
             p[static_cast<std::size_t>(k - i)][static_cast<std::size_t>(c)];
      p[static_cast<std::size_t>(k)][static_cast<std::size_t>(c)] = v / w;
    }
  return std::array<V3, 3>{p[1], p[2], p[3]};
}

Rational dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V3 cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

std::string num(double v) { return format_number(v, 6); }

/// One joint judged: the violation's message, or nothing when G3 holds
/// (kl, kr: kappa; sl, sr: dkappa/ds; tl, tr: tau, NaN in 2D).
std::optional<std::string> judge(double kl, double kr, double sl, double sr, double tl, double tr, double tol) {
  const double kmax = std::max(std::abs(kl), std::abs(kr));
  std::string why;
  if (std::abs(kl - kr) > tol * kmax) {
    why = "curvature ";
    why.append(num(kl)).append(" | ").append(num(kr));
  }
  if (std::isfinite(sl) && std::isfinite(sr) && !g3_agree(sl, sr, tol, kmax * kmax)) {
    if (!why.empty()) why.append(", ");
    why.append("dkappa/ds ").append(num(sl)).append(" | ").append(num(sr));
  }
  if (std::isfinite(tl) && std::isfinite(tr) && !g3_agree(tl, tr, tol, kmax)) {
    if (!why.empty()) why.append(", ");
    why.append("torsion ").append(num(tl)).append(" | ").append(num(tr));
  }
  if (why.empty()) return std::nullopt;
  return why;
}

GateViolation at_joint(int index, double knot, const std::string& why, double tol) {
  GateViolation v;
  v.joint = index;
  v.t = knot;
  v.message = why;
  v.message.append(" at smooth joint ").append(std::to_string(index)).append(" (t = ").append(num(knot));
  v.message.append("): not G3 within ").append(num(tol));
  return v;
}

}  // namespace

double planar_end_kappa_slope(const BSpline& spline, const Segment& s, int side) {
  std::vector<H4> H;
  for (const HPoint<Rational>& p : segment_homogeneous_points<Rational>(spline, s)) H.push_back({p.x, p.y, 0, p.z});
  const std::optional<std::array<V3, 3>> d = end_derivatives(H, side == 1);
  if (!d) return kNaN;
  const auto& [d1, d2, d3] = *d;
  const Rational g = dot(d1, d1);
  if (sgn(g) == 0) return kNaN;
  const Rational c = d1[0] * d2[1] - d1[1] * d2[0], c1 = d1[0] * d3[1] - d1[1] * d3[0];
  const Rational value = (c1 * g - 3 * c * dot(d1, d2)) / (g * g * g);
  return value.get_d();
}

double space_end_kappa_slope(const SpaceSpline& spline, const Segment& s, int side) {
  const SpaceWindow w = space_window(spline, s);
  std::vector<H4> H;
  for (const HPoint3<Rational>& p : space_window_bezier<Rational>(w, space_window_hpoints<Rational>(spline, w)))
    H.push_back({p.x, p.y, p.z, p.w});
  const std::optional<std::array<V3, 3>> d = end_derivatives(H, side == 1);
  if (!d) return kNaN;
  const auto& [d1, d2, d3] = *d;
  const Rational g = dot(d1, d1);
  const V3 c = cross(d1, d2), c1 = cross(d1, d3);
  const Rational c2 = dot(c, c);
  if (sgn(g) == 0 || sgn(c2) == 0) return kNaN;
  const Rational m = dot(c, c1) * g - 3 * c2 * dot(d1, d2);
  const Rational g3 = g * g * g;
  const Rational square = m * m / (c2 * g3 * g3);  // (dkappa/ds)^2
  return sgn(m) * std::sqrt(square.get_d());
}

bool g3_agree(double a, double b, double tol, double floor) {
  return std::abs(a - b) <= tol * std::max({std::abs(a), std::abs(b), floor});
}

std::vector<GateViolation> g3_violations(const SplineReport& r, double tol) {
  std::vector<GateViolation> out;
  const auto& segments = r.spline->segments();
  const int N = static_cast<int>(segments.size());
  for (const JointReport& jr : r.joints) {
    if (jr.corner) continue;
    const double kl = jr.joint.kappa_left, kr = jr.joint.kappa_right;
    if (!std::isfinite(kl) || !std::isfinite(kr)) continue;  // a cusp: no curvature to compare
    const int right = jr.joint.index % N, left = (jr.joint.index + N - 1) % N;
    const double sl = planar_end_kappa_slope(*r.spline, segments[static_cast<std::size_t>(left)], 1);
    const double sr = planar_end_kappa_slope(*r.spline, segments[static_cast<std::size_t>(right)], 0);
    if (const std::optional<std::string> why = judge(kl, kr, sl, sr, kNaN, kNaN, tol))
      out.push_back(at_joint(jr.joint.index, jr.joint.knot, *why, tol));
  }
  return out;
}

std::vector<GateViolation> space_g3_violations(const SpaceSpline& spline, const SpaceAnalysis& a, double tol) {
  std::vector<const SpaceJoint*> joints;
  for (const SpaceJoint& j : a.joints) joints.push_back(&j);
  if (a.seam) joints.push_back(&*a.seam);
  std::vector<GateViolation> out;
  const auto& segments = spline.segments();
  const int N = static_cast<int>(segments.size());
  for (const SpaceJoint* j : joints) {
    if (!j->g1 || j->zero_tangent) continue;  // a corner: exempt, as g2-at-smooth-nodes
    const double kl = j->kappa_left, kr = j->kappa_right;
    if (!std::isfinite(kl) || !std::isfinite(kr)) continue;
    const int right = j->index % N, left = (j->index + N - 1) % N;
    const double sl = space_end_kappa_slope(spline, segments[static_cast<std::size_t>(left)], 1);
    const double sr = space_end_kappa_slope(spline, segments[static_cast<std::size_t>(right)], 0);
    if (const std::optional<std::string> why = judge(kl, kr, sl, sr, j->tau_left, j->tau_right, tol))
      out.push_back(at_joint(j->index, j->knot, *why, tol));
  }
  return out;
}

}  // namespace cmr::report
