#include "report/severity.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <set>

#include "bezierize/extract.hpp"
#include "design/fix.hpp"
#include "report/batch.hpp"
#include "report/certified_fix.hpp"
#include "report/contour_moves.hpp"
#include "report/glyph_fix.hpp"
#include "spline/errors.hpp"
#include "spline/fields.hpp"
#include "spline/format.hpp"

namespace cmr::report {

bool has_severity(const Gate& g) {
  return g.kind == Gate::Kind::extrema_at_nodes || g.kind == Gate::Kind::max_extrema_per_segment ||
         g.kind == Gate::Kind::g2_at_smooth_nodes;
}

namespace {

/// The same place: the segment of an extremum, the joint of a jump.
bool same_place(const GateViolation& a, const GateViolation& b) {
  return a.segment >= 0 ? a.segment == b.segment : a.joint == b.joint && b.segment < 0;
}

/// How many violations of the judge's one gate lie at `place` on `spline`;
/// with `first` >= 0 judged on the window of the place alone (its segment,
/// or the two segments meeting at its joint, starting at segment `first`):
/// the gate reads a segment's extrema from that segment and a joint's
/// curvatures from its two sides. An extremum gate on a segment's window
/// counts the extrema alone (segment_extrema_count: the same number).
int violations_at(const BSpline& spline, const ReportOptions& judge, const GateViolation& place, int first) {
  try {
    GateViolation here = place;
    std::optional<BSpline> w;
    if (first >= 0) {
      here = GateViolation{};
      if (place.segment >= 0) here.segment = 0;
      else here.joint = 1;
      w = segments_window(spline, first, place.segment >= 0 ? 1 : 2);
      const Gate& gate = judge.gates[0];
      const bool extrema = gate.kind == Gate::Kind::extrema_at_nodes || gate.kind == Gate::Kind::max_extrema_per_segment;
      if (place.segment >= 0 && extrema)
        if (const std::optional<int> count = segment_extrema_count(*w, judge))
          return gate.kind == Gate::Kind::extrema_at_nodes ? *count : (*count > gate.max_extrema ? 1 : 0);
    }
    const SplineReport r = gate_report(w ? *w : spline, judge);
    return static_cast<int>(std::count_if(r.gates[0].violations.begin(), r.gates[0].violations.end(),
                                          [&](const GateViolation& x) { return same_place(here, x); }));
  } catch (const InputError&) {
    return std::numeric_limits<int>::max() / 2;
  }
}

/// Whether a segment is a straight piece: its Bezier points exactly
/// collinear (contour_of's test).
bool straight_piece(const std::vector<Vec2>& b) {
  for (const Vec2 q : b)
    if (det(q - b.front(), b.back() - b.front()) != 0) return false;
  return true;
}

/// A g2 jump where a straight piece meets a curve (a stem meeting a bowl).
/// The line's curvature is exactly 0, so the jump goes only when the curve's
/// end curvature is exactly 0 too: its Bezier points B0 (the node), B1 (the
/// handle, on the line's tangent) and B2 exactly collinear. A search by
/// grid cells and rays does not hit that line; this constructs the moves:
/// each point the designer may move (`moves`) that shifts B2 (and not B0,
/// B1), moved the least that puts B2 exactly on the tangent line (a free
/// point along the line's normal; a handle of an exactly smooth node along
/// its own tangent, so the node stays smooth), for a tangent parallel to an
/// axis (a vertical or horizontal stem: the coordinate is then set exactly);
/// for a slanted line (an italic stem), the point that is B2 itself moved
/// to B0 + t w (w: u, or its primitive integer direction), t the multiple of
/// 2^-20 nearest the foot of its perpendicular (exactly on the line in
/// doubles, at most |w| 2^-21 from the foot; a smooth node's handle there is
/// left to the search, as it would have to lie on two lines). Each candidate is re-judged by the gate on the
/// whole spline; the least that passes. nullopt: not such a joint (the
/// search decides); a SeverityMove without `moved`: such a joint, and no
/// construction passes ("none found").
std::optional<SeverityMove> line_join_move(const BSpline& spline, const ReportOptions& judge, const GateViolation& v,
                                           const ContourMoves& moves, double max_move) {
  if (v.segment >= 0 || v.joint < 0 || spline.is_rational() || spline.degree() < 2) return std::nullopt;
  const int n = spline.segment_count(), d = spline.degree();
  if (v.joint == 0 && !spline.closed()) return std::nullopt;
  const int right = v.joint % n, left = (right + n - 1) % n;
  const Segment& ls = spline.segments()[static_cast<std::size_t>(left)];
  const Segment& rs = spline.segments()[static_cast<std::size_t>(right)];
  const std::vector<Vec2> L = bezier_segment(spline, ls).points, R = bezier_segment(spline, rs).points;
  const bool line_left = straight_piece(L), line_right = straight_piece(R);
  if (line_left == line_right) return std::nullopt;
  const Segment& curve = line_left ? rs : ls;
  auto ends = [&](const BSpline& s) {  // B0, B1, B2 of the curve at the joint
    const std::vector<Vec2> b = bezier_segment(s, curve).points;
    return line_left ? std::array<Vec2, 3>{b[0], b[1], b[2]} : std::array<Vec2, 3>{b[d], b[d - 1], b[d - 2]};
  };
  const std::array<Vec2, 3> e = ends(spline);
  const Vec2 u = e[1] - e[0];
  if (u == Vec2(0.0)) return std::nullopt;
  SeverityMove best;
  // A slanted line: B2 goes to B0 + t u with t a multiple of 2^-20 nearest
  // the foot of the perpendicular (exact in doubles for font coordinates),
  // moved by a point that is B2 itself (weight 1); a smooth node's handle,
  // which would have to meet two lines at once, is left to the search.
  const bool slanted = u.x != 0 && u.y != 0;
  const int axis = u.x == 0 ? 0 : 1;  // the coordinate B2 must share with B0 (axis-parallel line)
  const double limit = max_move > 0 ? max_move : curve_size(spline);
  const int m = spline.unique_point_count();
  const std::vector<Vec2>& P = spline.points();
  const import::Contour contour = contour_of(spline, {});  // its nodes
  auto coord = [](Vec2 p, int a) { return a == 0 ? p.x : p.y; };
  bool acts = false;  // some allowed point moves B0, B1 or B2
  for (int k : segment_points(spline, curve)) {
    if (!moves.movable(k)) continue;
    // A handle next to an exactly smooth node slides along its tangent;
    // next to a nearly smooth one it is left to the search's ties.
    Vec2 dir(0.0);
    int tie = -1;
    bool skip = false;
    for (int side : {-1, 1}) {
      if (!spline.closed() && (k + side < 0 || k + side >= m || k + 2 * side < 0 || k + 2 * side >= m)) continue;
      const int node = (k + side + m) % m, other = (k + 2 * side + m) % m;
      if (!contour.node[static_cast<std::size_t>(node)]) continue;
      const Vec2 a = P[k] - P[node], b = P[other] - P[node];
      if (a == Vec2(0.0) || b == Vec2(0.0) || !(dot(a, b) < 0)) continue;
      const double cross = det(a, b);
      if (cross == 0) {
        if (tie >= 0) skip = true;  // held by two tangents
        tie = node, dir = a / std::hypot(a.x, a.y);
      } else if (std::abs(cross) <= 1e-9 * std::hypot(a.x, a.y) * std::hypot(b.x, b.y)) {
        skip = true;
      }
    }
    const bool slide = tie >= 0;
    if (skip) continue;  // held, or left to the search's ties
    // How B2 depends on P_k (affinely, the same weight in x and y), and
    // that B0 and B1 do not.
    const std::array<Vec2, 3> probe = ends(spline.with_point(k, P[k] + Vec2(1.0, 1.0)));
    if (probe[0] != e[0] || probe[1] != e[1]) {
      acts = true;
      continue;
    }
    const double c = probe[2].x - e[2].x;
    if (!(std::abs(c) > 1e-12)) continue;
    acts = true;
    if (slanted) {
      // A smooth node's handle would have to stay on its tangent too: left
      // to the search (it may act, so the finding is not "no allowed move").
      if (slide || c != 1 || probe[2].y - e[2].y != 1) continue;  // or B2 is not P_k itself
      // Along the primitive direction of an integer u (so a foot on the
      // font's grid is found exactly).
      Vec2 w = u;
      if (u.x == std::floor(u.x) && u.y == std::floor(u.y) && std::abs(u.x) < 0x1p52 && std::abs(u.y) < 0x1p52)
        w = u / static_cast<double>(std::gcd(static_cast<long long>(std::abs(u.x)), static_cast<long long>(std::abs(u.y))));
      const double foot = dot(e[2] - e[0], w) / dot(w, w);
      const double t = std::ldexp(std::nearbyint(std::ldexp(foot, 20)), -20);
      const Vec2 to = P[k] + (e[0] + t * w - e[2]);
      BSpline moved = spline.with_point(k, to);
      const std::array<Vec2, 3> f = ends(moved);
      if (det(f[1] - f[0], f[2] - f[0]) != 0) continue;  // not exactly on the line in doubles
      const double dist = std::hypot(to.x - P[k].x, to.y - P[k].y);
      if (dist > limit || dist >= best.distance) continue;
      ++best.evaluations;
      if (violations_at(moved, judge, v, -1) != 0) continue;
      best.distance = dist;
      best.moved = std::move(moved);
      continue;
    }
    const double gap = coord(e[0], axis) - coord(e[2], axis);  // B2 must move by this along the axis
    Vec2 delta(0.0);
    if (slide) {
      const double along = coord(dir, axis);
      if (!(std::abs(along) > 1e-12)) continue;
      delta = (gap / (c * along)) * dir;
    } else {
      (axis == 0 ? delta.x : delta.y) = gap / c;
    }
    Vec2 to = P[k] + delta;
    // Exactly on the line: the coordinate nudged by ulps until B2's equals B0's.
    BSpline moved = spline.with_point(k, to);
    // (Not a slide: nudged on one axis alone it would leave its tangent.)
    for (int tries = 0; !slide && tries < 8 && coord(ends(moved)[2], axis) != coord(e[0], axis); ++tries) {
      const double off = coord(ends(moved)[2], axis) - coord(e[0], axis);
      double& x = axis == 0 ? to.x : to.y;
      x = std::nextafter(x, (off > 0) == (c > 0) ? -HUGE_VAL : HUGE_VAL);
      moved = spline.with_point(k, to);
    }
    const std::array<Vec2, 3> f = ends(moved);
    if (det(f[1] - f[0], f[2] - f[0]) != 0) continue;
    const double dist = std::hypot(to.x - P[k].x, to.y - P[k].y);
    if (dist > limit || dist >= best.distance) continue;
    if (slide && !(dot(to - P[tie], dir) > 0)) continue;  // the handle would reach or pass its node
    ++best.evaluations;
    if (violations_at(moved, judge, v, -1) != 0) continue;
    best.distance = dist;
    best.moved = std::move(moved);
  }
  best.none_allowed = !acts;  // no allowed move reaches B0, B1 or B2: none can remove the jump
  return best;
}

}  // namespace

SeverityMove severity_move(const BSpline& spline, const Gate& gate, const GateViolation& v,
                           const ReportOptions& options, double max_move) {
  const ContourMoves moves = contour_moves(contour_of(spline, {}));
  return severity_move(spline, gate, v, options, moves, max_move);
}

SeverityMove severity_move(const BSpline& spline, const Gate& gate, const GateViolation& v,
                           const ReportOptions& options, const ContourMoves& moves, double max_move,
                           long max_evaluations, double max_seconds) {
  const int n = spline.segment_count();
  // The place's segments [a, a + count): v's segment, or the two meeting at v's joint.
  int a = v.segment, count = 1;
  if (v.segment < 0) {
    if (v.joint < 0 || (v.joint == 0 && !spline.closed())) return {};
    a = v.joint > 0 ? v.joint - 1 : n - 1, count = 2;
  }
  std::set<int> points;
  for (int i = a; i < a + count; ++i)
    for (int k : segment_points(spline, spline.segments()[static_cast<std::size_t>(i % n)])) points.insert(k);
  const ReportOptions judge = judge_only(options, gate);
  FixRequest q = gate_fix_request(gate, options.max_depth, max_seconds);
  q.max_evaluations = max_evaluations;
  q.points.assign(points.begin(), points.end());
  // The designer's moves only (report/contour_moves.hpp): a line's points
  // stay, smooth nodes keep G1. None of the place's points may move: no
  // allowed move removes the finding.
  if (!moves.restrict(q)) {
    SeverityMove none;
    none.none_allowed = true;
    return none;
  }
  // A stem meeting a bowl: constructed, not searched (line_join_move).
  if (gate.kind == Gate::Kind::g2_at_smooth_nodes)
    if (std::optional<SeverityMove> j = line_join_move(spline, judge, v, moves, max_move)) return *j;
  q.max_move = max_move;
  // The search judges each candidate on the place's own segments (a window:
  // the extrema of a segment are read from it, a joint's curvatures from
  // its two sides), its answer on the whole spline; where they disagree, or
  // with --segments (a range of the whole spline), the search judges the
  // whole spline.
  // Empty: judge the whole spline (the window's answer did not hold on it).
  long evaluations = 0;  // of both searches
  auto search = [&](int first) -> std::optional<SeverityMove> {
    q.judge = [judge, v, first](const BSpline& s) { return violations_at(s, judge, v, first); };
    try {
      FixResult f = fix(spline, q);
      evaluations += f.evaluations;
      if (!f.fixed && !f.already) {
        SeverityMove none;
        none.none_allowed = f.nothing_moves;
        return none;
      }
      if (first >= 0 && violations_at(*f.spline, judge, v, -1) != 0) return std::nullopt;
      SeverityMove found;
      found.distance = f.already ? 0 : f.max_distance;
      found.moved = std::move(f.spline);
      return found;
    } catch (const InputError&) {
      if (first >= 0) return std::nullopt;
      return SeverityMove{};
    }
  };
  std::optional<SeverityMove> out;
  if (!options.segments && count < n) out = search(a);
  if (!out) out = search(-1);
  out->evaluations = evaluations;
  return *out;
}

namespace {

/// The memo's key: the spline's degree, closedness, knots, points and
/// weights as bytes (bit for bit: -0.0 and 0.0 differ, as they may in a search).
std::string memo_key(const BSpline& s) {
  std::string key;
  auto put = [&key](const void* p, std::size_t n) { key.append(static_cast<const char*>(p), n); };
  const int head[2] = {s.degree(), s.closed() ? 1 : 0};
  put(head, sizeof head);
  put(s.knots().data(), s.knots().size() * sizeof(double));
  key.push_back('|');
  put(s.points().data(), s.points().size() * sizeof(Vec2));
  key.push_back('|');
  put(s.weights().data(), s.weights().size() * sizeof(double));
  return key;
}

}  // namespace

std::optional<std::vector<SeverityMemo::Entry>> SeverityMemo::find(const BSpline& spline) const {
  const std::string key = memo_key(spline);
  const std::lock_guard lock(mutex_);
  const auto it = entries_.find(key);
  if (it == entries_.end()) return std::nullopt;
  return it->second;
}

void SeverityMemo::store(const BSpline& spline, std::vector<Entry> entries) {
  std::string key = memo_key(spline);
  const std::lock_guard lock(mutex_);
  entries_.emplace(std::move(key), std::move(entries));
}

void assess_severity(SplineReport& r, const ReportOptions& options, SeverityMemo* memo) {
  if (options.min_severity < 0 || !r.spline || !r.error.empty()) return;
  std::size_t count = 0;
  for (const GateResult& g : r.gates)
    if (has_severity(g.gate)) count += g.violations.size();
  std::optional<std::vector<SeverityMemo::Entry>> known;
  if (memo != nullptr && count > 0) known = memo->find(*r.spline);
  if (known && known->size() != count) known.reset();  // cannot happen for one run's options; be safe
  std::vector<SeverityMemo::Entry> found;
  std::optional<ContourMoves> moves;  // the same rules for every finding of the spline
  std::size_t index = 0;
  for (GateResult& g : r.gates) {
    if (!has_severity(g.gate)) continue;
    for (GateViolation& v : g.violations) {
      if (known) {
        v.severity = (*known)[index].severity;
        v.severity_outcome = (*known)[index].outcome;
      } else {
        if (!moves) moves = contour_moves(contour_of(*r.spline, {}));
        const SeverityMove first = severity_move(*r.spline, g.gate, v, options, *moves);
        v.severity = first.distance;
        // Coarse to fine near the threshold: the search's first grids scale
        // with the curve, and a move below the threshold can lie between their
        // cells; a search within the threshold alone looks there.
        const double t = options.min_severity;
        if (!first.none_allowed && t > 0 && v.severity >= t && (v.severity < kRefineBelow * t || !std::isfinite(v.severity)))
          v.severity = std::min(v.severity, severity_move(*r.spline, g.gate, v, options, *moves, t).distance);
        v.severity_outcome = std::isfinite(v.severity) ? SeverityOutcome::moved
                             : first.none_allowed       ? SeverityOutcome::no_allowed_move
                                                        : SeverityOutcome::none_found;
        found.push_back({v.severity, v.severity_outcome});
      }
      ++index;
      v.info = v.severity < options.min_severity && !options.strict;
    }
  }
  if (memo != nullptr && !known && count > 0) memo->store(*r.spline, std::move(found));
  const bool gates_pass = std::all_of(r.gates.begin(), r.gates.end(), [](const GateResult& g) { return g.pass(); });
  // report.pass is the requirement's verdict (when one is asked) and every gate's.
  const bool requirement = r.requirement_pass || (!options.require && !options.gates.empty());
  r.pass = requirement && gates_pass;
}

void set_severity_options(ReportOptions& options, std::optional<double> min_severity, bool severity, bool strict) {
  if (min_severity && !(*min_severity >= 0 && std::isfinite(*min_severity)))
    throw InputFieldError(field("min_severity") + ": " + format_number(*min_severity) + " is not a distance >= 0");
  if (!severity && min_severity) throw InputFieldError(field("no_severity") + ": not with " + field("min_severity"));
  if (strict && !severity)
    throw InputFieldError(field("strict") + ": not with " + field("no_severity") + " (no finding is info)");
  options.min_severity = min_severity.value_or(-1);
  options.font_severity = severity;
  options.strict = strict;
}

}  // namespace cmr::report
