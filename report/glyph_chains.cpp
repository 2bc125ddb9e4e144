// The glyph fix's chain search (glyph_chains.hpp: the derivation).
#include "report/glyph_chains.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>
#include <optional>
#include <span>
#include <utility>

#include "bezierize/classify.hpp"
#include "bezierize/extract.hpp"
#include "design/fix.hpp"
#include "report/batch.hpp"
#include "spline/errors.hpp"

namespace cmr::report::glyph_detail {

bool may_move(const import::Contour& c, const std::vector<int>& movable, int k) {
  return c.font_point[k] >= 0 && std::find(movable.begin(), movable.end(), k) != movable.end();
}

std::array<double, 2> passing_left(double kr, double t) {
  if (kr > 0) return {kr * (1 - t), kr / (1 - t)};
  if (kr < 0) return {kr / (1 - t), kr * (1 - t)};
  return {0, 0};
}

namespace {

/// A candidate of one segment: its two handles' positions (or none: a line,
/// held), end curvatures and cost.
struct State {
  Vec2 h1{0.0}, h2{0.0};
  double k0 = 0, k1 = 0, cost = 0;
  Vec2 inner{0.0};  ///< a run of three's middle off-curve point
  int s_off = 0, e_off = 0;  ///< its start and end node's offsets (indices into their node_offsets)
};

/// The positions one handle tries, each with its squared move from the source.
struct Options {
  std::vector<Vec2> at;
  std::vector<double> cost;
  bool line = false;  ///< `at` is in order along one line (a slide, or a line's grid points)
};

/// End curvatures of the Bezier piece b (degree d = b.size() - 1 >= 2),
/// signed, as the gate computes them (bezierize/analyze.cpp,
/// certified_end_curvature): c A / G / sqrt(G), c = (d-1)/d, with a and b
/// the first two legs read from that end, A = det(a, b) (negated at the
/// end: read backwards the turning sense flips) and G = a.a; NaN where G
/// is 0. Where A and G are exact in doubles (grid coordinates: products of
/// a few dozen bits) the gate's certified values are their truncations,
/// the same doubles, so these are its values bit for bit.
std::array<double, 2> end_curvatures(std::span<const Vec2> b) {
  const std::size_t d = b.size() - 1;
  const double c = (static_cast<double>(d) - 1.0) / static_cast<double>(d);
  auto kappa = [c](Vec2 q0, Vec2 q1, Vec2 q2, double sense) {
    const Vec2 a = q1 - q0;
    const double A = sense * det(a, q2 - q1) + 0.0, G = dot(a, a);
    return G > 0 ? c * A / G / std::sqrt(G) : std::numeric_limits<double>::quiet_NaN();
  };
  return {kappa(b[0], b[1], b[2], 1.0), kappa(b[d], b[d - 1], b[d - 2], -1.0)};
}

/// A segment's Bezier points as sums of its control points: weights[r],
/// the (distinct point, weight) pairs with B_r = sum of weight * point (the
/// blossom of data 1 on that point, 0 elsewhere; for a cubic chain and a
/// quadratic's explicit node a single 1, for an implied node 1/2 and 1/2).
struct Piece {
  std::array<std::vector<std::pair<int, double>>, 4> weights;
};

/// Per segment of the closed polynomial `s` (degree 2 or 3), its Piece:
/// each distinct point's influence (every copy of it in the unrolled points).
std::vector<Piece> pieces_of(const BSpline& s) {
  const int d = s.degree(), m = s.unique_point_count();
  std::vector<Piece> out(static_cast<std::size_t>(s.segment_count()));
  for (int k = 0; k < m; ++k) {
    std::vector<int> copies;
    for (int i = k; i < s.point_count(); i += m) copies.push_back(i);
    for (const SegmentInfluence& si : influence(s, copies))
      for (int r = 0; r <= d; ++r)
        if (si.w[static_cast<std::size_t>(r)] != 0)
          out[static_cast<std::size_t>(si.segment)].weights[r].push_back({k, si.w[static_cast<std::size_t>(r)]});
  }
  return out;
}

/// A run of segments from one explicit node to the next: a cubic segment,
/// or a quadratic run of off-curve points (its pieces meet at implied
/// nodes). `free`: its points other than the two nodes, in order.
struct Unit {
  std::vector<int> segments;
  int start = 0, end = 0;  ///< the nodes it runs from and to
  std::vector<int> free;
};

/// The node a piece starts (ends) at: its first (last) Bezier point where
/// that is one control point that `node` marks explicit; -1 elsewhere.
int node_at(const Piece& p, int r, const std::vector<bool>& node) {
  const auto& w = p.weights[static_cast<std::size_t>(r)];
  return w.size() == 1 && w[0].second == 1 && node[static_cast<std::size_t>(w[0].first)] ? w[0].first : -1;
}

/// The units of a contour, in order from the first segment that starts at
/// an explicit node (so unit u is segment u of a cubic contour); none where
/// no segment does or a piece's ends are not what units need.
std::vector<Unit> units_of(const std::vector<Piece>& pieces, int degree, const std::vector<bool>& node) {
  const int n = static_cast<int>(pieces.size());
  int first = 0;
  while (first < n && node_at(pieces[static_cast<std::size_t>(first)], 0, node) < 0) ++first;
  if (first == n) return {};
  std::vector<Unit> out;
  for (int i = 0; i < n; ++i) {
    const int s = (first + i) % n;
    const Piece& p = pieces[static_cast<std::size_t>(s)];
    if (const int start = node_at(p, 0, node); start >= 0) out.push_back({{}, start, -1, {}});
    Unit& u = out.back();
    u.segments.push_back(s);
    for (int r = 0; r <= degree; ++r)
      for (const auto& [k, w] : p.weights[static_cast<std::size_t>(r)])
        if (k != u.start && std::find(u.free.begin(), u.free.end(), k) == u.free.end()) u.free.push_back(k);
    u.end = node_at(p, degree, node);
  }
  for (Unit& u : out) {
    if (u.end < 0) return {};
    u.free.erase(std::remove(u.free.begin(), u.free.end(), u.end), u.free.end());
    if (u.free.empty()) return {};
  }
  return out;
}

/// One step of the shortest path: best[q], the least cost of reaching state
/// q of `layer` from a state p of `prev` (whose least cost is prev_best[p])
/// that ends where q starts (p's end node offset q's start node offset)
/// with g2 passing between p's k1 and q's k0 (tolerance t), plus q's own
/// cost; from[q] that p (-1, best infinite: none). Both sorted by the
/// offset and then by the curvatures there, the passing p of each q form a
/// window of its offset's group whose ends rise with q's k0: a
/// sliding-window minimum.
void advance(const std::vector<State>& prev, const std::vector<double>& prev_best, const std::vector<State>& layer,
             double t, std::vector<double>& best, std::vector<int>& from) {
  best.assign(layer.size(), std::numeric_limits<double>::infinity());
  from.assign(layer.size(), -1);
  std::vector<int> by_k1(prev.size()), by_k0(layer.size());
  std::iota(by_k1.begin(), by_k1.end(), 0);
  std::iota(by_k0.begin(), by_k0.end(), 0);
  std::sort(by_k1.begin(), by_k1.end(), [&](int x, int y) {
    return prev[x].e_off != prev[y].e_off ? prev[x].e_off < prev[y].e_off : prev[x].k1 < prev[y].k1;
  });
  std::sort(by_k0.begin(), by_k0.end(), [&](int x, int y) {
    return layer[x].s_off != layer[y].s_off ? layer[x].s_off < layer[y].s_off : layer[x].k0 < layer[y].k0;
  });
  std::size_t group = 0;  // the first of by_k1 in the current offset's group
  for (std::size_t b = 0; b < by_k0.size();) {
    const int off = layer[by_k0[b]].s_off;
    std::size_t b_end = b;
    while (b_end < by_k0.size() && layer[by_k0[b_end]].s_off == off) ++b_end;
    while (group < by_k1.size() && prev[by_k1[group]].e_off < off) ++group;
    std::size_t group_end = group;
    while (group_end < by_k1.size() && prev[by_k1[group_end]].e_off == off) ++group_end;
    std::deque<std::size_t> window;  // positions in by_k1 whose best rises from the front
    std::size_t in = group, out_of = group;
    for (; b < b_end; ++b) {
      const int q = by_k0[b];
      const std::array<double, 2> range = passing_left(layer[q].k0, t);
      while (in < group_end && prev[by_k1[in]].k1 <= range[1]) {
        const double v = prev_best[by_k1[in]];
        while (!window.empty() && prev_best[by_k1[window.back()]] >= v) window.pop_back();
        window.push_back(in++);
      }
      while (out_of < in && prev[by_k1[out_of]].k1 < range[0]) ++out_of;
      while (!window.empty() && window.front() < out_of) window.pop_front();
      if (window.empty() || !std::isfinite(prev_best[by_k1[window.front()]])) continue;
      best[q] = layer[q].cost + prev_best[by_k1[window.front()]], from[q] = by_k1[window.front()];
    }
    group = group_end;
  }
}

/// Whether g2 passes (tolerance t) between end curvatures kl and kr, as the gate judges it.
bool g2_passes(double kl, double kr, double t) { return std::abs(kl - kr) <= t * std::max(std::abs(kl), std::abs(kr)); }

}  // namespace

/// Keyed by the unit's index, the box and the points its states depend on
/// (ChainCache); at most kChainCacheStates states in all (some 80 MB;
/// cleared when full). The bowl search's largest measured: 67 MB of the
/// whole process, URW Gothic b with every last-resort try at 4 M work.
struct ChainCache::Impl {
  std::map<std::vector<double>, std::vector<State>> states;
  std::size_t count = 0;
};
ChainCache::ChainCache() : impl(std::make_unique<Impl>()) {}
ChainCache::~ChainCache() = default;
constexpr std::size_t kChainCacheStates = std::size_t{1} << 20;

std::optional<bool> quadratic_monotone(Vec2 b0, Vec2 b1, Vec2 b2) {
  // Half-integers below 2^20: the differences are exact, and so are the products (below 2^44) and their sums.
  const auto half_integer = [](double v) { return std::abs(v) < 0x1p20 && 2 * v == std::trunc(2 * v); };
  for (const Vec2 p : {b0, b1, b2})
    if (!half_integer(p.x) || !half_integer(p.y)) return std::nullopt;
  const Vec2 a = b1 - b0, b = b2 - b1, c = b - a;
  if (det(a, b) == 0) return true;  // a line: constant (zero) curvature
  const double s0 = dot(a, c), s1 = dot(b, c);
  return !((s0 < 0 && s1 > 0) || (s0 > 0 && s1 < 0));
}

std::optional<ChainResult> chain_search(const import::Contour& c, const std::vector<Vec2>& src,
                                        const std::vector<Vec2>& at, const std::vector<int>& movable,
                                        const ReportOptions& o, double grid, double max_move, Work& work,
                                        const ChainBox& box, bool every, bool all_or_none,
                                        const std::vector<int>& moving_nodes) {
  const BSpline& source = c.spline;
  const int d = source.degree();
  if (o.require || o.gates.empty() || source.is_rational() || (d != 2 && d != 3) || !source.closed())
    return std::nullopt;
  double tol = -1;  // the strictest g2 tolerance (-1: no g2 gate)
  bool extrema = false;
  for (const Gate& g : o.gates) {
    if (g.kind == Gate::Kind::g2_at_smooth_nodes)
      tol = tol < 0 ? g.tolerance : std::min(tol, g.tolerance);
    else if (g.kind == Gate::Kind::extrema_at_nodes)
      extrema = true;
    else
      return std::nullopt;
  }
  const int m = source.unique_point_count(), n = source.segment_count();
  const std::vector<Vec2> here(at.begin(), at.begin() + m);
  const BSpline spline = source.with_points(here);
  const std::vector<Piece> pieces = pieces_of(spline);
  if (pieces.empty()) return std::nullopt;
  const std::vector<Unit> units = units_of(pieces, d, c.node);
  if (units.empty()) return std::nullopt;
  const int nu = static_cast<int>(units.size());
  SplineReport report;
  try {
    work.charge(n);
    report = gate_report(spline, o);
  } catch (const InputError&) {
    return std::nullopt;
  }
  // Which segments and joints fail, and which joints g2 judges (a link of a chain).
  std::vector<char> failing_segment(n, 0), failing_joint(n, 0), link(n, 0);
  for (const GateResult& g : report.gates)
    for (const GateViolation& v : g.violations) {
      if (v.info) continue;
      if (v.segment >= 0) failing_segment[v.segment % n] = 1;
      if (v.joint >= 0) failing_joint[v.joint % n] = 1;
    }
  if (tol >= 0)
    for (const JointReport& jr : report.joints)
      if (!jr.corner && std::isfinite(jr.joint.kappa_left) && std::isfinite(jr.joint.kappa_right))
        link[jr.joint.index % n] = 1;
  // The same per unit: a unit fails where one of its pieces or the joints
  // inside it (implied nodes) fails; a joint between units (at a node) links them.
  std::vector<char> failing_unit(nu, 0), failing_start(nu, 0), unit_link(nu, 0), straight_unit(nu, 1);
  const std::vector<char> straight = straight_segments(source);
  for (int u = 0; u < nu; ++u) {
    const std::vector<int>& segs = units[u].segments;
    unit_link[u] = link[segs.front()], failing_start[u] = failing_joint[segs.front()];
    for (std::size_t i = 0; i < segs.size(); ++i) {
      failing_unit[u] = failing_unit[u] || failing_segment[segs[i]] || (i > 0 && failing_joint[segs[i]]);
      straight_unit[u] = straight_unit[u] && straight[static_cast<std::size_t>(segs[i])];
    }
  }
  const auto unlinked = std::find(unit_link.begin(), unit_link.end(), 0);
  const auto any = [](const std::vector<char>& v) { return std::find(v.begin(), v.end(), 1) != v.end(); };
  if (!every && !any(failing_unit) && !any(failing_start)) return ChainResult{here, 0, 0, 0, {}, true, {}, {}};
  const double t = (tol >= 0 ? tol : 0) * (1 - 1e-6);
  const double limit = max_move > 0 ? max_move : std::numeric_limits<double>::infinity();
  ClassifyOptions classify;
  classify.max_depth = o.max_depth;
  classify.inflection = false;

  // Where the box moves nodes (ChainBox::node_reach): a node inside a chain
  // (g2 judges it), exactly smooth, movable with both its handles, between
  // two units of two or more free points, takes each grid translation
  // within node_reach cells each way (and max_move of the source), its
  // handles with it; node_offsets[k]: node k's translations, 0 first (only
  // 0 for every other point).
  const auto may_move = [&](int k) { return glyph_detail::may_move(c, movable, k); };
  std::vector<std::vector<Vec2>> node_offsets(static_cast<std::size_t>(m), std::vector<Vec2>{Vec2(0.0)});
  if (box.node_reach > 0 && nu >= 2 && std::find(unit_link.begin(), unit_link.end(), 0) != unit_link.end())
    for (int u = 0; u < nu; ++u) {
      const int before = (u + nu - 1) % nu, k = units[u].start;
      const bool listed = std::find(moving_nodes.begin(), moving_nodes.end(), k) != moving_nodes.end();
      if (!listed || !unit_link[u] || straight_unit[u] || straight_unit[before] || units[u].free.size() < 2 ||
          units[before].free.size() < 2 || !exactly_smooth(here, m, k) || !may_move(k) ||
          !may_move(units[u].free.front()) || !may_move(units[before].free.back()))
        continue;
      for (int i = -box.node_reach; i <= box.node_reach; ++i)
        for (int j = -box.node_reach; j <= box.node_reach; ++j) {
          const Vec2 v(static_cast<double>(i) * grid, static_cast<double>(j) * grid), p = here[k] + v;
          if ((i != 0 || j != 0) && std::sqrt(dot(p - src[k], p - src[k])) <= limit) node_offsets[k].push_back(v);
        }
    }
  // `base` with unit u's start (end: at_end) node moved by v, both its handles with it.
  const auto moved_node = [&](std::vector<Vec2>& base, int u, bool at_end, Vec2 v) {
    if (v.x == 0 && v.y == 0) return;
    const Unit& unit = units[u];
    const Unit& other = units[(u + (at_end ? 1 : nu - 1)) % nu];
    for (int k : {at_end ? unit.end : unit.start, at_end ? unit.free.back() : unit.free.front(),
                  at_end ? other.free.front() : other.free.back()})
      base[k] = base[k] + v;
  };

  // The positions a handle (point k next to node `node`) tries, the
  // contour at `base` (`here` with the unit's nodes moved). `lines`:
  // lines the handle must lie on (a line through `first`, along `second`):
  // a straight piece's, where the unit meets it smoothly at its other end
  // (g2 there needs the curve's end curvature exactly 0, so this handle on
  // the line), and a quadratic unit's one off-curve point's other node's
  // tangent, where that node is exactly smooth.
  using Line = std::pair<Vec2, Vec2>;
  auto options_of = [&](const std::vector<Vec2>& base, int k, int node, const std::vector<Line>& lines) {
    Options out;
    const auto on_lines = [&](Vec2 p) {
      for (const Line& l : lines)
        if (det(p - l.first, l.second) != 0) return false;
      return true;
    };
    auto add = [&](Vec2 p) {
      const Vec2 dp = p - src[k];
      if (std::sqrt(dot(dp, dp)) > limit || !on_lines(p)) return;
      out.at.push_back(p), out.cost.push_back(dot(dp, dp));
    };
    if (!may_move(k)) {
      if (on_lines(base[k])) out.at.push_back(base[k]), out.cost.push_back(dot(base[k] - src[k], base[k] - src[k]));
      return out;
    }
    if (node >= 0 && exactly_smooth(base, m, node)) {  // along its tangent, by the primitive grid vector on it
      const Vec2 a = base[k] - base[node];
      const std::optional<Vec2> step = grid_vector(a, grid);
      if (!step) {  // off the grid's lines through its node: held
        add(base[k]);
        return out;
      }
      out.line = true;
      for (int s = -box.slide_reach; s <= box.slide_reach; ++s) {
        const Vec2 p = base[k] + static_cast<double>(s) * *step;
        if (dot(p - base[node], a) > 0) add(p);  // never through its node
      }
      return out;
    }
    if (node < 0) {  // a run of three's middle point: half the box each way
      for (int i = -box.reach / 2; i <= box.reach / 2; ++i)
        for (int j = -box.reach / 2; j <= box.reach / 2; ++j)
          add(base[k] + Vec2(static_cast<double>(i) * grid, static_cast<double>(j) * grid));
      return out;
    }
    if (!lines.empty()) {  // the line's grid points past its join, out to beyond the handle's foot on it
      const Line& line = lines.front();
      const std::optional<Vec2> w = grid_vector(line.second, grid);
      if (!w) return out;
      const long j0 = std::lround(dot(base[k] - line.first, *w) / dot(*w, *w));
      out.line = true;
      for (long j = 1; j <= j0 + box.slide_reach; ++j) add(line.first + static_cast<double>(j) * *w);
      return out;
    }
    const int cells = box.reach / box.stride;  // each way, the handle's own cell among them whatever the stride
    const double pitch = box.stride * grid;
    for (int i = -cells; i <= cells; ++i)
      for (int j = -cells; j <= cells; ++j)
        add(base[k] + Vec2(static_cast<double>(i) * pitch, static_cast<double>(j) * pitch));
    return out;
  };
  // A piece's Bezier points at the positions `pos`.
  const auto bezier = [&](const Piece& piece, const std::vector<Vec2>& pos) {
    std::array<Vec2, 4> bz{};
    for (int r = 0; r <= d; ++r) {
      bz[r] = Vec2(0.0);
      for (const auto& [point, w] : piece.weights[r]) bz[r] = bz[r] + w * pos[point];
    }
    return bz;
  };
  // A corner that a candidate makes smooth (the header): at each unit's
  // start and end node that g2 does not judge at `here`, the neighbouring
  // unit's point next to it and its end curvature there, both at `here`.
  struct Corner {
    bool judged = false;  // a g2 gate, and the node a corner at `here` with a curvature on its other side
    Vec2 node{0.0}, other{0.0};
    double kappa = 0;
  };
  std::vector<std::array<Corner, 2>> corners(nu);  // [u][0]: at its start, [u][1]: at its end
  if (tol >= 0)
    for (int u = 0; u < nu; ++u) {
      const int before = (u + nu - 1) % nu, after = (u + 1) % nu;
      const Piece &last = pieces[static_cast<std::size_t>(units[before].segments.back())],
                  &first = pieces[static_cast<std::size_t>(units[after].segments.front())];
      const std::array<Vec2, 4> bl = bezier(last, here), bf = bezier(first, here);
      const double kl = end_curvatures({bl.data(), static_cast<std::size_t>(d + 1)})[1],
                   kr = end_curvatures({bf.data(), static_cast<std::size_t>(d + 1)})[0];
      if (!unit_link[u] && std::isfinite(kl))
        corners[u][0] = {true, here[units[u].start], here[units[before].free.back()], kl};
      if (!unit_link[after] && std::isfinite(kr))
        corners[u][1] = {true, here[units[u].end], here[units[after].free.front()], kr};
    }
  // Whether a candidate of unit u whose point next to its start (end: `at_end`) is at p, with end
  // curvature k there, passes g2 at that node where it makes the node smooth (its tangents within
  // the gate's angle, computed as the gate computes it), the neighbour as at `here`; true where it
  // leaves a corner.
  const auto corner_passes = [&](int u, bool at_end, Vec2 p, double k) {
    const Corner& cn = corners[static_cast<std::size_t>(u)][at_end ? 1 : 0];
    if (!cn.judged) return true;
    const Vec2 in = at_end ? cn.node - p : cn.node - cn.other, out = at_end ? cn.other - cn.node : p - cn.node;
    const double dt = det(in, out), dp = dot(in, out);
    const double angle = dt == 0 && dp > 0 ? 0.0 : std::atan2(std::abs(dt), dp) * (180.0 / std::numbers::pi);
    return angle > o.continuity.angle_deg || g2_passes(cn.kappa, k, t);
  };
  // Whether the extrema gate's check of a piece passes (Algorithm 1: certified monotone), when it is judged;
  // a quadratic piece's by its closed form (quadratic_monotone) where that decides.
  const auto monotone = [&](std::span<const Vec2> b) {
    if (!extrema) return true;
    if (b.size() == 3)
      if (const std::optional<bool> q = quadratic_monotone(b[0], b[1], b[2])) return *q;
    const Curvature cv = classify_bezier(b, classify).monotonicity.curvature;
    return cv == Curvature::increasing || cv == Curvature::decreasing || cv == Curvature::constant;
  };
  // The work, counted in ticks (kTicksPerUnit a unit): a piece judged costs piece_ticks, a candidate that
  // the end curvatures reject before any piece is judged kRejectTicks.
  long ticks = 0;
  const long piece_ticks = d == 3 ? kCubicPieceTicks : kQuadraticPieceTicks;
  const auto tick = [&](long count) {
    ticks += count;
    work.charge(ticks / kTicksPerUnit);
    ticks %= kTicksPerUnit;
  };

  // A run of three off-curve points (A, B, C) between nodes N0 and N1: the
  // pieces (N0, A, M1), (M1, B, M2), (M2, C, N1), M1 = (A + B) / 2 and M2 =
  // (B + C) / 2. For each position of B, the first piece depends on A alone
  // and the last on C alone, so each is judged once per position. Of the
  // pairs (A, C) of passing pieces (each a rejected candidate's work), only
  // those where the middle piece's curvature at one implied node (linear in
  // the other end point) lies in g2's window there have its end curvatures
  // computed, and only those where g2 passes at M1 and M2 have it judged (a
  // piece's work; kTicksPerUnit). Its passing states, B in `inner`; none
  // where the work ran out (`spent`).
  const auto run_of_three = [&](int u, const std::vector<Vec2>& base, const std::vector<Options>& options,
                                bool& spent) {
    std::vector<State> out;
    const Unit& unit = units[static_cast<std::size_t>(u)];
    const std::vector<int>& f = unit.free;
    const Piece &first = pieces[static_cast<std::size_t>(unit.segments[0])],
                &middle = pieces[static_cast<std::size_t>(unit.segments[1])],
                &last = pieces[static_cast<std::size_t>(unit.segments[2])];
    struct End {
      std::size_t at;
      double k_node, k_inner;  // its curvature at its node and at its implied node
    };
    // Whether the middle piece is (M1, B, M2) with M1 and M2 the midpoints (a TrueType run's, always): the
    // prefilter below assumes it.
    const auto half_of = [](const std::vector<std::pair<int, double>>& w, int x, int y) {
      return w.size() == 2 && w[0].second == 0.5 && w[1].second == 0.5 &&
             ((w[0].first == x && w[1].first == y) || (w[0].first == y && w[1].first == x));
    };
    const bool midpoints = d == 2 && half_of(middle.weights[0], f[0], f[1]) && middle.weights[1].size() == 1 &&
                           middle.weights[1][0].first == f[1] && half_of(middle.weights[2], f[1], f[2]);
    std::vector<Vec2> pos = base;
    // The passing positions of free point i (0: A, 2: C) for `piece` (its
    // first or last), B where pos has it; false where the work ran out.
    const auto ends = [&](std::size_t i, const Piece& piece, std::vector<End>& out_ends) {
      out_ends.clear();
      for (std::size_t q = 0; q < options[i].at.size(); ++q) {
        if (work.spent()) return false;
        tick(piece_ticks);
        pos[f[i]] = options[i].at[q];
        const std::array<Vec2, 4> bz = bezier(piece, pos);
        const std::span<const Vec2> b(bz.data(), static_cast<std::size_t>(d + 1));
        const std::array<double, 2> e = end_curvatures(b);
        if (!std::isfinite(e[0]) || !std::isfinite(e[1])) continue;
        if (!corner_passes(u, i != 0, options[i].at[q], i == 0 ? e[0] : e[1]) || !monotone(b)) continue;
        out_ends.push_back(i == 0 ? End{q, e[0], e[1]} : End{q, e[1], e[0]});
      }
      return true;
    };
    // Of the two end points, the inner loop's is one whose positions are in order along a line, where
    // either is (C first): there the prefilter's passing positions lie between two binary searches.
    const std::size_t outer = options[0].line && !options[2].line ? 2 : 0, inner = 2 - outer;
    const bool prefilter = midpoints && tol >= 0;
    std::vector<End> as, cs;
    for (std::size_t ib = 0; ib < options[1].at.size(); ++ib) {
      pos[f[1]] = options[1].at[ib];
      if (!ends(0, first, as) || !ends(2, last, cs)) return spent = true, std::vector<State>{};
      const std::vector<End>& outers = outer == 0 ? as : cs;
      const std::vector<End>& inners = outer == 0 ? cs : as;
      long pairs = 0;
      for (const End& o_end : outers) {
        pos[f[outer]] = options[outer].at[o_end.at];
        // g2 at the outer end's implied node first, on D = det(B - A, C - B) alone: the middle piece's
        // curvature there is c det((B - A) / 2, (C - B) / 2) / |h / 2|^3 = 2 c D / |h|^3, h = B - A at M1
        // (read from M2 backwards, the same with h = C - B), so the inner positions that pass have D in
        // passing_left of the outer piece's curvature there, scaled (widened by a margin far above the
        // doubles' rounding). D is linear in the inner point.
        const Vec2 h = pos[f[1]] - pos[f[outer]];
        const double scale = 2 * (d - 1.0) / d / (dot(h, h) * std::sqrt(dot(h, h)));
        std::array<double, 2> window = passing_left(o_end.k_inner, tol);
        const double margin = 1e-9 * std::max(std::abs(window[0]), std::abs(window[1])) + 1e-300;
        window = {(window[0] - margin) / scale, (window[1] + margin) / scale};
        const auto D = [&](const End& e) {
          const Vec2 p = options[inner].at[e.at], b = pos[f[1]];
          return outer == 0 ? det(b - pos[f[0]], p - b) : det(b - p, pos[f[2]] - b);
        };
        // Where the inner positions are in order along a line, D is linear along them, and those that pass
        // lie between two binary searches (a rejected candidate's work per step).
        auto from = inners.begin(), to = inners.end();
        if (prefilter && options[inner].line && !inners.empty()) {
          const bool rising = D(inners.front()) <= D(inners.back());
          from = std::partition_point(inners.begin(), inners.end(),
                                      [&](const End& e) { return rising ? D(e) < window[0] : D(e) > window[1]; });
          to = std::partition_point(from, inners.end(),
                                    [&](const End& e) { return rising ? D(e) <= window[1] : D(e) >= window[0]; });
          tick(kRejectTicks * (2 + 2 * static_cast<long>(std::bit_width(inners.size()))));
        }
        for (auto i_end = from; i_end != to; ++i_end) {
          if (++pairs % 64 == 0 && work.spent()) return spent = true, std::vector<State>{};
          tick(kRejectTicks);
          if (prefilter && (D(*i_end) < window[0] || D(*i_end) > window[1])) continue;
          pos[f[inner]] = options[inner].at[i_end->at];
          const End &a = outer == 0 ? o_end : *i_end, &cc = outer == 0 ? *i_end : o_end;
          const std::array<Vec2, 4> bz = bezier(middle, pos);
          const std::span<const Vec2> b(bz.data(), static_cast<std::size_t>(d + 1));
          const std::array<double, 2> e = end_curvatures(b);
          // At the implied nodes judged as the gate judges them (the header).
          if (tol >= 0 && (!g2_passes(a.k_inner, e[0], tol) || !g2_passes(e[1], cc.k_inner, tol))) continue;
          tick(piece_ticks);
          if (!monotone(b)) continue;
          out.push_back({pos[f[0]], pos[f[2]], a.k_node, cc.k_node,
                         options[0].cost[a.at] + options[1].cost[ib] + options[2].cost[cc.at], pos[f[1]]});
        }
      }
    }
    return out;
  };

  // A unit's passing states with the contour at `base` (`here` with its
  // nodes moved, each with both its handles); empty where none passes (or
  // the work ran out).
  auto states_with = [&](int u, const std::vector<Vec2>& base, bool& spent) {
    std::vector<State> out;
    const Unit& unit = units[u];
    const std::vector<int>& f = unit.free;
    const auto cost_here = [&] {
      double sum = 0;
      for (int k : f) sum += dot(base[k] - src[k], base[k] - src[k]);
      return sum;
    };
    if (straight_unit[u]) {  // a line: held, curvature 0
      out.push_back({base[f.front()], base[f.back()], 0, 0, cost_here()});
      return out;
    }
    // A smooth join with a straight piece at one end puts the far handle on that piece's line.
    const auto direction_of = [&](int v) {  // a straight unit's direction, first to last node
      return base[static_cast<std::size_t>(units[v].end)] - base[static_cast<std::size_t>(units[v].start)];
    };
    const int before = (u + nu - 1) % nu, after = (u + 1) % nu;
    // Each line through its join, pointed past the join into the curve.
    std::vector<Line> start_line, end_line;
    if (unit_link[u] && straight_unit[before]) start_line.push_back({base[unit.start], direction_of(before)});
    if (unit_link[after] && straight_unit[after]) end_line.push_back({base[unit.end], -1.0 * direction_of(after)});
    // Each free point's positions: a unit of two (a cubic's handles, or a
    // quadratic run's two off-curve points) like a cubic's H1 and H2; one
    // off-curve point between two nodes slides on a smooth one's tangent and
    // stays on the other's (and on both lines); of three or more, the two
    // next to the nodes move as a pair's do (so a line's join constrains an
    // inner point, which the end curvature then judges), the middle one of
    // three moves freely in the box (run_of_three), and the inner ones of
    // four or more are held.
    std::vector<Options> options;
    if (f.size() == 2) {
      options = {options_of(base, f[0], unit.start, end_line), options_of(base, f[1], unit.end, start_line)};
    } else if (f.size() == 1) {
      std::vector<Line> lines = start_line;
      lines.insert(lines.end(), end_line.begin(), end_line.end());
      const bool start_smooth = exactly_smooth(base, m, unit.start);
      const int other = start_smooth ? unit.end : unit.start;
      if (exactly_smooth(base, m, other)) lines.push_back({base[other], base[f[0]] - base[other]});
      options = {options_of(base, f[0], start_smooth ? unit.start : unit.end, lines)};
    } else {
      for (int k : f) options.push_back({{base[k]}, {dot(base[k] - src[k], base[k] - src[k])}});
      options.front() = options_of(base, f.front(), unit.start, {});
      options.back() = options_of(base, f.back(), unit.end, {});
      if (f.size() == 3) options[1] = options_of(base, f[1], -1, {});  // the middle point: a free box
    }
    for (const Options& op : options)
      if (op.at.empty()) return out;
    if (f.size() == 3) return run_of_three(u, base, options, spent);
    // Every combination, the last point's positions fastest. Each piece's
    // end curvatures first and g2 at the implied nodes inside the unit (a
    // few products; a combination it rejects costs kRejectTicks), then each
    // piece's extrema check (piece_ticks each).
    std::vector<std::size_t> pick(options.size(), 0);
    std::vector<Vec2> pos = base;
    std::vector<std::array<Vec2, 4>> bz(unit.segments.size());
    for (bool more = true; more;) {
      if (work.spent()) {
        spent = true;
        return std::vector<State>{};
      }
      double cost = 0;
      for (std::size_t i = 0; i < options.size(); ++i)
        pos[f[i]] = options[i].at[pick[i]], cost += options[i].cost[pick[i]];
      for (std::size_t i = options.size(); i-- > 0;) {  // the next combination
        if (++pick[i] < options[i].at.size()) break;
        pick[i] = 0;
        more = i > 0;
      }
      double k0 = 0, k1 = 0;
      bool passes = true;
      for (std::size_t p = 0; p < unit.segments.size() && passes; ++p) {
        bz[p] = bezier(pieces[static_cast<std::size_t>(unit.segments[p])], pos);
        const std::array<double, 2> e = end_curvatures({bz[p].data(), static_cast<std::size_t>(d + 1)});
        if (!std::isfinite(e[0]) || !std::isfinite(e[1])) passes = false;
        if (p == 0) k0 = e[0];
        // At an implied node inside the unit both sides' G is the same leg's, so A_l / A_r, a ratio of
        // small integers, meets the tolerance exactly as often as not: judged as the gate judges it.
        if (p > 0 && tol >= 0 && !g2_passes(k1, e[0], tol)) passes = false;
        k1 = e[1];
      }
      passes = passes && corner_passes(u, false, pos[f.front()], k0) && corner_passes(u, true, pos[f.back()], k1);
      if (!passes) {
        tick(kRejectTicks);
        continue;
      }
      for (std::size_t p = 0; p < unit.segments.size() && passes; ++p) {
        tick(piece_ticks);
        passes = monotone({bz[p].data(), static_cast<std::size_t>(d + 1)});
      }
      if (passes) out.push_back({pos[f.front()], pos[f.back()], k0, k1, cost});
      if (passes && box.probe_node >= 0 && !box.probe_ranges) break;  // a probe: the first passing one will do
    }
    return out;
  };

  // A unit's passing states: for each offset of its start node and of its
  // end node (node_offsets), those of states_with, each marked with its
  // offsets and its cost the start node's squared move added where that
  // node has offsets (each such node's move counted once along a chain: in
  // the unit it starts).
  auto states_of = [&](int u, bool& spent) {
    const Unit& unit = units[u];
    std::vector<double> key;
    if (box.cache && box.node_reach == 0 && box.probe_node < 0) {
      const int before = (u + nu - 1) % nu, after = (u + 1) % nu;
      key = {static_cast<double>(u), static_cast<double>(box.reach), static_cast<double>(box.slide_reach),
             static_cast<double>(box.stride)};
      const auto add = [&](int k) { key.insert(key.end(), {here[k].x, here[k].y}); };
      const auto add_unit = [&](int v) {
        add(units[v].start);
        for (const int k : units[v].free) add(k);
        add(units[v].end);
      };
      add_unit(u);
      if (straight_unit[before] || !unit_link[u]) add_unit(before);
      else add(units[before].free.back());
      if (straight_unit[after] || !unit_link[after]) add_unit(after);
      else add(units[after].free.front());
      const auto kept = box.cache->impl->states.find(key);
      if (kept != box.cache->impl->states.end()) return kept->second;
    }
    const auto keep = [&](std::vector<State> out) {
      if (key.empty() || spent) return out;
      ChainCache::Impl& kept = *box.cache->impl;
      if (out.size() > kChainCacheStates) return out;
      if (kept.count + out.size() > kChainCacheStates) kept.states.clear(), kept.count = 0;
      kept.count += out.size();
      kept.states.emplace(std::move(key), out);
      return out;
    };
    const std::vector<Vec2>& starts = node_offsets[unit.start];
    const std::vector<Vec2>& ends = node_offsets[unit.end];
    std::vector<State> out;
    for (std::size_t so = 0; so < starts.size(); ++so)
      for (std::size_t eo = 0; eo < ends.size(); ++eo) {
        std::vector<Vec2> base = here;
        moved_node(base, u, false, starts[so]);
        moved_node(base, u, true, ends[eo]);
        const Vec2 node_move = base[unit.start] - src[unit.start];
        const double node_cost = starts.size() > 1 ? dot(node_move, node_move) : 0.0;
        for (State st : states_with(u, base, spent)) {
          st.s_off = static_cast<int>(so), st.e_off = static_cast<int>(eo), st.cost += node_cost;
          out.push_back(st);
        }
        if (spent) return std::vector<State>{};
      }
    return keep(std::move(out));
  };

  // The chains, each a run of units from a joint g2 does not judge (or,
  // where g2 judges every joint, one chain closing on itself at unit 0's
  // start); those that fail (every one with `every`).
  const bool cycle = unlinked == unit_link.end();
  if (cycle && !every) return std::nullopt;  // a contour smooth all round: only in the settling (header)
  std::vector<std::vector<int>> chains;
  for (int start = cycle ? 0 : static_cast<int>(unlinked - unit_link.begin()), done = 0; done < nu;) {
    std::vector<int> chain{start};
    while (done + static_cast<int>(chain.size()) < nu && unit_link[(chain.back() + 1) % nu])
      chain.push_back((chain.back() + 1) % nu);
    done += static_cast<int>(chain.size());
    start = (chain.back() + 1) % nu;
    bool fails = every;
    for (std::size_t i = 0; i < chain.size(); ++i)
      fails = fails || failing_unit[chain[i]] || ((i > 0 || cycle) && failing_start[chain[i]]);
    if (fails) chains.push_back(std::move(chain));
  }
  // The end curvatures' ranges of unit u's passing states `st` (not empty).
  const auto range_of = [&](int u, const std::vector<State>& st) {
    CurvatureRange out{units[u].start, units[u].end, unit_link[u] != 0, st.front().k0, st.front().k0,
                       st.front().k1, st.front().k1};
    for (const State& x : st) {
      out.k0_lo = std::min(out.k0_lo, x.k0), out.k0_hi = std::max(out.k0_hi, x.k0);
      out.k1_lo = std::min(out.k1_lo, x.k1), out.k1_hi = std::max(out.k1_hi, x.k1);
    }
    return out;
  };
  // A probe (ChainBox::probe_node): the units at that node, each up to its first passing position (every
  // one with probe_ranges).
  if (box.probe_node >= 0) {
    ChainResult probe{here, static_cast<int>(chains.size()), 0, 0, {}, true, {}, {}};
    for (int u = 0; u < nu; ++u) {
      if (units[u].start != box.probe_node && units[u].end != box.probe_node) continue;
      bool spent = false;
      const std::vector<State> st = states_of(u, spent);
      if (spent) break;
      if (st.empty())
        probe.stuck.insert(probe.stuck.end(), {units[u].start, units[u].end});
      else if (box.probe_ranges)
        probe.ranges.push_back(range_of(u, st));
    }
    return probe;
  }
  // Asked to move nodes where none may: the search would be the one with every node held.
  const bool moves_a_node =
      std::any_of(node_offsets.begin(), node_offsets.end(), [](const auto& v) { return v.size() > 1; });
  if (box.node_reach > 0 && !moves_a_node)
    return ChainResult{here, static_cast<int>(chains.size()), 0, 0, {}, false, {}, {}};
  // Each unit's states, once; the failing units first, since a chain with
  // a unit that no position in the box makes monotone (its nodes would
  // have to move) has no answer, and that is found cheapest so.
  // With all_or_none, one hopeless chain ends the search: the failing units
  // of every chain, those with fewer free points (cheaper) first.
  std::vector<std::optional<std::vector<State>>> states(nu);
  std::vector<int> stuck;  // the nodes of each unit found with no passing position
  std::vector<char> hopeless(chains.size(), 0);
  bool spent = false;
  std::vector<std::pair<std::size_t, int>> failing;  // (chain, unit)
  for (std::size_t h = 0; h < chains.size(); ++h)
    for (int u : chains[h])
      if (failing_unit[u]) failing.push_back({h, u});
  if (all_or_none)
    std::stable_sort(failing.begin(), failing.end(), [&](const auto& x, const auto& y) {
      return units[x.second].free.size() < units[y.second].free.size();
    });
  for (const auto& [h, u] : failing) {
    if (spent) break;
    if (hopeless[h] && !box.every_stuck) continue;
    states[u] = states_of(u, spent);
    const bool none = states[u]->empty();
    hopeless[h] = hopeless[h] || none;
    if (none && !spent) stuck.insert(stuck.end(), {units[u].start, units[u].end});
    if (hopeless[h] && all_or_none)
      return ChainResult{here, static_cast<int>(chains.size()), 0, 0, stuck, true, {}, {}};
  }
  for (std::size_t h = 0; h < chains.size() && !spent; ++h)
    for (int u : chains[h])
      if (!states[u] && !hopeless[h]) states[u] = states_of(u, spent);
  ChainResult result{here, static_cast<int>(chains.size()), 0, 0, stuck, true, {}, {}};
  if (spent) return result;
  for (int u = 0; u < nu; ++u)
    if (states[u] && !states[u]->empty()) result.ranges.push_back(range_of(u, *states[u]));
  // The least-cost path through a chain's layers from the first layer's
  // states `first` (their best: their own cost); the last layer's best and
  // every layer's `from`.
  const auto path = [&](const std::vector<int>& chain, const std::vector<State>& first,
                        std::vector<std::vector<int>>& from) {
    std::vector<double> best(first.size());
    for (std::size_t q = 0; q < first.size(); ++q) best[q] = first[q].cost;
    from.assign(chain.size(), {});
    const std::vector<State>* prev = &first;
    for (std::size_t i = 1; i < chain.size(); ++i) {
      const std::vector<State>& layer = *states[chain[i]];
      std::vector<double> next;
      advance(*prev, best, layer, t, next, from[i]);
      best = std::move(next), prev = &layer;
    }
    return best;
  };
  // The nodes of chain h's units, where it is left unanswered.
  const auto unanswered = [&](std::size_t h) {
    for (const int u : chains[h]) result.unanswered.insert(result.unanswered.end(), {units[u].start, units[u].end});
  };
  for (std::size_t h = 0; h < chains.size(); ++h) {
    if (hopeless[h]) {
      unanswered(h);
      continue;
    }
    // A cycle is searched as a path per state of its first unit, closed at that unit's start, and any
    // unit's start closes it as well (the least cost is the same): the unit with the fewest states first.
    std::vector<int> chain = chains[h];
    if (cycle)
      std::rotate(chain.begin(), std::min_element(chain.begin(), chain.end(), [&](int x, int y) {
                    return states[x]->size() < states[y]->size();
                  }), chain.end());
    const std::vector<State>& first = *states[chain.front()];
    std::vector<std::vector<int>> from;
    std::vector<State> start = first;  // a cycle: the one state of its first unit that is best
    double least = std::numeric_limits<double>::infinity();
    int end = -1;
    if (!cycle) {
      const std::vector<double> best = path(chain, first, from);
      for (std::size_t q = 0; q < best.size(); ++q)
        if (best[q] < least) least = best[q], end = static_cast<int>(q);
    } else {
      // Each state of the first unit in turn (cheapest first, until its
      // cost alone and the other layers' least reach the best found), the
      // path from it, closed by g2 at joint 0 between the last layer and it.
      double rest = 0;
      for (std::size_t i = 1; i < chain.size(); ++i) {
        double low = std::numeric_limits<double>::infinity();
        for (const State& st : *states[chain[i]]) low = std::min(low, st.cost);
        rest += low;
      }
      std::vector<int> order(first.size());
      std::iota(order.begin(), order.end(), 0);
      std::sort(order.begin(), order.end(), [&](int x, int y) { return first[x].cost < first[y].cost; });
      for (int q0 : order) {
        if (!(first[q0].cost + rest < least)) break;
        if (work.spent()) return result;
        work.charge(static_cast<long>(chain.size()));
        std::vector<std::vector<int>> f;
        const std::vector<double> best = path(chain, {first[q0]}, f);
        const std::vector<State>& last = *states[chain.back()];
        int closing = -1;
        for (std::size_t q = 0; q < best.size(); ++q) {
          const State& end_state = chain.size() == 1 ? first[q0] : last[q];  // one unit closes on itself
          if (best[q] < least && end_state.e_off == first[q0].s_off && g2_passes(end_state.k1, first[q0].k0, t))
            least = best[q], closing = static_cast<int>(q);
        }
        if (closing >= 0) end = closing, start = {first[q0]}, from = std::move(f);
      }
    }
    if (end < 0) {
      unanswered(h);
      continue;
    }
    int q = end;
    for (int i = static_cast<int>(chain.size()) - 1; i >= 0; --i) {
      const State& st = i == 0 ? start[static_cast<std::size_t>(q)] : (*states[chain[i]])[q];
      const Unit& unit = units[static_cast<std::size_t>(chain[i])];
      result.points[unit.free.front()] = st.h1, result.points[unit.free.back()] = st.h2;
      if (unit.free.size() == 3) result.points[unit.free[1]] = st.inner;
      result.points[unit.start] = here[unit.start] + node_offsets[unit.start][st.s_off];
      result.points[unit.end] = here[unit.end] + node_offsets[unit.end][st.e_off];
      q = i > 0 ? from[i][q] : q;
    }
    result.cost += least;
    ++result.solved;
  }
  return result;
}

std::optional<std::vector<Vec2>> growing_chain_search(const import::Contour& c, const std::vector<Vec2>& src,
                                                      const std::vector<int>& movable, const ReportOptions& o,
                                                      double grid, double max_move, Work& work) {
  std::vector<Vec2> at = src;
  std::vector<int> stuck;  // the nodes of the units found with no passing position
  const auto more_stuck = [&](const std::vector<int>& nodes) {
    bool grew = false;
    for (const int k : nodes)
      if (std::find(stuck.begin(), stuck.end(), k) == stuck.end()) stuck.push_back(k), grew = true;
    return grew;
  };
  for (const bool nodes : {false, true}) {
    if (nodes && stuck.empty()) break;
    const std::span<const int> reaches = nodes ? std::span<const int>(kGrowingNodeRoundReach) : kGrowingReach;
    for (const int reach : reaches) {
      const ChainBox box{reach, kGrowingSlidePerCell * reach, nodes ? kChainNodeReach : 0};
      for (bool again = true; again;) {
        const std::optional<ChainResult> r =
            chain_search(c, src, at, movable, o, grid, max_move, work, box, false, true, stuck);
        if (!r || !r->searched) return std::nullopt;  // not searched: none of the stuck units' nodes may move
        at = r->points;
        if (r->solved == r->chains) return at;
        if (work.spent()) return std::nullopt;
        again = more_stuck(r->stuck) && nodes;  // with nodes moving: again with the new stuck units' nodes too
      }
    }
  }
  return std::nullopt;
}

}  // namespace cmr::report::glyph_detail
