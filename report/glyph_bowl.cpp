// The glyph fix's bowl search (glyph_bowl.hpp).
#include "report/glyph_bowl.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <utility>
#include <vector>

namespace cmr::report::glyph_detail {

std::optional<std::vector<Vec2>> bowl_search(const import::Contour& c, const std::vector<Vec2>& src,
                                             const std::vector<Vec2>& start, const std::vector<int>& movable,
                                             const ReportOptions& o, double grid, double max_move, Work& work) {
  if (c.spline.degree() != 3 || !(grid > 0)) return std::nullopt;
  const int m = c.spline.unique_point_count();
  const double limit = max_move > 0 ? max_move : std::numeric_limits<double>::infinity();
  const auto at_index = [&](int k) { return ((k % m) + m) % m; };
  // A node that moves with both its handles.
  const auto rigid = [&](int k) {
    const int before = at_index(k - 1), after = at_index(k + 1);
    return c.node[k] && !c.node[before] && !c.node[after] && may_move(c, movable, k) &&
           may_move(c, movable, before) && may_move(c, movable, after);
  };
  // The chain search from `at`, every stuck unit found; a contour smooth all round (no answer without
  // `every`) as one chain, which the first search finds out.
  bool every = false;
  const auto search = [&](const std::vector<Vec2>& at, const ChainBox& box) {
    std::optional<ChainResult> r = chain_search(c, src, at, movable, o, grid, max_move, work, box, every);
    if (!r && !every && !work.spent())
      every = true, r = chain_search(c, src, at, movable, o, grid, max_move, work, box, true);
    return r;
  };
  ChainBox full, probe{kChainReach, kBowlProbeSlide};
  full.every_stuck = probe.every_stuck = true;
  // Whether unit (n0, n1) is among r's stuck units.
  const auto stuck_in = [](const ChainResult& r, int n0, int n1) {
    for (std::size_t i = 0; i + 1 < r.stuck.size(); i += 2)
      if (r.stuck[i] == n0 && r.stuck[i + 1] == n1) return true;
    return false;
  };
  // The end of cubic unit (n0, n0 + 1, n1 - 1, n1) at which `p` makes it sharper, as a quarter arc says:
  // with d = n1 - n0 = a t0 + b t1 (t0, t1 its end tangents), the end whose tangent is square to the
  // longer extent, |a| |t0| or |b| |t1| (1: n1, -1: n0, 0: neither, or no such unit).
  const auto sharp_end = [&](const std::vector<Vec2>& p, int n0, int n1) {
    if (at_index(n0 + 3) != n1 || c.node[at_index(n0 + 1)] || c.node[at_index(n1 - 1)]) return 0;
    const Vec2 t0 = p[at_index(n0 + 1)] - p[n0], t1 = p[n1] - p[at_index(n1 - 1)], d = p[n1] - p[n0];
    const double cross = det(t0, t1);
    if (cross == 0) return 0;
    const double a = std::abs(det(d, t1) / cross) * std::sqrt(dot(t0, t0));
    const double b = std::abs(det(t0, d) / cross) * std::sqrt(dot(t1, t1));
    return a > b ? 1 : a < b ? -1 : 0;
  };
  // Whether `p` leaves unit (n0, n1) sharper at a smooth node where its neighbour there (a unit not
  // stuck in `r`) is flatter, or the other way round: g2 there would then join a sharp end to a flat one.
  const auto clashes = [&](const std::vector<Vec2>& p, int n0, int n1, const ChainResult& r) {
    const int own = sharp_end(p, n0, n1);
    const int before = at_index(n0 - 3), after = at_index(n1 + 3);
    const auto clash = [&](int node, int u0, int u1, bool sharp_here) {
      if (!exactly_smooth(p, m, node) || stuck_in(r, u0, u1)) return false;
      const int other = sharp_end(p, u0, u1);
      return other != 0 && sharp_here != (other == (u1 == node ? 1 : -1));
    };
    return own != 0 && (clash(n0, before, n0, own == -1) || clash(n1, n1, after, own == 1));
  };
  std::vector<Vec2> at = start;
  // The stuck units in the probe box at `at` (their nodes, pairs): the count a move must lower.
  std::optional<std::vector<int>> before;
  for (int moves = 0;; ++moves) {
    const std::optional<ChainResult> r = search(at, full);
    if (!r || work.spent()) return std::nullopt;
    if (r->solved == r->chains) return r->points;
    bool moved = false;
    if (!r->stuck.empty() && moves < kBowlNodeMoves) {
      if (!before) {  // after a move, what that move's probe left
        const std::optional<ChainResult> b = search(at, probe);
        if (!b || work.spent()) return std::nullopt;
        before = b->stuck;
      }
      // For the first stuck unit (n0, n1) where one does, the first move, nearest first, that unsticks it
      // and lowers the count of stuck units (a probe of the two units at the moved node each: the others
      // keep their points, so whether they are stuck): first only among those that leave no sharp end
      // against a flat one, then among all. Each try says whether the moves end there: the contour passes
      // every gate there (`answer`), the work ran out, or the move is taken.
      std::optional<std::vector<Vec2>> answer;
      std::vector<int> next;  // the stuck units at the move taken
      const auto try_move = [&](int n0, int n1, bool matching, int step, int node, int handle, double sign) {
        const std::optional<Vec2> tangent = grid_vector(at[handle] - at[node], grid);
        if (!tangent) return false;
        const Vec2 v = sign * static_cast<double>(step) * Vec2(-tangent->y, tangent->x), p = at[node] + v;
        if (std::sqrt(dot(v, v)) > kBowlNormalReach * grid || std::sqrt(dot(p - src[node], p - src[node])) > limit)
          return false;
        std::vector<Vec2> trial = at;
        for (const int k : {at_index(node - 1), node, at_index(node + 1)}) trial[k] = trial[k] + v;
        if (matching && clashes(trial, n0, n1, *r)) return false;
        ChainBox at_node = probe;
        at_node.probe_node = node;
        const std::optional<ChainResult> t = search(trial, at_node);
        if (!t || work.spent()) return true;
        if (t->solved == t->chains) return answer = t->points, true;
        if (stuck_in(*t, n0, n1)) return false;
        std::vector<int> after = t->stuck;
        for (std::size_t i = 0; i + 1 < before->size(); i += 2)
          if (const int u0 = (*before)[i], u1 = (*before)[i + 1]; u0 != node && u1 != node)
            after.insert(after.end(), {u0, u1});
        if (after.size() >= before->size()) return false;
        at = std::move(trial), next = std::move(after);
        return moved = true;
      };
      bool done = false;
      for (std::size_t i = 0; i + 1 < r->stuck.size() && !done; i += 2) {
        const int n0 = r->stuck[i], n1 = r->stuck[i + 1];
        // The unit's handle next to each of its nodes (the unit runs n0, n0 + 1, ..., n1 - 1, n1).
        const std::array<std::pair<int, int>, 2> ends{{{n0, at_index(n0 + 1)}, {n1, at_index(n1 - 1)}}};
        for (const bool matching : {true, false})
          for (int step = 1; step <= kBowlNormalReach && !done; ++step)
            for (const auto& [node, handle] : ends)
              for (const double sign : {1.0, -1.0})
                if (!done && rigid(node)) done = try_move(n0, n1, matching, step, node, handle, sign);
      }
      if (answer) return answer;
      if (moved) before = std::move(next);
    }
    if (moved) continue;
    // No unit stuck and a chain still unanswered (g2 fails between units that each have passing
    // positions), or no move unsticks a unit: wider boxes for the free handles. Where a chain ends at a
    // corner, its end units' free handles may need to go farther (URW Gothic a's bowl, its two quarters
    // made wider than tall: the bottom one flat at p11, the unit from there to the corner sharp there
    // unless its free handle moves some 20 units); a unit between nodes not exactly smooth, whose handles
    // are free, may need them farther than the box (URW Gothic s's spine, p38 to p41: handles of 31 and
    // 83 units).
    for (const int reach : kBowlWideReach) {
      const std::optional<ChainResult> w = search(at, ChainBox{reach, kChainSlideReach});
      if (!w || work.spent()) return std::nullopt;
      if (w->solved == w->chains) return w->points;
    }
    return std::nullopt;
  }
}

}  // namespace cmr::report::glyph_detail
