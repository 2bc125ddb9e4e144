// The editor's opening selection and its repairs: "fix" and "snap into
// region" (design/fix.hpp), animated and undoable (docs/edit.md).
#include <algorithm>
#include <cstdio>

#include "bezierize/analyze.hpp"
#include "region/region_reason.hpp"
#include "report/gates.hpp"
#include "report/glyph_fix.hpp"
#include "spline/errors.hpp"
#include "tools/edit/editor.hpp"
#include "tools/field_flags.hpp"

namespace cmr::edit {
namespace {

/// The certified monotone labels of the layer (the region's pixels), as
/// region_reason counts them.
int monotone_count(const RegionResult& r) {
  int n = 0;
  for (std::size_t i = 0; i < r.size(); ++i) n += r.in_region(i);
  return n;
}

/// region_reason's words for a closed curve judged over its whole period.
constexpr const char* kPeriodReason = "never monotone over its whole period";

}  // namespace

int opening_coarse(std::pair<int, int> canvas) {
  return std::max(1, std::max(canvas.first, canvas.second) / Editor::kOpeningGrid);
}

std::optional<int> Editor::open_on_region_point(std::optional<int> named) {
  const Document start = doc();
  if (named) {
    const int m = start.spline.unique_point_count();
    if (*named < 0 || *named >= m)
      throw InputError("--point: the curve has points 0.." + std::to_string(m - 1) + " (got " +
                       std::to_string(*named) + ")");
    Document d = start;
    d.selected = *named;
    std::erase(d.group, *named);
    history_ = History(std::move(d));
    changed_document();
    message.clear();
    region();  // its region now: when it is empty or full, the reason joins this line
    message = "opened on " + point_name(*named) + " (--point)" + (message.empty() ? "" : "; " + message);
    return named;
  }
  if (start.kcurve || start.all_points) return std::nullopt;
  const int m = start.spline.unique_point_count();
  const int coarse = opening_coarse(canvas());
  std::optional<std::string> first_reason;  // the first that names a segment, else P0's
  const auto open = [&](int k, const std::string& why) {
    Document d = start;
    d.selected = k;
    d.group.clear();
    if (history_.can_undo()) history_.commit(std::move(d));
    else history_ = History(std::move(d));  // opening: not an undo step
    changed_document();
    message = "opened on " + point_name(k) + ": " + why;
    return std::optional<int>(k);
  };
  int most = 0, most_at = -1;  // the largest region below kOpeningCells, if none reaches it
  for (int k = 0; k < m; ++k) {
    if (!movable(k)) continue;  // a font source's line point: not the designer's
    Document d = start;
    d.selected = k;
    d.group.clear();
    const std::vector<RegionRequest> q = requests_of(d, false, coarse);
    if (q.size() != 1) continue;
    try {
      const std::vector<RegionResult> r = compute_regions(start.spline, q, &memo());
      const int cells = monotone_count(r.front());
      if (cells >= kOpeningCells) return open(k, "the first point whose region shows in this view");
      if (cells > most) most = cells, most_at = k;
      if (cells > 0) continue;
      // The reason of the first point whose region is judged on segments it
      // does not wrap (a closed curve's whole period says nothing about one).
      if (!first_reason || first_reason->find(kPeriodReason) != std::string::npos)
        if (auto why = region_reason(memo().make(start.spline, q.front()), r.front()))
          if (*why = cli::show_fields(*why); !first_reason || why->find(kPeriodReason) == std::string::npos)
            first_reason = std::move(why);
    } catch (const InputError& e) {
      if (!first_reason) first_reason = cli::shown_message(e);
    }
  }
  if (most_at >= 0) return open(most_at, "the largest region in this view, and a small one");
  region();  // P0's region now, so that its bare reason does not replace this line
  message = "no point has a region in this view: " + first_reason.value_or("(no reason found)");
  return std::nullopt;
}

std::optional<SegmentRange> Editor::closed_support() const {
  const Document& d = doc();
  if (!d.spline.closed() || d.segments || d.split || d.chain || d.all_points || d.kcurve) return std::nullopt;
  const std::vector<RegionRequest> q = region_requests();
  if (q.size() != 1) return std::nullopt;
  return q.front().segments;
}

FixRequirement Editor::fix_requirement() const {
  const Document& d = doc();
  FixRequirement r;
  if (d.split) {
    r.kind = FixRequirement::Kind::split;
    r.split = *d.split;
  } else if (d.chain) {
    r.kind = FixRequirement::Kind::each_piece;
  } else {
    r.kind = d.mode == Mode::cmr ? FixRequirement::Kind::cmr : FixRequirement::Kind::cmrwi;
  }
  r.segments = d.segments;  // the judged range only (fix and snap)
  return r;
}

std::vector<int> Editor::glyph_fix_points() const {
  if (curves.empty()) return {};
  const OpenedCurve& c = curves[active_curve];
  const BSpline& s = doc().spline;
  const int m = static_cast<int>(c.font_point.size());
  if (m == 0 || m != s.unique_point_count()) return {};
  FixRequirement each;
  each.kind = FixRequirement::Kind::extrema_at_nodes;
  const SplineAnalysis a = analyze(s, fix_analyze_options(each, doc().max_depth));
  std::vector<bool> on_failing(m, false);
  for (int i = a.range.first; i <= a.range.last; ++i) {
    const Curvature k = a.segments[i].monotonicity.curvature;
    if (!a.shapes[i].pole && (k == Curvature::increasing || k == Curvature::decreasing || k == Curvature::constant))
      continue;
    for (int p : segment_points(s, s.segments()[i])) on_failing[p % m] = true;
  }
  std::vector<int> out;
  for (int k = 0; k < m; ++k) {
    if (c.font_point[k] < 0 || !on_failing[k]) continue;
    const bool line_end = c.node[k] && (c.font_point[(k + 1) % m] < 0 || c.font_point[(k + m - 1) % m] < 0);
    if (!line_end) out.push_back(k);
  }
  return out;
}

bool Editor::fix_curve() {
  FixRequest q;
  q.requirement = fix_requirement();
  q.keep = Keep::g1;
  q.max_seconds = kFixSeconds;
  // A glyph in chain mode: only the designer's points that act on a failing
  // segment, and no node at an end of a line (as `cmr fix FONT.ufo
  // --glyph`), so lines stay lines.
  if (q.requirement.kind == FixRequirement::Kind::each_piece && q.requirement.cuts.empty())
    q.points = glyph_fix_points();
  return apply_fix(q, "fix");
}

bool Editor::fix_on_grid() {
  finish_animation();
  const std::string what = "fix on the grid (" + grid_fix_gates + ")";
  if (curves.empty() || curves[active_curve].font_point.empty()) {
    message = what + ": for a font's glyph (cmr edit FONT.ufo --glyph NAME)";
    return false;
  }
  const OpenedCurve& oc = curves[active_curve];
  const Document& d = doc();
  if (static_cast<int>(oc.font_point.size()) != d.spline.unique_point_count() || d.spline.knots() != oc.spline.knots()) {
    message = what + ": the contour's knots or points changed (a knot operation); undo it first";
    return false;
  }
  import::Glyph g;
  g.name = oc.name;
  // What report::fix_glyph reads of a contour: its index, spline, names,
  // font points and nodes (the joint and source fields are for locating
  // findings in a file, not for fixing).
  g.contours.push_back(import::Contour{oc.contour, d.spline, oc.point_names, oc.font_point, oc.node, {}, {}, {}});
  report::GlyphFixOptions o;
  o.judge.max_depth = d.max_depth;
  o.grid = grid > 0 ? grid : 1;  // a binary font's units: its grid too
  o.glyph_work = report::kReportGlyphWork;  // the report's fix search: the editor finds what the report finds
  o.guard_seconds = kFixSeconds;
  std::vector<report::ContourFix> fixes;
  try {
    report::parse_require_list(grid_fix_gates, o.judge);
    fixes = report::fix_glyph(g, o);
  } catch (const InputError& e) {
    message = what + ": " + cli::shown_message(e);
    return false;
  }
  if (fixes.empty()) {
    message = what + ": nothing to fix";
    return false;
  }
  const report::ContourFix& f = fixes.front();
  if (f.already) {
    message = what + ": " + oc.name + " already meets it (nothing moved)";
    return true;
  }
  if (!f.fixed) {
    message = what + ": " + cli::show_fields(f.reason);
    return false;
  }
  BSpline to = d.spline;
  for (const PointMove& m : f.moves) to = to.with_point(m.point, m.to);
  std::string rejudged;
  for (const report::GateCount& gc : f.rejudged)
    rejudged += (rejudged.empty() ? "" : ", ") + gc.check + " " + std::to_string(gc.before) + " -> " +
                std::to_string(gc.after);
  char largest[64];
  double most = 0;
  for (const PointMove& m : f.moves) most = std::max(most, m.distance);
  std::snprintf(largest, sizeof largest, "%.4g", most);
  message = what + ": moved " + std::to_string(f.moves.size()) + " point(s) onto the grid, the largest by " + largest +
            " (cmr fix FONT.ufo --glyph's search); violations " + rejudged;
  animation_ = Animation{d.spline, to, 0, "fix" + std::to_string(++fix_serial_)};
  history_.seal();
  advance_animation(0);
  animation_->first = true;
  return true;
}

bool Editor::snap_selected() {
  finish_animation();
  const Document& d = doc();
  const std::string what = "snap " + point_name(d.selected);
  if (!d.group.empty()) {
    message = what + ": it has a rigid group, and snap moves the point alone (clear the group, or use fix)";
    return false;
  }
  FixRequest q;
  q.requirement = fix_requirement();
  q.points = {d.selected};
  q.keep = d.chain ? Keep::g1 : Keep::none;
  q.max_seconds = kFixSeconds;
  return apply_fix(q, what);
}

bool Editor::apply_fix(const FixRequest& request, const std::string& what) {
  finish_animation();
  const Document& d = doc();
  const std::string req = to_string(request.requirement);
  if (d.kcurve && !d.kcurve->modifying) {
    message = what + ": the kappa-curve is still being clicked (kcurve modify first)";
    return false;
  }
  if (d.spline.closed() && !request.requirement.segments && (request.requirement.kind == FixRequirement::Kind::cmr ||
                            request.requirement.kind == FixRequirement::Kind::cmrwi)) {
    message = what + ": a closed curve's curvature is never monotone over its whole period, and " + req +
              " judges every segment (use a split joint, or chain mode's each-piece)";
    return false;
  }
  FixResult r;
  std::string via;
  try {
    // Chain mode's each-piece with every joint a cut asks that every
    // segment's curvature be monotone on its own: what the report's
    // curvature-extrema-at-nodes asks, but searched as a whole (every step
    // analyses the whole spline and must lower its count). On a glyph that
    // search found nothing in 5 s where the per-segment search of
    // curvature-extrema-at-nodes (each failing segment repaired by the points
    // that act on it, judged alone) finds a fix at once (issue 36). So fix
    // searches per segment first and takes the result when each-piece itself
    // holds on it; otherwise the each-piece search runs as before.
    const bool per_segment = request.requirement.kind == FixRequirement::Kind::each_piece &&
                             request.requirement.cuts.empty() && !request.judge && !request.together;
    if (per_segment) {
      FixRequest local = request;
      local.requirement.kind = FixRequirement::Kind::extrema_at_nodes;
      r = fix(d.spline, local);
      if (r.fixed && !r.already && r.spline && requirement_holds(*r.spline, request.requirement, request.max_depth))
        via = " (searched segment by segment, as curvature-extrema-at-nodes; each-piece holds)";
      else
        r = FixResult{};
    }
    if (via.empty()) r = fix(d.spline, request);
  } catch (const InputError& e) {
    message = what + ": " + cli::shown_message(e);
    return false;
  }
  if (r.already) {
    message = what + ": the curve already meets " + req + " (nothing moved)";
    return true;
  }
  if (!r.fixed || !r.spline) {
    message = what + " (" + req + "): " + (r.reason.empty() ? "no certified fix" : cli::show_fields(r.reason));
    return false;
  }
  // A glyph's lines stay lines: no fix moves a line's added point or a node
  // at an end of a line.
  const std::vector<int>* fp = curves.empty() ? nullptr : &curves[active_curve].font_point;
  const int m = fp ? static_cast<int>(fp->size()) : 0;
  if (m > 0 && m == r.spline->unique_point_count())
    for (int k = 0; k < m; ++k) {
      if (r.spline->points()[k] == d.spline.points()[k]) continue;
      const bool added = (*fp)[k] < 0;
      const bool line_end = !added && curves[active_curve].node[k] && ((*fp)[(k + 1) % m] < 0 || (*fp)[(k + m - 1) % m] < 0);
      if (!added && !line_end) continue;
      message = what + " (" + req + "): the nearest fix moves " + point_name(k) +
                (added ? ", a straight piece's added point," : ", a node at an end of a line,") +
                " and would bend the line (chain mode's fix keeps lines)";
      return false;
    }
  std::string moves;
  for (std::size_t i = 0; i < r.moves.size(); ++i) {
    if (i == 3) {
      moves += " and " + std::to_string(r.moves.size() - 3) + " more";
      break;
    }
    char one[160];
    std::snprintf(one, sizeof one, "%s%s by %.4g (%.2g%% of the curve size)", i ? ", " : "",
                  point_name(r.moves[i].point).c_str(), r.moves[i].distance,
                  r.size > 0 ? 100 * r.moves[i].distance / r.size : 0.0);
    moves += one;
  }
  message = what + " (" + req + "): moved " + moves + "; certified by analyze" +
            (d.segments ? " (every segment judged, as cmr fix)" : "") + via;
  animation_ = Animation{d.spline, *r.spline, 0, "fix" + std::to_string(++fix_serial_)};
  history_.seal();     // the fix is an undo step of its own
  advance_animation(0);  // its first frame holds the state before it for undo
  animation_->first = true;
  return true;
}

void Editor::advance_animation(double seconds) {
  if (!animation_) return;
  Animation& a = *animation_;
  if (a.changes >= 0 && history_.changes() != a.changes) {
    a.t = 1;  // another change came between the frames: the fix lands at once
    a.key.clear();
  } else {
    // The first frame after the fix began also waited for its search: one
    // frame at 30 per second instead, so the move is seen from its start.
    const double dt = a.first ? std::min(std::max(0.0, seconds), 1.0 / 30) : std::max(0.0, seconds);
    a.first = false;
    a.t = std::min(1.0, a.t + dt / kFixAnimationSeconds);
  }
  Document next = doc();
  if (a.t >= 1) {
    next.spline = a.to;  // exactly the certified spline
  } else {
    const double e = a.t * a.t * (3 - 2 * a.t);  // smoothstep
    BSpline s = a.from;
    for (int k = 0; k < s.unique_point_count(); ++k) {
      const Vec2 p = a.from.points()[k], q = a.to.points()[k];
      if (p != q) s = s.with_point(k, p + (q - p) * e);
    }
    next.spline = std::move(s);
  }
  history_.commit(std::move(next), a.key);
  changed_document();
  if (a.t >= 1) {
    history_.seal();
    animation_.reset();
    region_stale_ = true;  // full resolution again
  } else {
    a.changes = history_.changes();
  }
}

void Editor::finish_animation() {
  if (!animation_) return;
  animation_->first = false;  // not the first frame's one step: all the way
  advance_animation(kFixAnimationSeconds);
}

}  // namespace cmr::edit
