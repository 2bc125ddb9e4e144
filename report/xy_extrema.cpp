// xy-extrema-at-nodes (report/xy_extrema.hpp): extrema of x and y away from
// the nodes, by exact root isolation of x' and y' per segment.
#include "report/xy_extrema.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "bezierize/extract.hpp"
#include "numeric/roots.hpp"
#include "report/report.hpp"
#include "spline/format.hpp"

namespace cmr::report {
namespace {

std::string num(double v, int precision = 6) { return format_number(v, precision); }

/// x (axis 0) or y (axis 1) of segment `segment` in Bernstein form, exactly:
/// the coordinate's Bezier coefficients, and W's for a rational spline
/// (empty when polynomial).
void coordinate(const BSpline& s, int segment, int axis, Bernstein<Rational>& c, Bernstein<Rational>& w) {
  const Segment& seg = s.segments()[segment];
  c.clear();
  w.clear();
  if (s.is_rational()) {
    for (const HPoint<Rational>& h : segment_homogeneous_points<Rational>(s, seg)) {
      c.push_back(axis == 0 ? h.x : h.y);
      w.push_back(h.z);
    }
  } else {
    for (const Point<Rational>& p : segment_bezier_points<Rational>(s, seg)) c.push_back(axis == 0 ? p.x : p.y);
  }
}

/// The outline's point at local parameter u of a segment, from its exact
/// Bezier form (rounded to double at the end).
Vec2 point_at(const BSpline& s, int segment, const Rational& u) {
  Bernstein<Rational> x, y, w;
  coordinate(s, segment, 0, x, w);
  coordinate(s, segment, 1, y, w);
  Rational X = bernstein_eval(x, u), Y = bernstein_eval(y, u);
  if (!w.empty()) {
    const Rational W = bernstein_eval(w, u);
    X /= W;
    Y /= W;
  }
  return {X.get_d(), Y.get_d()};
}

/// A root's place in its segment: the enclosure's middle (exact when the
/// root is).
Rational middle(const RootInterval& r) { return r.exact() ? r.lo : Rational((r.lo + r.hi) / 2); }

const char* axis_noun(int axis, int kind) {
  if (axis == 0) return kind > 0 ? "x maximum (vertical tangent)" : "x minimum (vertical tangent)";
  return kind > 0 ? "y maximum (horizontal tangent)" : "y minimum (horizontal tangent)";
}

}  // namespace

Bernstein<Rational> xy_derivative(const BSpline& s, int segment, int axis) {
  Bernstein<Rational> c, w;
  coordinate(s, segment, axis, c, w);
  if (w.empty()) return bernstein_derivative(c);
  // (X' W - X W') at degree 2n-1 (header comment).
  Bernstein<Rational> a = bernstein_product(bernstein_derivative(c), w);
  const Bernstein<Rational> b = bernstein_product(c, bernstein_derivative(w));
  if (a.empty()) return a;
  for (std::size_t k = 0; k < a.size(); ++k) a[k] -= b[k];
  return a;
}

std::vector<XyExtremum> xy_extrema(const SplineReport& r) {
  std::vector<XyExtremum> out;
  if (!r.spline) return out;
  const BSpline& s = *r.spline;
  const int N = s.segment_count(), d = s.degree();
  const bool closed = s.closed();
  // Joint j (0..N; a closed spline's seam is N, and also starts segment 0)
  // is a node when its knot multiplicity is >= d; an open spline's ends are.
  std::vector<bool> node(N + 1, false);
  node[0] = node[N] = !closed;
  for (const JointReport& jr : r.joints) {
    const int j = jr.joint.index;
    if (j >= 0 && j <= N) node[j] = jr.joint.multiplicity >= d;
    if (closed && (j == 0 || j == N)) node[0] = node[N] = jr.joint.multiplicity >= d;
  }

  // Along the outline, per axis: nodes and extrema in order, for the
  // overshoot (an extremum's neighbours in its own coordinate).
  struct Item {
    double value = 0;
    int extremum = -1;  ///< index into out, or -1 for a node
  };
  std::vector<Item> along[2];
  auto add_node = [&](double t) {
    const Vec2 p = evaluate(s, t);
    along[0].push_back({p.x, -1});
    along[1].push_back({p.y, -1});
  };
  if (!closed) add_node(s.domain_begin());

  // Per segment and axis: the roots of the derivative and the sign just
  // before its end (for a joint that is no node).
  std::vector<std::array<int, 2>> sign_end(N, {0, 0}), sign_start(N, {0, 0});
  std::vector<std::array<bool, 2>> root_end(N, {false, false}), root_start(N, {false, false});
  std::vector<std::array<std::vector<RootInterval>, 2>> roots(N);
  for (int i = 0; i < N; ++i) {
    const SpanReport& span = r.spans[i];
    if (span.eta_zero || span.shape.pole) continue;  // straight: none; a pole: every gate's violation already
    for (int axis = 0; axis < 2; ++axis) {
      const Bernstein<Rational> p = xy_derivative(s, i, axis);
      if (is_zero(p)) continue;  // axis-parallel piece
      roots[i][axis] = isolate_roots(p);
      for (const RootInterval& q : roots[i][axis]) {
        if (q.exact() && q.lo == 0) root_start[i][axis] = true, sign_start[i][axis] = q.sign_after;
        if (q.exact() && q.lo == 1) root_end[i][axis] = true, sign_end[i][axis] = q.sign_before;
      }
    }
  }

  for (int i = 0; i < N; ++i) {
    const Segment& seg = s.segments()[i];
    // Interior extrema of both axes in parameter order.
    std::vector<std::pair<Rational, int>> interior;  // (local u, axis) with the root's index below
    std::vector<const RootInterval*> which;
    for (int axis = 0; axis < 2; ++axis)
      for (const RootInterval& q : roots[i][axis]) {
        if (q.exact() && (q.lo == 0 || q.lo == 1)) continue;  // on a joint: below
        if (!q.sign_change()) continue;                        // touches without turning
        interior.emplace_back(middle(q), axis);
        which.push_back(&q);
      }
    std::vector<std::size_t> order(interior.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return interior[a].first != interior[b].first ? interior[a].first < interior[b].first
                                                    : interior[a].second < interior[b].second;
    });
    for (std::size_t k : order) {
      const RootInterval& q = *which[k];
      XyExtremum e;
      e.axis = interior[k].second;
      // x' goes from + to -: a maximum.
      e.kind = q.sign_before > 0 ? 1 : -1;
      e.segment = i;
      e.local_t = nearest_double(interior[k].first);
      e.local_lo = double_below(q.lo);
      e.local_hi = double_above(q.hi);
      e.t = seg.a + (seg.b - seg.a) * e.local_t;
      e.point = point_at(s, i, interior[k].first);
      out.push_back(e);
      for (int axis = 0; axis < 2; ++axis)
        along[axis].push_back({axis == 0 ? e.point.x : e.point.y, axis == e.axis ? static_cast<int>(out.size()) - 1 : -2});
    }
    // The joint at the segment's end.
    const int j = i + 1;
    if (!closed && j == N) {
      add_node(seg.b);
      break;
    }
    if (node[j]) {
      add_node(seg.b);
      continue;
    }
    const int next = j % N;
    for (int axis = 0; axis < 2; ++axis) {
      // C^1 at a joint that is no node: an extremum there when the
      // derivative vanishes on both sides and its sign differs across it.
      if (!root_end[i][axis] || !root_start[next][axis]) continue;
      if (sign_end[i][axis] == 0 || sign_start[next][axis] == 0 || sign_end[i][axis] == sign_start[next][axis]) continue;
      XyExtremum e;
      e.axis = axis;
      e.kind = sign_end[i][axis] > 0 ? 1 : -1;
      e.joint = closed && j == N ? N : j;
      e.t = seg.b;
      e.local_t = e.local_lo = e.local_hi = 1;
      e.point = evaluate(s, seg.b);
      out.push_back(e);
      for (int a = 0; a < 2; ++a)
        along[a].push_back({a == 0 ? e.point.x : e.point.y, a == axis ? static_cast<int>(out.size()) - 1 : -2});
    }
  }

  // Overshoot: against the nearer neighbour of the same axis (a node, or an
  // extremum of this axis; the other axis' extrema are skipped), cyclically
  // on a closed spline.
  for (int axis = 0; axis < 2; ++axis) {
    std::vector<Item> items;
    for (const Item& it : along[axis])
      if (it.extremum != -2) items.push_back(it);
    const int m = static_cast<int>(items.size());
    for (int k = 0; k < m; ++k) {
      if (items[k].extremum < 0) continue;
      const double v = items[k].value;
      double nearer = std::numeric_limits<double>::infinity();
      auto side = [&](int n) {
        if (n < 0 || n >= m) {
          if (!closed) return;
          n = (n + m) % m;
        }
        if (n == k) return;
        nearer = std::min(nearer, std::abs(v - items[n].value));
      };
      side(k - 1);
      side(k + 1);
      out[items[k].extremum].overshoot = std::isfinite(nearer) ? nearer : 0.0;
    }
  }
  return out;
}

std::vector<GateViolation> xy_extremum_violations(const SplineReport& r, double tolerance) {
  std::vector<GateViolation> out;
  for (const XyExtremum& e : xy_extrema(r)) {
    if (e.overshoot < tolerance) continue;
    GateViolation v;
    v.segment = e.segment;
    v.joint = e.joint;
    v.t = e.t;
    v.local_t = e.segment >= 0 ? e.local_t : 0.0;
    // Built by appending (GCC 12's -Wrestrict misfires on "literal" + string&& at -O3).
    std::string at = "(";
    at += num(e.point.x);
    at += ", ";
    at += num(e.point.y);
    at += ")";
    std::string& m = v.message;
    m = axis_noun(e.axis, e.kind);
    if (e.segment >= 0) {
      m += " inside segment ";
      m += std::to_string(e.segment);
      m += " at t = ";
      m += num(e.t);
      m += " (";
      m += num(e.local_t, 4);
      m += " of the segment)";
    } else {
      m += " at joint ";
      m += std::to_string(e.joint);
      m += " (t = ";
      m += num(e.t);
      m += "), which is no node";
    }
    m += " at ";
    m += at;
    m += ", ";
    m += num(e.overshoot, 4);
    m += " units past its neighbours: add a node at ";
    m += at;
    out.push_back(std::move(v));
  }
  return out;
}

}  // namespace cmr::report
