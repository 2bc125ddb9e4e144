#include "report/glyph_settle.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <utility>

#include "bezierize/extract.hpp"
#include "design/fix.hpp"
#include "design/fix_grid.hpp"
#include "report/batch.hpp"

namespace cmr::report::glyph_detail {
namespace {

/// The lattice steps d of `u` whose distance rho = |d + mean| from the
/// unit's cheapest position lies in (lo, hi] (lo < 0: from 0): a ring of
/// the grid (a translation) or two pieces of the slide's line. The settling
/// scans a unit's positions in such bands of rho, which is the order of
/// their cost, so it never lists the whole disc at once.
std::vector<Vec2> band_steps(const LatticeUnit& u, Vec2 mean, double grid, double lo, double hi) {
  std::vector<Vec2> out;
  auto in_band = [&](Vec2 d) {
    const double r2 = dot(d + mean, d + mean);
    return (lo < 0 || r2 > lo * lo) && r2 <= hi * hi;
  };
  if (u.slide) {
    const double len = std::sqrt(dot(u.step, u.step)), centre = -dot(mean, u.step) / (len * len);
    const double a = hi / len + 1, b = lo < 0 ? -1 : lo / len - 1;
    for (long j = std::lround(std::floor(centre - a)); j <= std::lround(std::ceil(centre + a)); ++j) {
      if (b > 0 && std::abs(static_cast<double>(j) - centre) < b) j = std::lround(std::floor(centre + b));
      const Vec2 d = static_cast<double>(j) * u.step;
      if (in_band(d)) out.push_back(d);
    }
    return out;
  }
  const long i0 = std::lround(std::floor((-mean.x - hi) / grid)) - 1, i1 = std::lround(std::ceil((-mean.x + hi) / grid)) + 1;
  for (long i = i0; i <= i1; ++i) {
    const double dx = static_cast<double>(i) * grid + mean.x;
    if (dx * dx > hi * hi) continue;
    const double yhi = std::sqrt(hi * hi - dx * dx), ylo = lo > 0 && dx * dx < lo * lo ? std::sqrt(lo * lo - dx * dx) : -1;
    auto run = [&](double from, double to) {
      for (long j = std::lround(std::floor(from / grid)) - 1; j <= std::lround(std::ceil(to / grid)) + 1; ++j) {
        const Vec2 d(static_cast<double>(i) * grid, static_cast<double>(j) * grid);
        if (in_band(d)) out.push_back(d);
      }
    };
    if (ylo < 0) {
      run(-mean.y - yhi, -mean.y + yhi);
    } else {
      run(-mean.y - yhi, -mean.y - ylo);
      run(-mean.y + ylo, -mean.y + yhi);
    }
  }
  return out;
}

}  // namespace

double squared_move(const std::vector<Vec2>& src, const std::vector<Vec2>& pts) {
  double t = 0;
  for (std::size_t k = 0; k < src.size(); ++k) t += dot(pts[k] - src[k], pts[k] - src[k]);
  return t;
}

bool settle_nearer(const std::vector<Vec2>& src, std::vector<Vec2>& at, const std::vector<LatticeUnit>& given,
                   double grid, double max_move, const Judge& passes,
                   const std::function<std::vector<int>(const std::vector<int>&)>& depends_on, const Rejects& rejects,
                   Work& work, bool turns_from_settled) {
  std::vector<LatticeUnit> units = given;  // a turn changes its slides' steps
  const int m = static_cast<int>(src.size());  // the distinct points (a closed spline's first ones are not repeated)
  // Per unit, the points its verdicts read (depends_on), as flags.
  std::vector<std::vector<char>> reads(units.size(), std::vector<char>(static_cast<std::size_t>(m), 0));
  for (std::size_t u = 0; u < units.size(); ++u)
    for (int k : depends_on(units[u].points)) reads[u][static_cast<std::size_t>(k)] = 1;
  auto cost_of = [&](const std::vector<Vec2>& pts) { return squared_move(src, pts); };
  auto within = [&](const std::vector<Vec2>& pts) {
    for (int k = 0; k < m; ++k)
      if (std::hypot(pts[k].x - src[k].x, pts[k].y - src[k].y) > max_move) return false;
    return true;
  };
  // The first candidate (in order of cost, each lower than now) that
  // passes becomes `at`; false when none does or time is up. A candidate
  // is (cost, what `build` makes the moved points of).
  bool out_of_time = false;
  auto take_first = [&](auto& candidates, const auto& build) {
    if (work.spent()) return !(out_of_time = true);  // also where `rejects` left no candidate
    std::stable_sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (auto& [unused, c] : candidates) {
      if (work.spent()) return !(out_of_time = true);
      std::vector<Vec2> t = build(c);
      if (!within(t) || !passes(at, t)) continue;
      at = std::move(t);
      return true;
    }
    return false;
  };
  // Units and pairs done where `at` is now (singles, below: tried; pairs:
  // none of their candidates passed) until a point they read moves: moved()
  // frees them.
  std::vector<char> stuck(units.size(), 0);
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t a = 0; a < units.size(); ++a)
    for (std::size_t b = a + 1; b < units.size(); ++b) {
      const int d = std::abs(units[a].points.front() - units[b].points.front());
      if (std::min(d, m - d) <= 3) pairs.emplace_back(a, b);
    }
  std::vector<char> pair_stuck(pairs.size(), 0);
  // Turns (on request): the two sliding handles of one smooth node (units on one anchor).
  std::vector<std::pair<std::size_t, std::size_t>> turns;
  for (std::size_t a = 0; turns_from_settled && a < units.size(); ++a)
    for (std::size_t b = a + 1; b < units.size(); ++b)
      if (units[a].slide && units[b].slide && units[a].anchor >= 0 && units[a].anchor == units[b].anchor &&
          units[a].step.x != 0 && units[a].step.y != 0)  // a level or upright tangent (an x/y extremum) stays
        turns.emplace_back(a, b);
  std::vector<char> turn_stuck(turns.size(), 0);
  // From a settled position, every single and pair is done until a turn moves a point it reads.
  if (turns_from_settled) stuck.assign(stuck.size(), 1), pair_stuck.assign(pair_stuck.size(), 1);
  std::vector<std::vector<char>> turn_reads(turns.size());
  for (std::size_t t = 0; t < turns.size(); ++t) {
    turn_reads[t].assign(static_cast<std::size_t>(m), 0);
    for (int k : depends_on({units[turns[t].first].points.front(), units[turns[t].second].points.front()}))
      turn_reads[t][static_cast<std::size_t>(k)] = 1;
  }
  std::vector<std::vector<char>> pair_reads(pairs.size(), std::vector<char>(static_cast<std::size_t>(m), 0));
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    std::vector<int> both = units[pairs[p].first].points;
    both.insert(both.end(), units[pairs[p].second].points.begin(), units[pairs[p].second].points.end());
    for (int k : depends_on(both)) pair_reads[p][static_cast<std::size_t>(k)] = 1;
  }
  auto moved = [&](const std::vector<std::size_t>& which) {
    for (std::size_t w : which)
      for (int k : units[w].points) {
        for (std::size_t u = 0; u < units.size(); ++u)
          if (reads[u][static_cast<std::size_t>(k)]) stuck[u] = 0;
        for (std::size_t p = 0; p < pairs.size(); ++p)
          if (pair_reads[p][static_cast<std::size_t>(k)]) pair_stuck[p] = 0;
        for (std::size_t t = 0; t < turns.size(); ++t)
          if (turn_reads[t][static_cast<std::size_t>(k)]) turn_stuck[t] = 0;
      }
  };
  auto moved_by = [&](const std::vector<std::pair<const LatticeUnit*, Vec2>>& steps) {
    std::vector<Vec2> t = at;
    for (const auto& [u, d] : steps)
      for (int k : u->points) t[k] = t[k] + d;
    return t;
  };
  // Single units until none moves.
  auto singles = [&] {
    for (bool any = true; any && !out_of_time;) {
      any = false;
      for (std::size_t ui = 0; ui < units.size(); ++ui) {
        if (stuck[ui]) continue;
        const LatticeUnit& u = units[ui];
        // The unit's share of the cost as a function of its step delta:
        // sum over its points of |a_k + delta|^2 = n |delta + mean|^2 + rest.
        Vec2 mean(0.0);
        double own = 0;
        for (int k : u.points) {
          const Vec2 a = at[k] - src[k];
          mean = mean + a, own += dot(a, a);
        }
        if (own == 0) continue;
        const double n = static_cast<double>(u.points.size());
        mean = mean / n;
        const double rest = own - n * dot(mean, mean), now = cost_of(at);
        auto share = [&](Vec2 d) { return n * dot(d + mean, d + mean) + rest; };
        // The positions cheaper than now (rho = |d + mean| < reach), band
        // by band of rho (kSettleCandidates or so each), so in order of
        // cost, until one passes.
        const double reach = std::sqrt(std::max(0.0, (own - rest) / n));
        const double width = u.slide ? kSettleCandidates / 2.0 * std::sqrt(dot(u.step, u.step))
                                     : std::sqrt(kSettleCandidates / 3.14159) * grid;
        bool taken = false;
        for (double lo = -1; lo < reach && !taken && !out_of_time; lo = lo < 0 ? width : lo + width) {
          std::vector<std::pair<double, Vec2>> candidates;
          for (const Vec2 d : band_steps(u, mean, grid, lo, lo < 0 ? width : lo + width))
            if (share(d) < own) candidates.emplace_back(now - own + share(d), d);
          if (rejects && !candidates.empty()) {
            std::vector<Vec2> steps;
            for (const auto& c : candidates) steps.push_back(c.second);
            const std::vector<char> out = rejects(at, u, steps);
            std::size_t kept = 0;
            for (std::size_t c = 0; c < candidates.size(); ++c)
              if (!out[c]) candidates[kept++] = candidates[c];
            candidates.resize(kept);
          }
          taken = take_first(candidates, [&](Vec2 d) { return moved_by({{&u, d}}); });
        }
        if (taken) {
          any = true;
          moved({ui});
        }
        // Taken or not, every position of the unit nearer than where it is
        // now was judged in this scan, every other point where it is (a
        // pair's candidates are near where the pair is: a moved pair is not
        // done so).
        if (!out_of_time) stuck[ui] = 1;
      }
    }
  };
  auto offsets = [&](const LatticeUnit& u) {
    std::vector<Vec2> out;
    if (u.slide) {
      for (int j = -kPairSlideReach; j <= kPairSlideReach; ++j)
        if (j != 0) out.push_back(static_cast<double>(j) * u.step);
    } else {
      for (int i = -kPairReach; i <= kPairReach; ++i)
        for (int j = -kPairReach; j <= kPairReach; ++j)
          if (i != 0 || j != 0) out.emplace_back(i * grid, j * grid);
    }
    return out;
  };
  // A turn's positions cheaper than now: handle `lead` up to kTurnReach
  // cells from where it is, `other` on the tangent through the node.
  auto turned = [&](const std::pair<std::size_t, std::size_t>& tr) {
    const int node = units[tr.first].anchor;
    const Vec2 n = at[node];
    const double now = cost_of(at);
    std::vector<std::pair<double, std::vector<Vec2>>> out;
    for (const bool first_leads : {true, false}) {
      const int lead = units[first_leads ? tr.first : tr.second].points.front();
      const int other = units[first_leads ? tr.second : tr.first].points.front();
      const Vec2 tangent = at[other] - at[lead];
      for (int i = -kTurnReach; i <= kTurnReach; ++i)
        for (int j = -kTurnReach; j <= kTurnReach; ++j) {
          if (i * i + j * j > kTurnReach * kTurnReach || (i == 0 && j == 0)) continue;
          const Vec2 l = at[lead] + Vec2(i * grid, j * grid);
          const long wx = std::lround((n.x - l.x) / grid), wy = std::lround((n.y - l.y) / grid);
          const long g = std::gcd(wx, wy);
          if (g == 0) continue;
          const Vec2 v(static_cast<double>(wx / g) * grid, static_cast<double>(wy / g) * grid);
          if (v.x * tangent.y == v.y * tangent.x) continue;  // the same tangent: a slide
          const double b = dot(src[other] - n, v) / dot(v, v);
          for (const double whole : {std::floor(b), std::ceil(b)}) {
            std::vector<Vec2> t = at;
            t[lead] = l, t[other] = n + v * std::max(1.0, whole);
            if (const double cost_t = cost_of(t); cost_t < now) out.emplace_back(cost_t, std::move(t));
          }
        }
    }
    return out;
  };
  if (!turns_from_settled) singles();
  for (bool any_turn = true; any_turn && !out_of_time;) {
    // Pairs in turn, until a whole round moves none.
    for (std::size_t next = 0, quiet = 0; quiet < pairs.size() && !out_of_time; next = (next + 1) % pairs.size()) {
      if (pair_stuck[next]) {
        ++quiet;
        continue;
      }
      const LatticeUnit* a = &units[pairs[next].first];
      const LatticeUnit* b = &units[pairs[next].second];
      const double now = cost_of(at);
      std::vector<std::pair<double, std::vector<Vec2>>> candidates;
      for (const Vec2 da : offsets(*a))
        for (const Vec2 db : offsets(*b)) {
          std::vector<Vec2> t = moved_by({{a, da}, {b, db}});
          if (const double cost_t = cost_of(t); cost_t < now) candidates.emplace_back(cost_t, std::move(t));
        }
      if (take_first(candidates, [](std::vector<Vec2>& t) { return std::move(t); })) {
        quiet = 0;
        moved({pairs[next].first, pairs[next].second});
        singles();
      } else {
        ++quiet;
        if (!out_of_time) pair_stuck[next] = 1;
      }
    }
    // Then the turns (on request); after one moves, the singles and the pairs again.
    any_turn = false;
    for (std::size_t t = 0; t < turns.size() && !out_of_time && !any_turn; ++t) {
      if (turn_stuck[t]) continue;
      std::vector<std::pair<double, std::vector<Vec2>>> candidates = turned(turns[t]);
      if (take_first(candidates, [](std::vector<Vec2>& x) { return std::move(x); })) {
        any_turn = true;
        for (const std::size_t u : {turns[t].first, turns[t].second})  // they slide on the new tangent
          units[u].step = grid_vector(at[units[u].points.front()] - at[units[u].anchor], grid).value_or(units[u].step);
        moved({turns[t].first, turns[t].second});
        singles();
      } else if (!out_of_time) {
        turn_stuck[t] = 1;
      }
    }
  }
  return !out_of_time;
}

RunJudge::RunJudge(const BSpline& contour, const ReportOptions& o) : o_(o), segments_(contour.segment_count()) {
  // The runs are cyclic: a closed contour's (an open spline, which the glyph
  // fix does not take, is judged whole).
  local_ = contour.closed() && !o.require && std::all_of(o.gates.begin(), o.gates.end(), [](const Gate& g) {
    return g.kind == Gate::Kind::extrema_at_nodes || g.kind == Gate::Kind::max_extrema_per_segment ||
           g.kind == Gate::Kind::g2_at_smooth_nodes;
  });
  const int distinct = contour.unique_point_count();  // points() repeats a closed spline's first ones
  touches_.resize(static_cast<std::size_t>(distinct));
  shapes_.resize(static_cast<std::size_t>(segments_));
  for (int i = 0; i < segments_; ++i)
    for (int k : segment_points(contour, contour.segments()[static_cast<std::size_t>(i)])) {
      touches_[static_cast<std::size_t>(k % distinct)].push_back(i);
      shapes_[static_cast<std::size_t>(i)].push_back(k % distinct);
    }
}

std::vector<int> RunJudge::depends_on(const std::vector<int>& points) const {
  const int distinct = static_cast<int>(touches_.size());
  std::vector<Vec2> from(touches_.size(), Vec2(0.0)), to = from;
  for (int k : points) to[static_cast<std::size_t>(k)] = Vec2(1.0);
  std::vector<int> out;
  if (const std::optional<Run> r = run(from, to)) {
    std::vector<char> in(touches_.size(), 0);
    for (int i = r->first - 1; i <= r->first + r->length; ++i)
      for (int k : shapes_[static_cast<std::size_t>((i + segments_) % segments_)]) in[static_cast<std::size_t>(k)] = 1;
    for (int k = 0; k < distinct; ++k)
      if (in[static_cast<std::size_t>(k)]) out.push_back(k);
  } else {
    out.resize(touches_.size());
    std::iota(out.begin(), out.end(), 0);
  }
  return out;
}

std::optional<RunJudge::Run> RunJudge::run(const std::vector<Vec2>& from, const std::vector<Vec2>& to) const {
  if (!local_) return std::nullopt;
  const int n = segments_;
  std::vector<char> changed(static_cast<std::size_t>(n), 0);
  for (std::size_t k = 0; k < touches_.size(); ++k)
    if (from[k] != to[k])
      for (int i : touches_[k]) changed[static_cast<std::size_t>(i)] = 1;
  // The shortest cyclic run holding every changed segment: all but the
  // longest run of unchanged ones.
  int best_gap = 0, best_end = -1;
  for (int i = 0, gap = 0; i < 2 * n; ++i) {
    gap = changed[static_cast<std::size_t>(i % n)] ? 0 : gap + 1;
    if (gap > best_gap && gap <= n) best_gap = gap, best_end = i;
  }
  const int length = n - best_gap;
  if (length == 0 || length + 2 >= n) return std::nullopt;
  return Run{(best_end + 1) % n, length};
}

SplineReport RunJudge::report(const BSpline& s, const Run& r) const {
  const int n = segments_;
  SplineReport out = gate_report(segments_window(s, (r.first + n - 1) % n, r.length + 2), o_);
  for (GateResult& g : out.gates)
    std::erase_if(g.violations, [&](const GateViolation& v) {
      const bool on_run = v.segment >= 0 ? v.segment >= 1 && v.segment <= r.length : v.joint >= 1 && v.joint <= r.length + 1;
      return !on_run;
    });
  return out;
}

std::vector<std::vector<PointMove>> parts_of(const import::Contour& c, const FixResult& f) {
  const int m = c.spline.unique_point_count();
  std::vector<int> part(static_cast<std::size_t>(m), -1), parent(f.moves.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int i) {
    while (parent[static_cast<std::size_t>(i)] != i) {
      parent[static_cast<std::size_t>(i)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
      i = parent[static_cast<std::size_t>(i)];
    }
    return i;
  };
  for (std::size_t i = 0; i < f.moves.size(); ++i) part[static_cast<std::size_t>(f.moves[i].point % m)] = static_cast<int>(i);
  for (const Segment& seg : c.spline.segments()) {
    int first = -1;
    for (int k : segment_points(c.spline, seg)) {
      const int i = part[static_cast<std::size_t>(k % m)];
      if (i < 0) continue;
      if (first < 0) first = i;
      else parent[static_cast<std::size_t>(root(i))] = root(first);
    }
  }
  std::map<int, std::vector<PointMove>> by_root;
  for (std::size_t i = 0; i < f.moves.size(); ++i) by_root[root(static_cast<int>(i))].push_back(f.moves[i]);
  std::vector<std::vector<PointMove>> out;
  for (auto& [r, moves] : by_root) out.push_back(std::move(moves));
  return out;
}

std::optional<BSpline> snap_by_parts(const import::Contour& c, const FixResult& f,
                                     const std::function<int(const BSpline&)>& snap_judge,
                                     const std::function<std::vector<int>(const FixResult&)>& partners, GridOptions g,
                                     Work& work) {
  const std::vector<std::vector<PointMove>> parts = parts_of(c, f);
  if (parts.size() < 2 || !f.spline) return std::nullopt;
  BSpline base = *f.spline;
  const long segments = c.spline.segment_count();
  for (const std::vector<PointMove>& moves : parts) {
    if (work.spent()) return std::nullopt;
    BSpline original = base;
    for (const PointMove& mv : moves) original = original.with_point(mv.point, mv.from);
    FixResult part;
    part.fixed = true;
    part.spline = base;
    part.moves = moves;
    for (const PointMove& mv : moves) part.max_distance = std::max(part.max_distance, mv.distance);
    // The part's own units first (a few candidates each), then with its
    // partners.
    GridFix snapped;
    for (const bool with_partners : {false, true}) {
      if (work.spent()) return std::nullopt;
      g.partners = with_partners ? partners(part) : std::vector<int>{};
      g.max_seconds = work.seconds_left();
      g.thread_cpu_clock = true;
      g.max_evaluations = std::min(kSnapEvaluations, std::max(1L, work.left() / segments));
      snapped = snap_to_grid(original, part, snap_judge, g);
      work.charge(snapped.evaluations * segments + snapped.combinations / 2);
      if (snapped.found) break;
    }
    if (!snapped.found) return std::nullopt;
    base = *snapped.spline;
  }
  return base;
}

}  // namespace cmr::report::glyph_detail
