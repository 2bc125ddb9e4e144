#include "report/glyph_fix.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>

#include "report/batch.hpp"
#include "report/certified_fix.hpp"
#include "spline/errors.hpp"

namespace cmr::report {
namespace {

/// Violations of every required check, per check: the requirement (one when
/// it fails) first, then each gate's count.
std::vector<GateCount> judge_counts(const BSpline& s, const ReportOptions& o) {
  const SplineReport r = judged_report(s, o);
  std::vector<GateCount> out;
  if (o.require) out.push_back({to_string(*o.require), r.requirement_pass ? 0 : 1, 0});
  for (const GateResult& g : r.gates) out.push_back({to_string(g.gate), static_cast<int>(g.violations.size()), 0});
  return out;
}

int total(const std::vector<GateCount>& counts) {
  int n = 0;
  for (const GateCount& c : counts) n += c.before;
  return n;
}

/// The search's guide: the requirement's own fix requirement, else the
/// first failing gate's.
FixRequirement guide(const ReportOptions& o, const SplineReport& r) {
  if (o.require && !r.requirement_pass) {
    FixRequirement req;
    req.kind = o.require->split ? FixRequirement::Kind::split
               : o.require->mode == Mode::cmr ? FixRequirement::Kind::cmr
                                              : FixRequirement::Kind::cmrwi;
    if (o.require->split) req.split = *o.require->split;
    req.extremum = o.require->extremum == Extremum::sharpest   ? FixRequirement::Extremum::sharpest
                   : o.require->extremum == Extremum::flattest ? FixRequirement::Extremum::flattest
                                                               : FixRequirement::Extremum::any;
    return req;
  }
  for (const GateResult& g : r.gates)
    if (!g.pass() && g.gate.kind != Gate::Kind::xy_extrema_at_nodes && !is_interpolation_gate(g.gate))
      return requirement_of(g.gate);  // xy: a node; between masters: not a move of this contour
  return {};
}

/// The contour's points a fix may move: source points that are not a
/// straight piece's end node (a line's inner points are no source points).
std::vector<int> movable_points(const import::Contour& c) {
  const int m = static_cast<int>(c.font_point.size());
  std::vector<int> out;
  for (int k = 0; k < m; ++k) {
    if (c.font_point[k] < 0) continue;
    const bool line_end = c.node[k] && (c.font_point[(k + 1) % m] < 0 || c.font_point[(k + m - 1) % m] < 0);
    if (!line_end) out.push_back(k);
  }
  return out;
}

/// The movable handles (not nodes) nearest the fix's moved points along
/// the contour, nearest first: the grid snap's partners.
std::vector<int> partners_of(const import::Contour& c, const FixResult& f, const std::vector<int>& movable) {
  const int m = static_cast<int>(c.node.size());
  std::vector<std::pair<int, int>> by_distance;  // (steps along the contour, point)
  for (int k : movable) {
    if (c.node[k]) continue;
    int best = m;
    for (const PointMove& mv : f.moves) {
      const int d = std::abs(k - mv.point);
      best = std::min(best, std::min(d, m - d));
    }
    if (best > 0 && best <= 3) by_distance.emplace_back(best, k);
  }
  std::sort(by_distance.begin(), by_distance.end());
  std::vector<int> out;
  for (const auto& [d, k] : by_distance) out.push_back(k);
  return out;
}

/// Rounds of the search (each lowers the count of violations).
constexpr int kGlyphFixRounds = 12;

/// Every node that is exactly smooth in the source (its neighbours on both
/// sides exactly collinear with it, on opposite sides) is so in `s` too.
/// Exact for coordinates below 2^26 (products below 2^53): font units.
bool smooth_kept(const import::Contour& c, const BSpline& s) {
  const int m = static_cast<int>(c.node.size());
  const std::vector<Vec2>& a = c.spline.points();
  const std::vector<Vec2>& b = s.points();
  auto smooth = [&](const std::vector<Vec2>& p, int k) {
    const Vec2 u = p[(k + m - 1) % m] - p[k], v = p[(k + 1) % m] - p[k];
    if (u == Vec2(0.0) || v == Vec2(0.0)) return false;
    return u.x * v.y - u.y * v.x == 0 && u.x * v.x + u.y * v.y < 0;
  };
  for (int k = 0; k < m; ++k)
    if (c.node[k] && smooth(a, k) && !smooth(b, k)) return false;
  return true;
}

ContourFix fix_contour(const import::Contour& c, const GlyphFixOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  ContourFix out;
  out.contour = c.index;
  const ReportOptions o = judge_only(options.judge);
  out.rejudged = judge_counts(c.spline, o);
  if (total(out.rejudged) == 0) {
    out.already = out.fixed = true;
    for (GateCount& g : out.rejudged) g.after = g.before;
    return out;
  }
  auto judge_of = [](const ReportOptions& oi) {
    return [oi](const BSpline& s) {
      try {
        return total(judge_counts(s, oi));
      } catch (const InputError&) {
        return std::numeric_limits<int>::max() / 2;
      }
    };
  };
  const std::function<int(const BSpline&)> judge = judge_of(o);
  // Stages: the requirement, then each gate in turn, each judged together
  // with the checks before it (which it may not break), from where the
  // stage before left the contour.
  const std::vector<int> movable = movable_points(c);
  if (movable.empty()) {
    out.reason = "no source point may move (every node ends a straight piece)";
    return out;
  }
  // Rounds: each tries to fix one failing check alone (its own judge and
  // search guide), then all of them at once, from where the last round
  // left the contour, snapped to the grid; a round is taken when the total
  // count of violations of every check falls and every smooth node stays
  // exactly smooth. So the total falls each round and the loop ends.
  auto checks_of = [&](const BSpline& s) {
    std::vector<ReportOptions> out_checks;
    const SplineReport r = judged_report(s, o);
    if (o.require && !r.requirement_pass) {
      ReportOptions t = o;
      t.gates.clear();
      out_checks.push_back(t);
    }
    for (std::size_t g = 0; g < r.gates.size(); ++g)
      if (!r.gates[g].pass()) {
        ReportOptions t = o;
        t.require.reset();
        t.gates = {o.gates[g]};
        out_checks.push_back(t);
      }
    if (out_checks.size() > 1) out_checks.push_back(o);
    return out_checks;
  };
  BSpline current = c.spline;
  int current_total = total(out.rejudged);
  std::string why;
  for (int round = 0; round < kGlyphFixRounds && current_total > 0; ++round) {
    bool improved = false;
    for (const ReportOptions& t : checks_of(current)) {
      const std::function<int(const BSpline&)> check_judge = judge_of(t);
      FixRequest q;
      q.requirement = guide(t, judged_report(current, t));
      q.max_depth = o.max_depth;
      q.keep = Keep::g1;
      q.max_seconds = options.max_seconds;
      q.threads = 1;
      q.max_move = options.max_move;
      q.judge = check_judge;
      q.points = movable;  // with a judge every judged segment counts as failing, so each point acts on one
      const FixResult f = fix(current, q);
      if (!f.fixed || f.already) {
        why = f.reason;
        continue;
      }
      out.off_grid_distance = std::max(out.off_grid_distance, f.max_distance);
      BSpline next = *f.spline;
      // Off the grid it may still break another check; the grid snap (which
      // may move neighbouring handles too) then has to mend that.
      const bool off_grid_ok = judge(next) < current_total && smooth_kept(c, next);
      const std::string breaks = "the fix of " +
                                 (t.gates.size() == 1 && !t.require ? to_string(t.gates[0]) : std::string("every check")) +
                                 " breaks another check (no round lowers the count of violations)";
      if (!off_grid_ok && options.grid <= 0) {
        why = breaks;
        continue;
      }
      if (options.grid > 0) {
        // On the grid: the check passes and the total falls.
        const int before_total = current_total;
        auto snap_judge = [&](const BSpline& s) {
          const int own = check_judge(s);
          if (own != 0) return own;
          return judge(s) < before_total && smooth_kept(c, s) ? 0 : 1;
        };
        GridOptions g;
        g.grid = options.grid;
        g.max_move = options.max_move;
        g.max_seconds = options.max_seconds;
        g.partners = partners_of(c, f, movable);
        const GridFix snapped = snap_to_grid(current, f, snap_judge, g);
        if (!snapped.found) {
          why = off_grid_ok ? snapped.reason : breaks;
          continue;
        }
        next = *snapped.spline;
      }
      const int next_total = judge(next);
      if (next_total < current_total && smooth_kept(c, next)) {
        current = std::move(next);
        current_total = next_total;
        improved = true;
        break;
      }
    }
    if (!improved) break;
  }
  if (current_total > 0) {
    out.reason = why.empty() ? "no fix passes every check" : why;
    return out;
  }
  std::vector<PointMove> moves;
  for (int k = 0; k < c.spline.unique_point_count(); ++k) {
    const Vec2 from = c.spline.points()[k], to = current.points()[k];
    if (from != to) moves.push_back({k, from, to, std::hypot(to.x - from.x, to.y - from.y)});
  }
  const BSpline& fixed = current;
  // Re-judged, check by check: none may be worse, all must pass.
  const std::vector<GateCount> after = judge_counts(fixed, o);
  bool all_pass = true;
  for (std::size_t i = 0; i < out.rejudged.size() && i < after.size(); ++i) {
    out.rejudged[i].after = after[i].before;
    all_pass = all_pass && after[i].before == 0;
  }
  if (!all_pass) {
    out.reason = "the fix fails a check when re-judged";
    return out;
  }
  out.fixed = true;
  out.moves = moves;
  for (const PointMove& m : moves) {
    std::string name = "P";  // appended: GCC 12 warns (-Wrestrict) on "P" + to_string
    out.names.push_back(m.point < static_cast<int>(c.point_names.size()) ? c.point_names[m.point]
                                                                         : name.append(std::to_string(m.point)));
    out.source_points.push_back(m.point < static_cast<int>(c.font_point.size()) ? c.font_point[m.point] : -1);
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace

std::vector<ContourFix> fix_glyph(const import::Glyph& glyph, const GlyphFixOptions& options) {
  if (!glyph.error.empty()) throw InputError(glyph.error);
  std::vector<ContourFix> out;
  for (const import::Contour& c : glyph.contours) out.push_back(fix_contour(c, options));
  return out;
}

}  // namespace cmr::report
