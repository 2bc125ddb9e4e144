#include "design/fix_grid.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <limits>
#include <set>

#include "spline/cpu_clock.hpp"
#include "spline/errors.hpp"
#include "spline/format.hpp"

namespace cmr {
namespace {

double norm(Vec2 v) { return std::hypot(v.x, v.y); }

bool on_grid(double c, double grid) {
  const double q = c / grid;
  return std::isfinite(q) && q == std::floor(q) && std::abs(q) < 1e15;
}

bool on_grid(Vec2 p, double grid) { return on_grid(p.x, grid) && on_grid(p.y, grid); }

/// One unit of motion of the fix and its candidate displacements.
struct Unit {
  enum class Kind { free, group, slide } kind = Kind::free;
  std::vector<int> points;  ///< unique point indices moved together
  Vec2 target{0.0};         ///< the off-grid fix's displacement
  // slide: the handle is anchor + t * step; t0 where it was
  Vec2 anchor{0.0}, step{0.0};
  long t0 = 0;
};

/// The runs of cyclically consecutive moved points with one displacement
/// (length >= 2: a rigid group), slides and free points.
std::vector<Unit> units_of(const BSpline& s, const FixResult& fix, double grid) {
  const int m = s.unique_point_count();
  const bool closed = s.closed();
  std::vector<int> moved_at(m, -1);
  for (std::size_t i = 0; i < fix.moves.size(); ++i) moved_at[fix.moves[i].point] = static_cast<int>(i);
  auto delta = [&](int k) { return fix.moves[moved_at[k]].to - fix.moves[moved_at[k]].from; };
  auto next = [&](int k, int d) { return closed ? (k + d + m) % m : k + d; };
  std::vector<bool> done(m, false);
  std::vector<Unit> units;
  for (const PointMove& mv : fix.moves) {
    const int k = mv.point;
    if (done[k]) continue;
    Unit u;
    u.target = mv.to - mv.from;
    // Grow a run of equal displacements both ways.
    int a = k, b = k;
    while (true) {
      const int p = next(a, -1);
      if (p < 0 || p >= m || p == b || moved_at[p] < 0 || done[p] || delta(p) != u.target) break;
      a = p;
    }
    while (true) {
      const int q = next(b, 1);
      if (q < 0 || q >= m || q == a || moved_at[q] < 0 || done[q] || delta(q) != u.target) break;
      b = q;
    }
    for (int i = a;; i = next(i, 1)) {
      u.points.push_back(i);
      done[i] = true;
      if (i == b) break;
    }
    if (u.points.size() >= 2) {
      u.kind = Unit::Kind::group;
    } else {
      // A slide: along the line through an unmoved neighbour (its node).
      for (int d : {-1, 1}) {
        const int j = next(k, d);
        if (j < 0 || j >= m || moved_at[j] >= 0) continue;
        const Vec2 node = s.points()[j];
        const Vec2 a0 = mv.from - node, a1 = mv.to - node;
        const double cross = a0.x * a1.y - a0.y * a1.x;
        if (std::abs(cross) > 1e-9 * norm(a0) * norm(a1) || dot(a0, a1) <= 0) continue;
        if (!on_grid(node, grid) || !on_grid(mv.from, grid)) continue;
        const long dx = std::lround(a0.x / grid), dy = std::lround(a0.y / grid);
        const long g = std::gcd(std::abs(dx), std::abs(dy));
        if (g == 0) continue;
        u.kind = Unit::Kind::slide;
        u.anchor = node;
        u.step = Vec2(static_cast<double>(dx / g) * grid, static_cast<double>(dy / g) * grid);
        u.t0 = g;
        break;
      }
    }
    units.push_back(std::move(u));
  }
  return units;
}

/// The partners (GridOptions::partners) that no unit moves yet, each a
/// unit of its own that stays near where it is: a slide where the point is
/// a handle of an exactly smooth node (the point, the node and the node's
/// other neighbour exactly collinear, the node between), else free.
void add_partners(std::vector<Unit>& units, const BSpline& s, const GridOptions& options) {
  const int m = s.unique_point_count();
  const std::vector<Vec2>& p = s.points();
  std::vector<bool> taken(m, false);
  for (const Unit& u : units)
    for (int k : u.points) taken[k] = true;
  int added = 0;
  for (int k : options.partners) {
    if (k < 0 || k >= m || taken[k] || added >= options.max_partners) continue;
    Unit u;
    u.points = {k};
    for (int d : {-1, 1}) {
      const int j = s.closed() ? (k + d + m) % m : k + d, o = s.closed() ? (j + d + m) % m : j + d;
      if (j < 0 || j >= m || o < 0 || o >= m) continue;
      const Vec2 a = p[k] - p[j], b = p[o] - p[j];
      if (a == Vec2(0.0) || b == Vec2(0.0) || a.x * b.y - a.y * b.x != 0 || dot(a, b) >= 0) continue;
      if (!on_grid(p[j], options.grid) || !on_grid(p[k], options.grid)) continue;
      const long dx = std::lround(a.x / options.grid), dy = std::lround(a.y / options.grid);
      const long g = std::gcd(std::abs(dx), std::abs(dy));
      u.kind = Unit::Kind::slide;
      u.anchor = p[j];
      u.step = Vec2(static_cast<double>(dx / g) * options.grid, static_cast<double>(dy / g) * options.grid);
      u.t0 = g;
      break;
    }
    taken[k] = true;
    units.push_back(std::move(u));
    ++added;
  }
}

/// A unit's candidates at `radius` cells: displacements of its points.
std::vector<Vec2> candidates(const Unit& u, const BSpline& s, int radius, double grid, double max_move) {
  std::vector<Vec2> out{Vec2(0.0)};  // staying put
  const Vec2 lead = s.points()[u.points.front()];
  auto keep = [&](Vec2 d) {
    if (max_move > 0 && norm(d) > max_move) return;
    if (d != Vec2(0.0)) out.push_back(d);
  };
  if (u.kind == Unit::Kind::slide) {
    const double t_star = dot(lead + u.target - u.anchor, u.step) / dot(u.step, u.step);
    const long c = std::lround(t_star);
    for (long t = c - radius; t <= c + radius; ++t)
      if (t != u.t0 && (t > 0) == (u.t0 > 0) && t != 0)  // never onto or past the node: the tangent would turn
        keep(u.anchor + static_cast<double>(t) * u.step - lead);
    return out;
  }
  // free or group: grid displacements (a group's points move by the same
  // one, so a group on the grid stays on it); a free point to grid positions.
  const Vec2 base = u.kind == Unit::Kind::group ? Vec2(0.0) : lead;
  const Vec2 centre = base + u.target;
  const long cx = std::lround(centre.x / grid), cy = std::lround(centre.y / grid);
  for (long i = cx - radius; i <= cx + radius; ++i)
    for (long j = cy - radius; j <= cy + radius; ++j)
      keep(Vec2(static_cast<double>(i) * grid, static_cast<double>(j) * grid) - base);
  return out;
}

}  // namespace

GridFix snap_to_grid(const BSpline& original, const FixResult& fix, const std::function<int(const BSpline&)>& judge,
                     const GridOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  ThreadCpuDeadline cpu_deadline = options.thread_cpu_clock ? ThreadCpuDeadline(options.max_seconds) : ThreadCpuDeadline();
  GridFix out;
  out.off_grid_max_distance = fix.max_distance;
  if (!(options.grid > 0) || !std::isfinite(options.grid)) throw InputError("grid must be a positive step");
  if (!fix.spline || fix.moves.empty()) {
    out.reason = "the fix moves no point";
    return out;
  }
  std::vector<Unit> units = units_of(original, fix, options.grid);
  add_partners(units, original, options);

  std::set<std::vector<long>> tried;  // by the candidates' grid coordinates
  double best_cost = std::numeric_limits<double>::infinity();
  std::vector<Vec2> best;
  // First every moved unit pushed on together, s grid steps past its
  // off-grid target along its own move (a fix lies on its region's edge;
  // a little farther out, rounding stays inside): one passing combination
  // bounds the cost that the enumeration below must beat.
  for (const double push : {0.0, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0}) {
    std::vector<Vec2> delta(original.unique_point_count(), Vec2(0.0));
    double cost = 0;
    for (const Unit& u : units) {
      const Vec2 lead = original.points()[u.points.front()];
      const double len = norm(u.target);
      if (len == 0) continue;  // a partner stays
      Vec2 d;
      if (u.kind == Unit::Kind::slide) {
        const double t_star = dot(lead + u.target - u.anchor, u.step) / dot(u.step, u.step);
        const double away = t_star > static_cast<double>(u.t0) ? 1 : -1;
        const long t = std::lround(t_star + away * push * options.grid / norm(u.step));
        if (t == 0 || (t > 0) != (u.t0 > 0)) continue;
        d = u.anchor + static_cast<double>(t) * u.step - lead;
      } else {
        const Vec2 want = (u.kind == Unit::Kind::group ? Vec2(0.0) : lead) + u.target * (1 + push * options.grid / len);
        d = Vec2(std::round(want.x / options.grid) * options.grid, std::round(want.y / options.grid) * options.grid) -
            (u.kind == Unit::Kind::group ? Vec2(0.0) : lead);
      }
      if (options.max_move > 0 && norm(d) > options.max_move) continue;
      for (int k : u.points) delta[k] = d;
      cost += static_cast<double>(u.points.size()) * dot(d, d);
    }
    if (cost == 0 || cost >= best_cost) continue;
    BSpline moved = original;
    for (std::size_t k = 0; k < delta.size(); ++k)
      if (delta[k] != Vec2(0.0)) moved = moved.with_point(static_cast<int>(k), original.points()[k] + delta[k]);
    ++out.evaluations;
    if (judge(moved) == 0) {
      best_cost = cost;
      best = delta;
      out.spline = std::move(moved);
      break;
    }
  }
  int found_at = out.spline ? 1 : 0;  // the radius of the first pass: one wider round may still hold a cheaper one
  for (int radius = 1; radius <= 8 && (found_at == 0 || radius <= 2 * found_at); radius *= 2) {
    // Each unit's candidates; radii shrink (largest first) until the product fits.
    std::vector<int> r(units.size(), radius);
    std::vector<std::vector<Vec2>> cand(units.size());
    while (true) {
      double product = 1;
      for (std::size_t i = 0; i < units.size(); ++i) {
        cand[i] = candidates(units[i], original, r[i], options.grid, options.max_move);
        product *= static_cast<double>(cand[i].size());
      }
      if (product <= static_cast<double>(kMaxCombinations)) break;
      const auto widest = std::max_element(r.begin(), r.end());
      if (*widest == 0) break;
      --*widest;
    }
    // Every combination, cheapest first (total squared displacement).
    std::vector<std::pair<double, std::vector<std::size_t>>> combos{{0.0, {}}};
    for (std::size_t i = 0; i < units.size(); ++i) {
      std::vector<std::pair<double, std::vector<std::size_t>>> grown;
      grown.reserve(combos.size() * cand[i].size());
      const double weight = static_cast<double>(units[i].points.size());
      for (const auto& [cost, pick] : combos)
        for (std::size_t c = 0; c < cand[i].size(); ++c) {
          std::vector<std::size_t> p = pick;
          p.push_back(c);
          grown.emplace_back(cost + weight * dot(cand[i][c], cand[i][c]), std::move(p));
        }
      combos = std::move(grown);
    }
    out.combinations += static_cast<long>(combos.size());
    std::sort(combos.begin(), combos.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [cost, pick] : combos) {
      if (cost >= best_cost) break;  // a found one is cheaper than all the rest
      if (cost == 0) continue;       // nothing moved: the input fails
      std::vector<long> key;
      std::vector<Vec2> delta(original.unique_point_count(), Vec2(0.0));
      for (std::size_t i = 0; i < units.size(); ++i) {
        const Vec2 d = cand[i][pick[i]];
        key.push_back(std::lround(d.x / options.grid * 1024));
        key.push_back(std::lround(d.y / options.grid * 1024));
        for (int k : units[i].points) delta[k] = d;
      }
      if (!tried.insert(key).second) continue;
      if (out.evaluations >= options.max_evaluations ||
          (options.thread_cpu_clock ? cpu_deadline.passed()
                                    : std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() >
                                          options.max_seconds))
        break;
      BSpline moved = original;
      for (std::size_t k = 0; k < delta.size(); ++k)
        if (delta[k] != Vec2(0.0)) moved = moved.with_point(static_cast<int>(k), original.points()[k] + delta[k]);
      ++out.evaluations;
      const int verdict = judge(moved);
      if (verdict == 0) {
        best_cost = cost;
        best = delta;
        out.spline = std::move(moved);
        break;  // sorted: the cheapest passing one of this round
      }
    }
    if (out.spline && found_at == 0) found_at = radius;
  }
  if (!out.spline) {
    out.reason = "no position on the grid (step " + format_number(options.grid) + ") near the fix passes" +
                 (options.max_move > 0 ? " within the largest move " + format_number(options.max_move) : std::string()) +
                 "; the nearest off-grid fix moves " + format_number(fix.max_distance);
    return out;
  }
  out.found = true;
  for (std::size_t k = 0; k < best.size(); ++k) {
    if (best[k] == Vec2(0.0)) continue;
    PointMove m;
    m.point = static_cast<int>(k);
    m.from = original.points()[k];
    m.to = m.from + best[k];
    m.distance = norm(best[k]);
    out.total_squared += m.distance * m.distance;
    out.max_distance = std::max(out.max_distance, m.distance);
    out.moves.push_back(m);
  }
  return out;
}

}  // namespace cmr
