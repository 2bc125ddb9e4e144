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
    if (!g.pass()) return requirement_of(g.gate);
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

ContourFix fix_contour(const import::Contour& c, const GlyphFixOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  ContourFix out;
  out.contour = c.index;
  ReportOptions o = options.judge;
  o.regions = false;
  o.certified_fixes = false;
  o.threads = 1;
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
  BSpline current = c.spline;
  ReportOptions stage = o;
  stage.gates.clear();
  const std::size_t stages = o.gates.size() + (o.require ? 1 : 0);
  for (std::size_t i = 0; i < stages; ++i) {
    if (!(o.require && i == 0)) stage.gates.push_back(o.gates[i - (o.require ? 1 : 0)]);  // stage 0: the requirement alone
    const std::function<int(const BSpline&)> stage_judge = judge_of(stage);
    if (stage_judge(current) == 0) continue;
    FixRequest q;
    q.requirement = guide(stage, judged_report(current, stage));
    q.max_depth = o.max_depth;
    q.keep = Keep::g1;
    q.max_seconds = options.max_seconds;
    q.threads = 1;
    q.max_move = options.max_move;
    q.judge = stage_judge;
    q.together = i > 0;  // later stages: the points together, from where the earlier stages left them
    q.points = movable;  // with a judge every judged segment counts as failing, so each point acts on one
    const FixResult f = fix(current, q);
    if (!f.fixed) {
      out.reason = f.reason;
      return out;
    }
    current = *f.spline;
  }
  // The stages' moves together, from the original points.
  FixResult f;
  f.fixed = true;
  f.spline = current;
  for (int k = 0; k < c.spline.unique_point_count(); ++k) {
    const Vec2 from = c.spline.points()[k], to = current.points()[k];
    if (from == to) continue;
    const double d = std::hypot(to.x - from.x, to.y - from.y);
    f.moves.push_back({k, from, to, d});
    f.max_distance = std::max(f.max_distance, d);
  }
  out.off_grid_distance = f.max_distance;
  std::vector<PointMove> moves = f.moves;
  BSpline fixed = *f.spline;
  if (options.grid > 0) {
    GridOptions g;
    g.grid = options.grid;
    g.max_move = options.max_move;
    g.max_seconds = options.max_seconds;
    const GridFix snapped = snap_to_grid(c.spline, f, judge, g);
    if (!snapped.found) {
      out.reason = snapped.reason;
      return out;
    }
    moves = snapped.moves;
    fixed = *snapped.spline;
  }
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
