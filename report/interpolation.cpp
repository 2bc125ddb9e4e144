// The interpolation gates (report/interpolation.hpp).
#include "report/interpolation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "bezierize/bernstein.hpp"
#include "bezierize/extract.hpp"
#include "bezierize/roots.hpp"
#include "report/report.hpp"
#include "spline/format.hpp"

namespace cmr::report {
namespace {

using RPoint = Point<Rational>;
using Poly = Bernstein<Rational>;

std::string num(double v, int precision = 6) { return format_number(v, precision); }

Poly sub(Poly a, const Poly& b) {
  for (std::size_t k = 0; k < a.size(); ++k) a[k] -= b[k];
  return a;
}
Poly add(Poly a, const Poly& b) {
  for (std::size_t k = 0; k < a.size(); ++k) a[k] += b[k];
  return a;
}

double value_at(const Poly& p, const Rational& s) { return bernstein_eval(p, s).get_d(); }

Rational middle(const RootInterval& r) { return r.exact() ? r.lo : Rational((r.lo + r.hi) / 2); }

}  // namespace

G1Between g1_between(const NodeTangents& t) {
  G1Between out;
  const Poly ux{t.u0x, t.u1x}, uy{t.u0y, t.u1y}, vx{t.v0x, t.v1x}, vy{t.v0y, t.v1y};
  const Poly c = sub(bernstein_product(ux, vy), bernstein_product(uy, vx));
  const Poly d = add(bernstein_product(ux, vx), bernstein_product(uy, vy));
  // Smooth at both ends: collinear, the same direction.
  if (c.front() != 0 || c.back() != 0 || d.front() <= 0 || d.back() <= 0) return out;
  out.judged = true;
  if (is_zero(c)) {
    // Collinear throughout: G1 unless the direction reverses (d <= 0 somewhere).
    std::vector<RootInterval> roots = isolate_roots(d);
    if (roots.empty()) {
      out.holds = true;
      return out;
    }
    // d > 0 at both ends: between its first and last root it is <= 0 (touching: one point).
    out.fail.emplace_back(double_below(roots.front().lo), double_above(roots.back().hi));
    out.worst_s = nearest_double(middle(roots.front()));
    out.worst_angle = 180;
    return out;
  }
  // c != 0: the open intervals between its roots in [0, 1].
  std::vector<RootInterval> roots = isolate_roots(c);
  for (std::size_t k = 0; k + 1 < roots.size(); ++k)
    out.fail.emplace_back(double_below(roots[k].hi), double_above(roots[k + 1].lo));
  // The worst angle: at a root of g = c' d - c d' inside (0, 1).
  const Poly g = sub(bernstein_product(bernstein_derivative(c), d), bernstein_product(c, bernstein_derivative(d)));
  double worst = -1;
  for (const RootInterval& r : isolate_roots(g)) {
    const Rational s = middle(r);
    if (s <= 0 || s >= 1) continue;
    const double a = std::abs(std::atan2(value_at(c, s), value_at(d, s))) * 180 / std::numbers::pi;
    if (a > worst) {
      worst = a;
      out.worst_s = nearest_double(s);
    }
  }
  if (worst < 0) {  // g has no root inside (it cannot, with c(0) = c(1) = 0 and c != 0): the middle
    out.worst_s = 0.5;
    worst = std::abs(std::atan2(value_at(c, Rational(1, 2)), value_at(d, Rational(1, 2)))) * 180 / std::numbers::pi;
  }
  out.worst_angle = worst;
  return out;
}

namespace {

/// Segment `seg`'s Bezier points on the piece's end `sigma` (0 or 1):
/// (1 - s) A + s B at s = s0 or s1, exactly.
std::vector<RPoint> end_points(const import::ContourMotion& m, int seg, bool end) {
  const std::vector<RPoint> a = segment_bezier_points<Rational>(m.a, m.a.segments()[seg]);
  const std::vector<RPoint> b = segment_bezier_points<Rational>(m.b, m.b.segments()[seg]);
  const Rational s(end ? m.piece->s1 : m.piece->s0);
  std::vector<RPoint> out;
  for (std::size_t k = 0; k < a.size(); ++k)
    out.push_back(RPoint{Rational(a[k].x + s * (b[k].x - a[k].x)), Rational(a[k].y + s * (b[k].y - a[k].y))});
  return out;
}

bool is_zero_vector(const Rational& x, const Rational& y) { return x == 0 && y == 0; }

}  // namespace

std::vector<GateViolation> g1_between_violations(const SplineReport& r) {
  std::vector<GateViolation> out;
  if (!r.motions || !r.spline) return out;
  const BSpline& s = *r.spline;
  const int N = s.segment_count(), deg = s.degree();
  for (const JointReport& jr : r.joints) {
    const int j = jr.joint.index;
    if (jr.joint.multiplicity < deg) continue;  // an implied node: C1 by construction at every instance
    const int right = j % N;                     // the segment the node starts
    const int left = s.closed() ? (right + N - 1) % N : right - 1;
    if (left < 0 || (!s.closed() && j >= N)) continue;
    for (const import::ContourMotion& m : *r.motions) {
      if (m.a.segment_count() != N || m.b.segment_count() != N || m.a.is_rational()) continue;
      if (right < static_cast<int>(m.smooth.size()) && !m.smooth[right]) continue;
      std::vector<RPoint> L[2] = {end_points(m, left, false), end_points(m, left, true)};
      std::vector<RPoint> R[2] = {end_points(m, right, false), end_points(m, right, true)};
      const std::size_t n = L[0].size() - 1;
      // Incoming and outgoing tangents at both ends; a handle of zero length at both ends: the next point.
      auto tangent = [&](int back) {
        std::array<Rational, 4> u{};
        for (int e = 0; e < 2; ++e) {
          u[2 * e] = L[e][n].x - L[e][n - back].x;
          u[2 * e + 1] = L[e][n].y - L[e][n - back].y;
        }
        return u;
      };
      auto tangent_out = [&](int fwd) {
        std::array<Rational, 4> v{};
        for (int e = 0; e < 2; ++e) {
          v[2 * e] = R[e][fwd].x - R[e][0].x;
          v[2 * e + 1] = R[e][fwd].y - R[e][0].y;
        }
        return v;
      };
      std::array<Rational, 4> u = tangent(1), v = tangent_out(1);
      if (n >= 2 && is_zero_vector(u[0], u[1]) && is_zero_vector(u[2], u[3])) u = tangent(2);
      if (n >= 2 && is_zero_vector(v[0], v[1]) && is_zero_vector(v[2], v[3])) v = tangent_out(2);
      const G1Between g = g1_between({u[0], u[1], u[2], u[3], v[0], v[1], v[2], v[3]});
      if (!g.judged || g.holds) continue;
      const import::Piece& p = *m.piece;
      GateViolation viol;
      viol.joint = j;
      viol.t = jr.joint.knot;
      std::string& msg = viol.message;
      msg = "smooth at ";
      msg += p.from;
      msg += " and ";
      msg += p.to;
      msg += g.worst_angle >= 180 ? " but its tangents reverse between them: " : " but a kink between them: not G1 for ";
      for (std::size_t k = 0; k < g.fail.size(); ++k) {
        if (k) msg += "; ";
        msg += p.range(g.fail[k].first, g.fail[k].second);
        msg += " (s in (";
        msg += num(g.fail[k].first, 12);
        msg += ", ";
        msg += num(g.fail[k].second, 12);
        msg += "))";
      }
      msg += "; worst ";
      msg += num(g.worst_angle, 6);
      msg += " degrees at {";
      msg += p.location(g.worst_s);
      msg += "} (s = ";
      msg += num(g.worst_s, 12);
      msg += ")";
      out.push_back(std::move(viol));
    }
  }
  return out;
}

FontInfo interpolation_inputs(const std::string& path, const import::GlyphSelection& which,
                              const std::optional<import::Segment2>& between, std::vector<ReportInput>& inputs) {
  import::Masters m = import::read_masters(path, which, between);
  const std::size_t first = inputs.size();
  FontInfo info = font_inputs(m.font, inputs);
  // font_inputs: per glyph, an error item or one item per contour, in order.
  for (std::size_t gi = 0; gi < m.font.glyphs.size() && gi < info.glyphs.size(); ++gi) {
    if (!m.font.glyphs[gi].error.empty()) continue;
    const std::vector<std::size_t>& items = info.glyphs[gi].items;
    for (std::size_t c = 0; c < items.size() && c < m.motions[gi].size(); ++c)
      if (items[c] >= first)
        inputs[items[c]].motions =
            std::make_shared<const std::vector<import::ContourMotion>>(std::move(m.motions[gi][c]));
  }
  return info;
}

}  // namespace cmr::report
