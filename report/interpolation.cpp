// The interpolation gates (report/interpolation.hpp).
#include "report/interpolation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <numbers>

#include "numeric/bernstein.hpp"
#include "bezierize/between.hpp"
#include "bezierize/extract.hpp"
#include "numeric/roots.hpp"
#include "report/report.hpp"
#include "spline/format.hpp"

namespace cmr::report {
namespace {

using RPoint = Point<Rational>;
using Poly = Bernstein<Rational>;

std::string num(double v, int precision = 6) { return format_number(v, precision); }

/// "1 degree", "0.5 degrees".
std::string degrees(double v) {
  std::string out = num(v, 6);
  out += v == 1 ? " degree" : " degrees";
  return out;
}

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

bool g1_at(const Rational& ux, const Rational& uy, const Rational& vx, const Rational& vy, const Rational& tan_turn) {
  const Rational c = ux * vy - uy * vx, d = ux * vx + uy * vy;
  if (tan_turn == 0) return c == 0 && d > 0;
  return d > 0 && abs(c) <= tan_turn * d;
}

G1Between g1_between(const NodeTangents& t, const Rational& tan_turn) {
  G1Between out;
  out.judged = true;
  const Poly ux{t.u0x, t.u1x}, uy{t.u0y, t.u1y}, vx{t.v0x, t.v1x}, vy{t.v0y, t.v1y};
  const Poly c = sub(bernstein_product(ux, vy), bernstein_product(uy, vx));
  const Poly d = add(bernstein_product(ux, vx), bernstein_product(uy, vy));
  const double to_degrees = 180 / std::numbers::pi;
  // The open intervals between consecutive zeros of p in [0, 1] (0 and 1
  // count as bounds), where p != 0; with `negative`, those where p < 0.
  auto between_roots = [&](const Poly& p, bool negative) {
    const std::vector<RootInterval> roots = isolate_roots(p);
    std::vector<std::pair<Rational, Rational>> bounds;
    if (roots.empty() || roots.front().lo != 0) bounds.emplace_back(Rational(0), Rational(0));
    for (const RootInterval& r : roots) bounds.emplace_back(r.lo, r.hi);
    if (roots.empty() || roots.back().hi != 1) bounds.emplace_back(Rational(1), Rational(1));
    for (std::size_t k = 0; k + 1 < bounds.size(); ++k) {
      if (!(bounds[k].second < bounds[k + 1].first)) continue;
      const Rational mid = (bounds[k].second + bounds[k + 1].first) / 2;
      if (negative && bernstein_eval(p, mid) > 0) continue;
      out.fail.emplace_back(double_below(bounds[k].second), double_above(bounds[k + 1].first));
    }
  };
  // The worst angle: at a root of g = c' d - c d' inside (0, 1), or at an end.
  auto worst = [&] {
    const Poly g = sub(bernstein_product(bernstein_derivative(c), d), bernstein_product(c, bernstein_derivative(d)));
    std::vector<Rational> candidates{Rational(0), Rational(1)};
    if (!is_zero(g))
      for (const RootInterval& r : isolate_roots(g))
        if (middle(r) > 0 && middle(r) < 1) candidates.push_back(middle(r));
    out.worst_angle = -1;
    for (const Rational& s : candidates) {
      const double a = std::abs(std::atan2(value_at(c, s), value_at(d, s))) * to_degrees;
      if (a > out.worst_angle) {
        out.worst_angle = a;
        out.worst_s = nearest_double(s);
      }
    }
  };
  if (tan_turn > 0) {
    // Within the turn: T d - c >= 0, T d + c >= 0 and d > 0 (the header's h+ and h-).
    Poly scaled = d;
    for (Rational& k : scaled) k *= tan_turn;
    for (const Poly& h : {sub(scaled, c), add(scaled, c), d})
      if (!is_zero(h)) between_roots(h, true);
    std::sort(out.fail.begin(), out.fail.end());
    std::vector<std::pair<double, double>> merged;
    for (const auto& f : out.fail) {
      if (!merged.empty() && f.first <= merged.back().second)
        merged.back().second = std::max(merged.back().second, f.second);
      else
        merged.push_back(f);
    }
    out.fail = std::move(merged);
    out.holds = out.fail.empty();
    if (!out.holds) worst();
    return out;
  }
  if (is_zero(c)) {
    // Collinear throughout: G1 unless the direction reverses (d <= 0 somewhere).
    between_roots(d, true);
    const std::vector<RootInterval> zeros = isolate_roots(d);
    if (out.fail.empty() && zeros.empty()) {
      out.holds = true;
      return out;
    }
    out.worst_s = zeros.empty() ? out.fail.front().first : nearest_double(middle(zeros.front()));
    out.worst_angle = 180;
    if (out.fail.empty()) out.fail.emplace_back(out.worst_s, out.worst_s);  // touches 0: a collapsed handle
    return out;
  }
  between_roots(c, false);
  worst();
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

std::vector<GateViolation> g1_between_violations(const SplineReport& r, double turn_degrees) {
  std::vector<GateViolation> out;
  if (!r.motions || !r.spline) return out;
  const Rational T(turn_degrees > 0 ? std::tan(turn_degrees * std::numbers::pi / 180) : 0.0);
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
      // Smooth at the masters (s = 0 and 1 of the masters' line, whatever part of it the piece is).
      if (m.piece->s0 != 0 || m.piece->s1 != 1) {
        const import::Piece whole;
        import::ContourMotion line{std::make_shared<const import::Piece>(whole), m.a, m.b, {}};
        std::vector<RPoint> l0 = end_points(line, left, false), l1 = end_points(line, left, true);
        std::vector<RPoint> r0 = end_points(line, right, false), r1 = end_points(line, right, true);
        const int bu = u == tangent(1) ? 1 : 2, bv = v == tangent_out(1) ? 1 : 2;
        if (!g1_at(l0[n].x - l0[n - bu].x, l0[n].y - l0[n - bu].y, r0[bv].x - r0[0].x, r0[bv].y - r0[0].y, T) ||
            !g1_at(l1[n].x - l1[n - bu].x, l1[n].y - l1[n - bu].y, r1[bv].x - r1[0].x, r1[bv].y - r1[0].y, T))
          continue;
      } else if (!g1_at(u[0], u[1], v[0], v[1], T) || !g1_at(u[2], u[3], v[2], v[3], T)) {
        continue;
      }
      const G1Between g = g1_between({u[0], u[1], u[2], u[3], v[0], v[1], v[2], v[3]}, T);
      if (g.holds) continue;
      const import::Piece& p = *m.piece;
      GateViolation viol;
      viol.joint = j;
      viol.t = jr.joint.knot;
      viol.motion = static_cast<int>(&m - r.motions->data());
      viol.motion_s = p.s0 + (p.s1 - p.s0) * std::clamp(g.worst_s, 0.0, 1.0);
      std::string& msg = viol.message;
      if (T > 0) {
        msg = "within ";
        msg += degrees(turn_degrees);
        msg += " of G1 at ";
      } else {
        msg = "smooth at ";
      }
      msg += p.master_a;
      msg += " and ";
      msg += p.master_b;
      if (g.worst_angle >= 180) {
        msg += " but its tangents reverse between them: ";
      } else if (T > 0) {
        msg += " but not between them: turns more than ";
        msg += degrees(turn_degrees);
        msg += " for ";
      } else {
        msg += " but a kink between them: not G1 for ";
      }
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

namespace {

/// Segment `seg`'s Bezier points (doubles: the splines' own control points of a Bezier window).
std::vector<Vec2> bezier_of(const BSpline& s, int seg) { return segment_bezier_points<double>(s, s.segments()[seg]); }

/// Where on the piece a location s of the masters' line lies: sigma.
double sigma_of(const import::Piece& p, double s) { return p.s1 == p.s0 ? 0.0 : (s - p.s0) / (p.s1 - p.s0); }

}  // namespace

std::vector<GateViolation> curvature_between_violations(const SplineReport& r, bool extrema) {
  std::vector<GateViolation> out;
  if (!r.motions || !r.spline) return out;
  const BSpline& s = *r.spline;
  const int N = s.segment_count(), deg = s.degree();
  BetweenOptions options;
  for (const import::ContourMotion& m : *r.motions) {
    if (m.a.segment_count() != N || m.b.segment_count() != N || m.a.is_rational() || deg < 2) continue;
    const import::Piece& p = *m.piece;
    for (int i = 0; i < N; ++i) {
      const std::vector<Vec2> A = bezier_of(m.a, i), B = bezier_of(m.b, i);
      // Monotone at both masters (straight pieces: constant, which passes).
      if (monotone_between(A, A, options).kind != BetweenVerdict::Kind::holds_throughout ||
          monotone_between(B, B, options).kind != BetweenVerdict::Kind::holds_throughout)
        continue;
      const BetweenVerdict v = monotone_between(A, B, options);
      if (v.kind == BetweenVerdict::Kind::holds_throughout) continue;
      if (v.s_lower >= p.s1) continue;  // certified on all of this part of the line
      GateViolation viol;
      viol.segment = i;
      viol.t = s.segments()[i].a;
      std::string& msg = viol.message;
      msg = "curvature monotone at ";
      msg += p.master_a;
      msg += " and ";
      msg += p.master_b;
      const bool inside = v.kind == BetweenVerdict::Kind::fails && v.s_first_fail >= p.s0 && v.s_first_fail <= p.s1;
      if (inside) {
        viol.motion = static_cast<int>(&m - r.motions->data());
        viol.motion_s = v.s_first_fail;
        const double sig = sigma_of(p, v.s_first_fail);
        viol.local_t = v.t_witness;
        viol.t = s.segments()[i].a + (s.segments()[i].b - s.segments()[i].a) * v.t_witness;
        msg += " but not at {";
        msg += p.location(sig);
        msg += "} (s = ";
        msg += num(sig, 12);
        msg += "): a curvature extremum inside segment ";
        msg += std::to_string(i);
        msg += " at t = ";
        msg += num(v.t_witness, 6);
        msg += " of the segment; monotone at every location before {";
        msg += p.location(std::max(0.0, sigma_of(p, v.s_lower)));
        msg += "}";
      } else {
        msg += ": undecided between them (certified up to {";
        msg += p.location(std::max(0.0, sigma_of(p, v.s_lower)));
        msg += "}, the certificate's depth or cell budget spent)";
      }
      out.push_back(std::move(viol));
    }
    if (!extrema) continue;
    // A node that is a curvature extremum at both masters must stay one.
    for (const JointReport& jr : r.joints) {
      const int j = jr.joint.index;
      if (jr.joint.multiplicity < deg) continue;
      const int right = j % N, left = s.closed() ? (right + N - 1) % N : right - 1;
      if (left < 0 || (!s.closed() && j >= N)) continue;
      const NodeBetween nb = node_lambda_between(bezier_of(m.a, left), bezier_of(m.b, left), bezier_of(m.a, right),
                                                 bezier_of(m.b, right));
      if (nb.pattern_kept()) continue;
      // An extremum at both masters: the signs at s = 0 and 1 differ across the node on each.
      const NodeBetween at_a = node_lambda_between(bezier_of(m.a, left), bezier_of(m.a, left), bezier_of(m.a, right),
                                                   bezier_of(m.a, right));
      const NodeBetween at_b = node_lambda_between(bezier_of(m.b, left), bezier_of(m.b, left), bezier_of(m.b, right),
                                                   bezier_of(m.b, right));
      const bool extremum_a = at_a.pattern_kept() && at_a.left_sign != at_a.right_sign;
      const bool extremum_b = at_b.pattern_kept() && at_b.left_sign != at_b.right_sign;
      if (!extremum_a || !extremum_b) continue;
      const double zero = nb.left_zero_s >= 0 && (nb.right_zero_s < 0 || nb.left_zero_s <= nb.right_zero_s)
                              ? nb.left_zero_s
                              : nb.right_zero_s;
      if (zero < p.s0 || zero > p.s1) continue;
      GateViolation viol;
      viol.joint = j;
      viol.t = jr.joint.knot;
      viol.message = "a curvature extremum at ";
      viol.message += p.master_a;
      viol.message += " and ";
      viol.message += p.master_b;
      viol.message += " but the curvature turns flat beside the node at {";
      viol.message += p.location(sigma_of(p, zero));
      viol.message += "} (lambda = 0 there): its extremum may leave the node";
      out.push_back(std::move(viol));
    }
  }
  return out;
}

FontInfo interpolation_inputs(const std::string& path, const import::GlyphSelection& which,
                              const std::optional<import::Segment2>& between, std::vector<ReportInput>& inputs,
                              const std::optional<Shard>& shard, std::size_t position) {
  import::Masters m = import::read_masters(path, which, between);
  if (shard) {  // the same glyphs of both lists (parallel: motions[g] is glyph g's)
    keep_shard_glyphs(*shard, position, m.font.glyphs);
    keep_shard_glyphs(*shard, position, m.motions);
  }
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
