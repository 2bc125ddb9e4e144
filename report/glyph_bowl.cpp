// The glyph fix's bowl search (glyph_bowl.hpp).
#include "report/glyph_bowl.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

namespace cmr::report::glyph_detail {

std::optional<std::vector<Vec2>> bowl_search(const import::Contour& c, const std::vector<Vec2>& src,
                                             const std::vector<Vec2>& start, const std::vector<int>& movable,
                                             const ReportOptions& o, double grid, double max_move, Work& work,
                                             ChainCache& kept) {
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
  full.cache = &kept;
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
  // `at` with `node` and its two handles moved `step` grid steps along its normal (the primitive grid vector
  // square to the way to `handle`), `sign` says which way; nullopt where that way is off the grid, or the
  // move is farther than `reach` grid units or max_move from the source.
  const auto moved_along_normal = [&](int node, int handle, int step, double sign,
                                      int reach) -> std::optional<std::vector<Vec2>> {
    const std::optional<Vec2> tangent = grid_vector(at[handle] - at[node], grid);
    if (!tangent) return std::nullopt;
    const Vec2 v = sign * static_cast<double>(step) * Vec2(-tangent->y, tangent->x), p = at[node] + v;
    if (std::sqrt(dot(v, v)) > reach * grid || std::sqrt(dot(p - src[node], p - src[node])) > limit)
      return std::nullopt;
    std::vector<Vec2> trial = at;
    for (const int k : {at_index(node - 1), node, at_index(node + 1)}) trial[k] = trial[k] + v;
    return trial;
  };
  // The strictest g2 tolerance (0: no g2 gate); whether a curvature in [l_lo, l_hi] on a node's left can
  // meet g2 with one in [r_lo, r_hi] on its right: the union of passing_left over the right range is one
  // interval (both its ends rise with kr), from that of r_lo to that of r_hi.
  double tol = 0;
  for (const Gate& g : o.gates)
    if (g.kind == Gate::Kind::g2_at_smooth_nodes) tol = tol > 0 ? std::min(tol, g.tolerance) : g.tolerance;
  const auto ranges_meet = [&](double l_lo, double l_hi, double r_lo, double r_hi) {
    return l_hi >= passing_left(r_lo, tol)[0] && l_lo <= passing_left(r_hi, tol)[1];
  };
  // The nodes where g2 judges two units of `ranges` whose handles all slide (`sliding`: their nodes exactly
  // smooth) and whose ranges there cannot meet (a gap): their count, and with `list` each such node, its
  // left unit's start and its right unit's end in `gapped`.
  const auto sliding = [&](const CurvatureRange& u) {
    return exactly_smooth(at, m, u.start) && exactly_smooth(at, m, u.end);
  };
  std::vector<int> gapped;
  const auto count_gaps = [&](const std::vector<CurvatureRange>& ranges, bool list) {
    int n = 0;
    for (const CurvatureRange& right : ranges)
      for (const CurvatureRange& left : ranges)
        if (left.end == right.start && right.linked_start && sliding(left) && sliding(right) &&
            !ranges_meet(left.k1_lo, left.k1_hi, right.k0_lo, right.k0_hi)) {
          ++n;
          if (list) gapped.insert(gapped.end(), {right.start, left.start, right.end});
        }
    return n;
  };
  // The stuck units in the probe box at `at` (their nodes, pairs): the count a move must lower.
  std::optional<std::vector<int>> before;
  // Stuck units `stuck` (their nodes, pairs) less the two at `node`, appended to `out`.
  const auto add_away_from = [](const std::vector<int>& stuck, int node, std::vector<int>& out) {
    for (std::size_t i = 0; i + 1 < stuck.size(); i += 2)
      if (stuck[i] != node && stuck[i + 1] != node) out.insert(out.end(), {stuck[i], stuck[i + 1]});
  };
  // The stages before the last resort in three quarters of the work handed over (the caller's: a third of
  // the contour's), the last resort in all of it.
  const long handed = work.cap(work.left() / 4 * 3);
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
        std::optional<std::vector<Vec2>> trial = moved_along_normal(node, handle, step, sign, kBowlNormalReach);
        if (!trial || (matching && clashes(*trial, n0, n1, *r))) return false;
        ChainBox at_node = probe;
        at_node.probe_node = node;
        const std::optional<ChainResult> t = search(*trial, at_node);
        if (!t || work.spent()) return true;
        if (t->solved == t->chains) return answer = t->points, true;
        if (stuck_in(*t, n0, n1)) return false;
        std::vector<int> after = t->stuck;
        add_away_from(*before, node, after);
        if (after.size() >= before->size()) return false;
        at = std::move(*trial), next = std::move(after);
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
    // No unit stuck and a chain still unanswered: where the curvatures that a smooth node's two units reach
    // there (their ranges in the probe box) cannot meet g2, a gap, and every handle of both slides (their
    // nodes exactly smooth: a wider box for free handles, below, cannot close it), a node of those units
    // moves along its normal, nearest first, up to kBowlGapReach grid units, to the first place where both
    // units at the moved node have passing positions and fewer nodes have such a gap (a try probes them
    // first up to a passing position each, then every one for their ranges).
    if (r->stuck.empty() && moves < kBowlNodeMoves && tol > 0) {
      const std::optional<ChainResult> b = search(at, probe);
      if (!b || work.spent()) return std::nullopt;
      gapped.clear();
      const int gaps = count_gaps(b->ranges, true);
      std::vector<int> nodes;
      for (const int k : gapped)
        if (rigid(k) && std::find(nodes.begin(), nodes.end(), k) == nodes.end()) nodes.push_back(k);
      // Whether the move of `node` to `trial` is taken: true also where the contour passes there or the
      // work ran out (the moves end).
      std::optional<std::vector<Vec2>> answer;
      const auto try_gap = [&](int node, std::vector<Vec2>& trial) {
        ChainBox at_node = probe;
        at_node.probe_node = node;
        std::optional<ChainResult> t = search(trial, at_node);
        if (!t || work.spent()) return true;
        if (t->solved == t->chains) return answer = std::move(trial), true;
        if (!t->stuck.empty()) return false;
        at_node.probe_ranges = true;
        t = search(trial, at_node);
        if (!t || work.spent()) return true;
        std::vector<CurvatureRange> ranges = t->ranges;
        for (const CurvatureRange& x : b->ranges)
          if (x.start != node && x.end != node) ranges.push_back(x);
        if (count_gaps(ranges, false) >= gaps) return false;
        at = std::move(trial), moved = true;
        before.emplace();  // the probe's stuck units, less the two at the moved node (they pass now)
        add_away_from(b->stuck, node, *before);
        return true;
      };
      bool done = gaps == 0;
      for (int step = 1; step <= kBowlGapReach && !done; ++step)
        for (const int node : nodes)
          for (const double sign : {1.0, -1.0})
            if (!done)
              if (std::optional<std::vector<Vec2>> trial =
                      moved_along_normal(node, at_index(node + 1), step, sign, kBowlGapReach))
                done = try_gap(node, *trial);
      if (answer) return answer;
    }
    if (moved) continue;
    // No unit stuck and a chain still unanswered (g2 fails between units that each have passing
    // positions), or no move unsticks a unit: wider boxes for the free handles. Where a chain ends at a
    // corner, its end units' free handles may need to go farther (URW Gothic a's bowl, its two quarters
    // made wider than tall: the bottom one flat at p11, the unit from there to the corner sharp there
    // unless its free handle moves some 20 units); a unit between nodes not exactly smooth, whose handles
    // are free, may need them farther than the box (URW Gothic s's spine, p38 to p41: handles of 31 and
    // 83 units). The widest boxes take every other cell (glyph_bowl.hpp).
    for (const auto& [reach, stride] : kBowlWideBoxes) {
      ChainBox wide{reach, kChainSlideReach};
      wide.stride = stride;
      const std::optional<ChainResult> w = search(at, wide);
      if (!w || work.spent()) return std::nullopt;
      if (w->solved == w->chains) return w->points;
    }
    // Last, where no unit is stuck: one node of an unanswered chain moved along its normal, nearest first, up
    // to kBowlGapReach grid units, each try judged by the chain search itself (the units away from the moved
    // node kept: ChainCache). Ranges that meet can still fail (a unit's k0 and k1 go together): P052 O, its
    // left side moved out (a gap move), is answered with its bottom node 6 units in.
    if (r->stuck.empty() && moves < kBowlNodeMoves) {
      work.release(handed);
      std::vector<int> nodes;  // the unanswered chains' rigid nodes, in contour order
      for (int k = 0; k < m; ++k)
        if (rigid(k) && std::find(r->unanswered.begin(), r->unanswered.end(), k) != r->unanswered.end())
          nodes.push_back(k);
      for (int step = 1; step <= kBowlGapReach; ++step)
        for (const int node : nodes)
          for (const double sign : {1.0, -1.0})
            if (std::optional<std::vector<Vec2>> trial =
                    moved_along_normal(node, at_index(node + 1), step, sign, kBowlGapReach)) {
              const std::optional<ChainResult> t = search(*trial, full);
              if (!t || work.spent()) return std::nullopt;
              if (t->solved == t->chains) return t->points;
            }
    }
    return std::nullopt;
  }
}

}  // namespace cmr::report::glyph_detail
