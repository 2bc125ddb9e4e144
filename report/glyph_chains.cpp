// The glyph fix's chain search (glyph_chains.hpp: the derivation).
#include "report/glyph_chains.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <numeric>
#include <optional>
#include <utility>

#include "bezierize/classify.hpp"
#include "bezierize/extract.hpp"
#include "design/fix.hpp"
#include "report/batch.hpp"
#include "spline/errors.hpp"

namespace cmr::report::glyph_detail {
namespace {

/// A candidate of one segment: its two handles' positions (or none: a line,
/// held), end curvatures and cost.
struct State {
  Vec2 h1{0.0}, h2{0.0};
  double k0 = 0, k1 = 0, cost = 0;
};

/// The positions one handle tries, each with its squared move from the source.
struct Options {
  std::vector<Vec2> at;
  std::vector<double> cost;
};

/// End curvatures of the cubic (b0, b1, b2, b3), signed (NaN at a zero handle).
std::array<double, 2> end_curvatures(const std::array<Vec2, 4>& b) {
  auto kappa = [](Vec2 turn_from, Vec2 turn_to, Vec2 handle) {
    const double l = std::sqrt(dot(handle, handle));
    return l > 0 ? 2.0 / 3.0 * det(turn_from, turn_to) / (l * l * l) : std::numeric_limits<double>::quiet_NaN();
  };
  return {kappa(b[1] - b[0], b[2] - b[1], b[1] - b[0]), kappa(b[2] - b[1], b[3] - b[2], b[3] - b[2])};
}

/// The interval of left curvatures kl that pass g2 (tolerance t) against kr.
std::array<double, 2> passing_left(double kr, double t) {
  if (kr > 0) return {kr * (1 - t), kr / (1 - t)};
  if (kr < 0) return {kr / (1 - t), kr * (1 - t)};
  return {0, 0};
}

/// One step of the shortest path: best[q], the least cost of reaching state
/// q of `layer` from a state p of `prev` (whose least cost is prev_best[p])
/// with g2 passing between p's k1 and q's k0 (tolerance t), plus q's own
/// cost; from[q] that p (-1, best infinite: none). Both sorted by the
/// curvatures there, the passing p of each q form a window whose ends rise
/// with q's k0: a sliding-window minimum.
void advance(const std::vector<State>& prev, const std::vector<double>& prev_best, const std::vector<State>& layer,
             double t, std::vector<double>& best, std::vector<int>& from) {
  best.assign(layer.size(), std::numeric_limits<double>::infinity());
  from.assign(layer.size(), -1);
  std::vector<int> by_k1(prev.size()), by_k0(layer.size());
  std::iota(by_k1.begin(), by_k1.end(), 0);
  std::iota(by_k0.begin(), by_k0.end(), 0);
  std::sort(by_k1.begin(), by_k1.end(), [&](int x, int y) { return prev[x].k1 < prev[y].k1; });
  std::sort(by_k0.begin(), by_k0.end(), [&](int x, int y) { return layer[x].k0 < layer[y].k0; });
  std::deque<int> window;  // positions in by_k1 whose best rises from the front
  std::size_t in = 0, out_of = 0;
  for (int q : by_k0) {
    const std::array<double, 2> range = passing_left(layer[q].k0, t);
    while (in < by_k1.size() && prev[by_k1[in]].k1 <= range[1]) {
      const double v = prev_best[by_k1[in]];
      while (!window.empty() && prev_best[by_k1[window.back()]] >= v) window.pop_back();
      window.push_back(static_cast<int>(in++));
    }
    while (out_of < in && prev[by_k1[out_of]].k1 < range[0]) ++out_of;
    while (!window.empty() && window.front() < static_cast<int>(out_of)) window.pop_front();
    if (window.empty() || !std::isfinite(prev_best[by_k1[window.front()]])) continue;
    best[q] = layer[q].cost + prev_best[by_k1[window.front()]], from[q] = by_k1[window.front()];
  }
}

/// Whether g2 passes (tolerance t) between end curvatures kl and kr, as the gate judges it.
bool g2_passes(double kl, double kr, double t) { return std::abs(kl - kr) <= t * std::max(std::abs(kl), std::abs(kr)); }

}  // namespace

std::optional<ChainResult> chain_search(const import::Contour& c, const std::vector<Vec2>& src,
                                        const std::vector<Vec2>& at, const std::vector<int>& movable,
                                        const ReportOptions& o, double grid, double max_move, Work& work,
                                        const ChainBox& box, bool every) {
  const BSpline& source = c.spline;
  if (o.require || o.gates.empty() || source.is_rational() || source.degree() != 3 || !source.closed())
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
  const auto unlinked = std::find(link.begin(), link.end(), 0);
  const auto any = [](const std::vector<char>& v) { return std::find(v.begin(), v.end(), 1) != v.end(); };
  if (!every && !any(failing_segment) && !any(failing_joint)) return ChainResult{here, 0, 0, 0};
  const std::vector<char> straight = straight_segments(source);
  const double t = (tol >= 0 ? tol : 0) * (1 - 1e-6);
  const double limit = max_move > 0 ? max_move : std::numeric_limits<double>::infinity();
  ClassifyOptions classify;
  classify.max_depth = o.max_depth;
  classify.inflection = false;

  // The positions a handle (point k next to node `node`) tries. `line`: a
  // line the handle must lie on (its join with the curve, its direction
  // past the join), where the segment meets a straight piece smoothly at its
  // other end: g2 there needs the curve's end curvature exactly 0, so this
  // handle on the line.
  using Line = std::optional<std::pair<Vec2, Vec2>>;
  auto options_of = [&](int k, int node, const Line& line) {
    Options out;
    const auto on_line = [&](Vec2 p) { return !line || det(p - line->first, line->second) == 0; };
    auto add = [&](Vec2 p) {
      const Vec2 d = p - src[k];
      if (std::sqrt(dot(d, d)) > limit || !on_line(p)) return;
      out.at.push_back(p), out.cost.push_back(dot(d, d));
    };
    if (c.font_point[k] < 0 || std::find(movable.begin(), movable.end(), k) == movable.end()) {
      if (on_line(here[k])) out.at.push_back(here[k]), out.cost.push_back(dot(here[k] - src[k], here[k] - src[k]));
      return out;
    }
    if (exactly_smooth(here, m, node)) {  // along its tangent, by the primitive grid vector on it
      const Vec2 a = here[k] - here[node];
      const std::optional<Vec2> step = grid_vector(a, grid);
      if (!step) {  // off the grid's lines through its node: held
        add(here[k]);
        return out;
      }
      for (int s = -box.slide_reach; s <= box.slide_reach; ++s) {
        const Vec2 p = here[k] + static_cast<double>(s) * *step;
        if (dot(p - here[node], a) > 0) add(p);  // never through its node
      }
      return out;
    }
    if (line) {  // the line's grid points past its join, out to beyond the handle's foot on it
      const std::optional<Vec2> w = grid_vector(line->second, grid);
      if (!w) return out;
      const long j0 = std::lround(dot(here[k] - line->first, *w) / dot(*w, *w));
      for (long j = 1; j <= j0 + box.slide_reach; ++j) add(line->first + static_cast<double>(j) * *w);
      return out;
    }
    for (int i = -box.reach; i <= box.reach; ++i)
      for (int j = -box.reach; j <= box.reach; ++j)
        add(here[k] + Vec2(static_cast<double>(i) * grid, static_cast<double>(j) * grid));
    return out;
  };

  // A segment's passing states; empty where none passes (or the work ran out).
  auto states_of = [&](int s, bool& spent) {
    std::vector<State> out;
    const std::vector<int> pts = segment_points(spline, spline.segments()[static_cast<std::size_t>(s)]);
    std::array<int, 4> k{};
    for (int i = 0; i < 4; ++i) k[i] = pts[static_cast<std::size_t>(i)] % m;
    if (straight[static_cast<std::size_t>(s)]) {  // a line: held, curvature 0
      out.push_back({here[k[1]], here[k[2]], 0, 0, 0});
      return out;
    }
    // A smooth join with a straight piece at one end puts the far handle on that piece's line.
    const auto direction_of = [&](int segment) {  // a straight segment's direction, first to last point
      const std::vector<int> q = segment_points(spline, spline.segments()[static_cast<std::size_t>(segment)]);
      return here[static_cast<std::size_t>(q.back() % m)] - here[static_cast<std::size_t>(q.front() % m)];
    };
    const int before = (s + n - 1) % n, after = (s + 1) % n;
    // Each line through its join, pointed past the join into the curve.
    const Line start_line = link[s] && straight[static_cast<std::size_t>(before)]
                                ? Line(std::pair(here[k[0]], direction_of(before)))
                                : Line();
    const Line end_line = link[after] && straight[static_cast<std::size_t>(after)]
                              ? Line(std::pair(here[k[3]], -1.0 * direction_of(after)))
                              : Line();
    const Options a = options_of(k[1], k[0], end_line), b = options_of(k[2], k[3], start_line);
    for (std::size_t i = 0; i < a.at.size(); ++i)
      for (std::size_t j = 0; j < b.at.size(); ++j) {
        if (work.spent()) {
          spent = true;
          return std::vector<State>{};
        }
        work.charge();
        const std::array<Vec2, 4> bz{here[k[0]], a.at[i], b.at[j], here[k[3]]};
        if (extrema) {
          const Curvature cv = classify_bezier(bz, classify).monotonicity.curvature;
          if (cv != Curvature::increasing && cv != Curvature::decreasing && cv != Curvature::constant) continue;
        }
        const std::array<double, 2> e = end_curvatures(bz);
        if (!std::isfinite(e[0]) || !std::isfinite(e[1])) continue;
        out.push_back({a.at[i], b.at[j], e[0], e[1], a.cost[i] + b.cost[j]});
      }
    return out;
  };

  // The chains, each a run of segments from a joint g2 does not judge (or,
  // where g2 judges every joint, one chain closing on itself at joint 0);
  // those that fail (every one with `every`).
  const bool cycle = unlinked == link.end();
  if (cycle && !every) return std::nullopt;  // a contour smooth all round: only in the settling (header)
  std::vector<std::vector<int>> chains;
  for (int start = cycle ? 0 : static_cast<int>(unlinked - link.begin()), done = 0; done < n;) {
    std::vector<int> chain{start};
    while (done + static_cast<int>(chain.size()) < n && link[(chain.back() + 1) % n])
      chain.push_back((chain.back() + 1) % n);
    done += static_cast<int>(chain.size());
    start = (chain.back() + 1) % n;
    bool fails = every;
    for (std::size_t i = 0; i < chain.size(); ++i)
      fails = fails || failing_segment[chain[i]] || ((i > 0 || cycle) && failing_joint[chain[i]]);
    if (fails) chains.push_back(std::move(chain));
  }
  // Each segment's states, once; the failing segments first, since a chain
  // with a segment that no handle position in the box makes monotone (its
  // nodes would have to move) has no answer, and that is found cheapest so.
  std::vector<std::optional<std::vector<State>>> states(n);
  std::vector<char> hopeless(chains.size(), 0);
  bool spent = false;
  for (std::size_t h = 0; h < chains.size() && !spent; ++h)
    for (int s : chains[h])
      if (failing_segment[s] && !hopeless[h]) {
        states[s] = states_of(s, spent);
        hopeless[h] = states[s]->empty();
      }
  for (std::size_t h = 0; h < chains.size() && !spent; ++h)
    for (int s : chains[h])
      if (!states[s] && !hopeless[h]) states[s] = states_of(s, spent);
  ChainResult result{here, static_cast<int>(chains.size()), 0, 0};
  if (spent) return result;
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
  for (std::size_t h = 0; h < chains.size(); ++h) {
    const std::vector<int>& chain = chains[h];
    if (hopeless[h]) continue;
    const std::vector<State>& first = *states[chain.front()];
    std::vector<std::vector<int>> from;
    std::vector<State> start = first;  // a cycle: the one state of its first segment that is best
    double least = std::numeric_limits<double>::infinity();
    int end = -1;
    if (!cycle) {
      const std::vector<double> best = path(chain, first, from);
      for (std::size_t q = 0; q < best.size(); ++q)
        if (best[q] < least) least = best[q], end = static_cast<int>(q);
    } else {
      // Each state of the first segment in turn (cheapest first, until its
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
          const State& end_state = chain.size() == 1 ? first[q0] : last[q];  // one segment closes on itself
          if (best[q] < least && g2_passes(end_state.k1, first[q0].k0, t))
            least = best[q], closing = static_cast<int>(q);
        }
        if (closing >= 0) end = closing, start = {first[q0]}, from = std::move(f);
      }
    }
    if (end < 0) continue;
    int q = end;
    for (int i = static_cast<int>(chain.size()) - 1; i >= 0; --i) {
      const State& st = i == 0 ? start[static_cast<std::size_t>(q)] : (*states[chain[i]])[q];
      const std::vector<int> pts = segment_points(spline, spline.segments()[static_cast<std::size_t>(chain[i])]);
      result.points[pts[1] % m] = st.h1, result.points[pts[2] % m] = st.h2;
      q = i > 0 ? from[i][q] : q;
    }
    result.cost += least;
    ++result.solved;
  }
  return result;
}

}  // namespace cmr::report::glyph_detail
