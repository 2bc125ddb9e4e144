#include "report/glyph_nodes.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "bezierize/extract.hpp"
#include "design/fix.hpp"
#include "report/batch.hpp"

namespace cmr::report {

namespace {

Vec2 lerp(Vec2 a, Vec2 b, double t) { return a + (b - a) * t; }

/// The tail of a point's name after its glyph and contour ("b/c1/p3" -> "p3").
std::string tail(const std::string& name) { return name.substr(name.rfind('/') + 1); }

/// `handle` (a split's B1' or B2') on the tangent of `node` through the
/// source handle `source`: node + k v, v the primitive grid vector of
/// source - node and k >= 1 the whole multiple nearest; the handle as it is
/// where the source handle lies on its node.
Vec2 on_tangent(Vec2 node, Vec2 source, Vec2 handle, double grid) {
  const long dx = std::lround((source.x - node.x) / grid), dy = std::lround((source.y - node.y) / grid);
  const long g = std::gcd(dx, dy);
  if (g == 0) return node;
  const Vec2 v{static_cast<double>(dx / g) * grid, static_cast<double>(dy / g) * grid};
  const double k = std::max(1.0, std::round(glm::dot(handle - node, v) / glm::dot(v, v)));
  return node + v * k;
}

/// A node S with handles Q (before) and R (after) on the grid, exactly
/// smooth: S' one of the 9 grid points around S (S itself where
/// `node_held`: a source node, which stays), Q' = S' - a v,
/// R' = S' + b v (v primitive, |v_x|, |v_y| <= 40 cells; a, b >= 1), the
/// choice with the least squared distance of the three from S, Q and R.
struct SmoothNode {
  Vec2 q, s, r;
};
SmoothNode smooth_on_grid(Vec2 q, Vec2 s, Vec2 r, double grid, bool node_held) {
  constexpr int kReach = 40;
  SmoothNode best{q, s, r};
  double best_cost = -1;
  const Vec2 qg = q / grid, sg = s / grid, rg = r / grid;
  const Vec2 s0 = node_held ? sg : Vec2{std::round(sg.x), std::round(sg.y)};
  const int around = node_held ? 0 : 1;
  for (int sx = -around; sx <= around; ++sx)
    for (int sy = -around; sy <= around; ++sy) {
      const Vec2 c = s0 + Vec2{static_cast<double>(sx), static_cast<double>(sy)};
      const double cs = glm::dot(c - sg, c - sg);
      for (int dx = -kReach; dx <= kReach; ++dx)
        for (int dy = -kReach; dy <= kReach; ++dy) {
          if (std::gcd(dx, dy) != 1) continue;
          const Vec2 v{static_cast<double>(dx), static_cast<double>(dy)};
          const double vv = glm::dot(v, v);
          const double a = std::max(1.0, std::round(glm::dot(c - qg, v) / vv));
          const double b = std::max(1.0, std::round(glm::dot(rg - c, v) / vv));
          const Vec2 q2 = c - v * a, r2 = c + v * b;
          const double cost = cs + glm::dot(q2 - qg, q2 - qg) + glm::dot(r2 - rg, r2 - rg);
          if (best_cost < 0 || cost < best_cost) best_cost = cost, best = {q2 * grid, c * grid, r2 * grid};
        }
    }
  return best;
}

constexpr const char* kExtremum = "a curvature extremum";
constexpr const char* kJoin = "a line's smooth join";

/// Where to split a contour's segments: per segment index, its parameters
/// and why (the extremum gate's violations inside a cubic segment; the
/// cubic of a smooth line-to-curve join that fails g2 at 1/2, or at 1/3
/// and 2/3 where `join_nodes` is 2).
std::map<int, std::vector<std::pair<double, std::string>>> splits_of(const import::Contour& c,
                                                                      const GlyphFixOptions& options, int join_nodes) {
  std::map<int, std::vector<std::pair<double, std::string>>> at;
  const BSpline& spline = c.spline;
  if (spline.degree() != 3) return at;
  const auto& segs = spline.segments();
  const int n = static_cast<int>(segs.size());
  // A source cubic: its two inner points are the source's off-curve points.
  auto cubic = [&](int i) {
    const std::vector<int> pts = segment_points(spline, segs[i]);
    return pts.size() == 4 && c.font_point[pts[1]] >= 0 && c.font_point[pts[2]] == c.font_point[pts[1]] + 1 &&
           c.node[pts[0]] && c.node[pts[3]];
  };
  auto line = [&](int i) {
    const std::vector<int> pts = segment_points(spline, segs[i]);
    return pts.size() == 4 && c.font_point[pts[1]] < 0 && c.font_point[pts[2]] < 0;
  };
  const SplineReport r = judged_report(spline, judge_only(options.judge));
  for (const GateResult& gate : r.gates)
    for (const GateViolation& v : gate.violations) {
      if (gate.gate.kind == Gate::Kind::extrema_at_nodes && v.segment >= 0 && v.segment < n && cubic(v.segment) &&
          v.local_t > 0.02 && v.local_t < 0.98)
        at[v.segment].emplace_back(v.local_t, kExtremum);
      if (gate.gate.kind == Gate::Kind::g2_at_smooth_nodes && v.joint >= 0) {
        const int after = v.joint % n, before = (v.joint + n - 1) % n;
        for (int k = 1; k <= join_nodes; ++k) {
          const double t = static_cast<double>(k) / (join_nodes + 1);
          if (line(before) && cubic(after)) at[after].emplace_back(t, kJoin);
          if (line(after) && cubic(before)) at[before].emplace_back(t, kJoin);
        }
      }
    }
  for (auto& [seg, ts] : at) {
    // A cubic at a line's join: its join nodes only.
    if (std::any_of(ts.begin(), ts.end(), [](const auto& x) { return x.second == kJoin; }))
      ts.erase(std::remove_if(ts.begin(), ts.end(), [](const auto& x) { return x.second != kJoin; }), ts.end());
    std::sort(ts.begin(), ts.end());
    ts.erase(std::unique(ts.begin(), ts.end(), [](const auto& a, const auto& b) { return b.first - a.first < 0.02; }),
             ts.end());
  }
  return at;
}

}  // namespace

std::optional<NodesAdded> add_nodes(const import::Glyph& g, const std::string& text,
                                    const std::vector<ContourFix>& fixes, const GlyphFixOptions& options,
                                    int join_nodes) {
  const double grid = options.grid;
  std::vector<import::PointEdit> edits;
  std::vector<AddedNode> nodes;
  std::vector<std::pair<int, int>> place;  // per node: the source point it follows, and how far after it
  std::vector<std::vector<import::NewPoint>> source;
  for (const import::Contour& c : g.contours) {
    // The source positions (every source point is a control point of a cubic contour).
    const int count = *std::max_element(c.font_point.begin(), c.font_point.end()) + 1;
    if (static_cast<int>(source.size()) <= c.index) source.resize(c.index + 1);
    source[c.index].assign(std::max(count, 0), {});
    for (std::size_t k = 0; k < c.font_point.size(); ++k)
      if (c.font_point[k] >= 0) source[c.index][c.font_point[k]] = {c.spline.points()[k].x, c.spline.points()[k].y};
    const auto fix =
        std::find_if(fixes.begin(), fixes.end(), [&](const ContourFix& f) { return f.contour == c.index; });
    if (fix == fixes.end() || fix->fixed || fix->already || fix->untouched || fix->not_searched) continue;
    // Per split segment: its first handle's edit, with the new points after it.
    std::map<int, Vec2> want;  // per source handle of a split segment: where the split puts it
    std::map<int, int> node_of;  // and its node
    const std::size_t first_edit = edits.size();
    for (const auto& [seg, ts] : splits_of(c, options, join_nodes)) {
      const Segment& s = c.spline.segments()[seg];
      const std::vector<int> pts = segment_points(c.spline, s);
      std::vector<Vec2> b = bezier_segment(c.spline, s).points;
      import::PointEdit first{c.index, c.font_point[pts[1]], 0, 0};
      double done = 0;
      std::vector<SmoothNode> made;
      for (const auto& [t_seg, why] : ts) {
        const double t = (t_seg - done) / (1 - done);
        const Vec2 p01 = lerp(b[0], b[1], t), p12 = lerp(b[1], b[2], t), p23 = lerp(b[2], b[3], t);
        const Vec2 q = lerp(p01, p12, t), r = lerp(p12, p23, t), sp = lerp(q, r, t);
        if (made.empty()) want[first.point] = p01;
        else made.back().r = p01;  // the piece before: its second point
        made.push_back({q, sp, r});
        b = {sp, r, p23, b[3]};
        done = t_seg;
        // Its index in the new text, for now: after which source point, and where among the added ones.
        nodes.push_back({c.index, c.point_names[pts[0]] + "-" + tail(c.point_names[pts[3]]), t_seg, why, 0});
        place.emplace_back(first.point, 3 * static_cast<int>(made.size()) - 1);  // after Q_1 S_1 R_1 ... Q_j
      }
      want[c.font_point[pts[2]]] = b[2];
      node_of[first.point] = c.font_point[pts[0]];
      node_of[c.font_point[pts[2]]] = c.font_point[pts[3]];
      for (std::size_t j = 0; j < made.size(); ++j) {  // each new node exactly smooth on the grid
        SmoothNode& m = made[j];
        m = smooth_on_grid(m.q, m.s, m.r, grid, false);
        nodes[nodes.size() - made.size() + j].at = m.s;
        first.then.push_back({m.q.x, m.q.y, false});
        first.then.push_back({m.s.x, m.s.y, true});
        first.then.push_back({m.r.x, m.r.y, false});
      }
      first.move = false;
      edits.push_back(first);
    }
    // The split segments' end nodes: an exactly smooth one keeps G1 (its two
    // handles on one primitive grid vector, the direction nearest both), one
    // smooth with a line keeps the line's direction, a corner's handle is rounded.
    const std::vector<import::NewPoint>& src = source[c.index];
    const int n = static_cast<int>(src.size());
    std::vector<bool> on(n, false);
    for (std::size_t k = 0; k < c.font_point.size(); ++k)
      if (c.font_point[k] >= 0) on[c.font_point[k]] = c.node[k];
    auto pos = [&](int i) { return Vec2{src[i].x, src[i].y}; };
    std::map<int, Vec2> landed;
    for (const auto& [h, node] : node_of) {
      if (landed.count(h)) continue;
      const Vec2 at = pos(node);
      const int in = (node + n - 1) % n, out = (node + 1) % n;
      const Vec2 d_in = at - pos(in), d_out = pos(out) - at;
      const bool collinear = d_in.x * d_out.y == d_in.y * d_out.x && glm::dot(d_in, d_out) > 0;
      auto wanted = [&](int i) { return want.count(i) ? want[i] : pos(i); };
      if (collinear && !on[in] && !on[out]) {
        const SmoothNode m = smooth_on_grid(wanted(in), at, wanted(out), grid, true);
        landed[in] = m.q, landed[out] = m.r;
      } else if (collinear) {
        landed[h] = on_tangent(at, pos(h), want[h], grid);
      } else {
        landed[h] = {std::round(want[h].x / grid) * grid, std::round(want[h].y / grid) * grid};
      }
    }
    for (const auto& [h, p] : landed) {
      auto e = std::find_if(edits.begin() + static_cast<std::ptrdiff_t>(first_edit), edits.end(),
                            [&](const import::PointEdit& x) { return x.point == h; });
      if (e == edits.end()) {
        edits.push_back({c.index, h, 0, 0});
        e = edits.end() - 1;
      }
      e->x = p.x, e->y = p.y, e->move = true;
    }
  }
  if (edits.empty()) return std::nullopt;
  NodesAdded out;
  out.text = import::rewrite_glif_points(text, edits, g.source);
  out.glyph = import::read_glif_text(out.text, g.source);
  out.glyph.name = g.name;
  out.source = std::move(source);
  // Where each point of the new text comes from, and the added nodes' indices in it.
  out.source_point.resize(out.source.size());
  for (std::size_t ci = 0; ci < out.source.size(); ++ci)
    for (int sp = 0; sp < static_cast<int>(out.source[ci].size()); ++sp) {
      for (std::size_t i = 0; i < nodes.size(); ++i)
        if (nodes[i].contour == static_cast<int>(ci) && place[i].first == sp)
          nodes[i].point = static_cast<int>(out.source_point[ci].size()) + place[i].second;
      out.source_point[ci].push_back(sp);
      for (const import::PointEdit& e : edits)
        if (e.contour == static_cast<int>(ci) && e.point == sp)
          out.source_point[ci].insert(out.source_point[ci].end(), e.then.size(), -1);
    }
  out.nodes = std::move(nodes);
  return out;
}

bool splits_a_join(const NodesAdded& added) {
  return std::any_of(added.nodes.begin(), added.nodes.end(), [](const AddedNode& n) { return n.why == kJoin; });
}

std::vector<import::PointEdit> source_edits(const NodesAdded& added, const std::vector<import::PointEdit>& edits) {
  std::vector<import::PointEdit> out;
  for (std::size_t ci = 0; ci < added.source_point.size(); ++ci) {
    // The new text's points at their final positions.
    std::vector<import::NewPoint> at;
    for (const import::Contour& c : added.glyph.contours)
      if (c.index == static_cast<int>(ci)) {
        at.assign(added.source_point[ci].size(), {});
        for (std::size_t k = 0; k < c.font_point.size(); ++k)
          if (c.font_point[k] >= 0) at[c.font_point[k]] = {c.spline.points()[k].x, c.spline.points()[k].y, c.node[k]};
      }
    if (at.empty()) continue;
    for (const import::PointEdit& e : edits)
      if (e.contour == static_cast<int>(ci) && e.point >= 0 && e.point < static_cast<int>(at.size()))
        at[e.point].x = e.x, at[e.point].y = e.y;
    const std::vector<int>& from = added.source_point[ci];
    int before = -1;  // the last source point
    for (std::size_t k = 0; k < from.size(); ++k) {
      if (from[k] >= 0) {
        before = from[k];
        const import::NewPoint& was = added.source[ci][before];
        if (at[k].x != was.x || at[k].y != was.y) out.push_back({static_cast<int>(ci), before, at[k].x, at[k].y});
      } else {
        // After the source point before it (its edit, made where it has none).
        if (out.empty() || out.back().contour != static_cast<int>(ci) || out.back().point != before) {
          const import::NewPoint& was = added.source[ci][before];
          out.push_back({static_cast<int>(ci), before, was.x, was.y, false});
        }
        out.back().then.push_back(at[k]);
      }
    }
  }
  return out;
}

}  // namespace cmr::report
