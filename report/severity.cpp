#include "report/severity.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <set>

#include "bezierize/fix.hpp"
#include "report/batch.hpp"
#include "report/certified_fix.hpp"
#include "report/contour_moves.hpp"
#include "report/glyph_fix.hpp"
#include "spline/errors.hpp"

namespace cmr::report {
namespace {

bool has_severity(const Gate& g) {
  return g.kind == Gate::Kind::extrema_at_nodes || g.kind == Gate::Kind::max_extrema_per_segment ||
         g.kind == Gate::Kind::g2_at_smooth_nodes;
}

/// The same place: the segment of an extremum, the joint of a jump.
bool same_place(const GateViolation& a, const GateViolation& b) {
  return a.segment >= 0 ? a.segment == b.segment : a.joint == b.joint && b.segment < 0;
}

/// Segments [first, first + count) of `spline` (indices taken cyclically on
/// a closed spline) as an open spline of their own, with the same polar
/// knots and control points (for a closed spline, its periodic extension):
/// each of its segments is the same polynomial piece as the spline's.
BSpline window(const BSpline& spline, int first, int count) {
  const int d = spline.degree(), n = spline.segment_count(), m = spline.unique_point_count();
  // A closed spline's segment i + n is segment i one period on: its span is m further.
  auto span = [&](int i) { return spline.segments()[static_cast<std::size_t>(((i % n) + n) % n)].span + (i >= n ? m : 0); };
  const int j0 = span(first), j1 = span(first + count - 1);
  std::vector<double> period;
  if (spline.closed()) period = spline.period_knots();
  const double T = spline.closed() ? period.back() - period.front() : 0;
  auto knot = [&](int k) {
    if (!spline.closed()) return spline.knots()[static_cast<std::size_t>(k)];
    const int i = k - d + 1;  // the periodic extension's index (BSpline::make_closed)
    const int q = i >= 0 ? i / m : -((-i + m - 1) / m);
    return period[static_cast<std::size_t>(i - q * m)] + q * T;
  };
  std::vector<double> knots, weights;
  std::vector<Vec2> points;
  for (int k = j0 - d + 1; k <= j1 + d; ++k) knots.push_back(knot(k));
  for (int k = j0 - d + 1; k <= j1 + 1; ++k) {
    const int p = spline.closed() ? ((k % m) + m) % m : k;
    points.push_back(spline.points()[static_cast<std::size_t>(p)]);
    if (spline.is_rational()) weights.push_back(spline.weight(p));
  }
  return BSpline::make(d, std::move(knots), std::move(points), spline.name(), std::move(weights));
}

/// How many violations of the judge's one gate lie at `place` on `spline`;
/// with `first` >= 0 judged on the window of the place alone (its segment,
/// or the two segments meeting at its joint, starting at segment `first`):
/// the gate reads a segment's extrema from that segment and a joint's
/// curvatures from its two sides.
int violations_at(const BSpline& spline, const ReportOptions& judge, const GateViolation& place, int first) {
  try {
    GateViolation here = place;
    std::optional<BSpline> w;
    if (first >= 0) {
      here = GateViolation{};
      if (place.segment >= 0) here.segment = 0;
      else here.joint = 1;
      w = window(spline, first, place.segment >= 0 ? 1 : 2);
    }
    const SplineReport r = judged_report(w ? *w : spline, judge);
    return static_cast<int>(std::count_if(r.gates[0].violations.begin(), r.gates[0].violations.end(),
                                          [&](const GateViolation& x) { return same_place(here, x); }));
  } catch (const InputError&) {
    return std::numeric_limits<int>::max() / 2;
  }
}

}  // namespace

SeverityMove severity_move(const BSpline& spline, const Gate& gate, const GateViolation& v,
                           const ReportOptions& options, double max_move) {
  const ContourMoves moves = contour_moves(contour_of(spline, {}));
  return severity_move(spline, gate, v, options, moves, max_move);
}

SeverityMove severity_move(const BSpline& spline, const Gate& gate, const GateViolation& v,
                           const ReportOptions& options, const ContourMoves& moves, double max_move) {
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
  FixRequest q = gate_fix_request(gate, options.max_depth, kSeverityFixSeconds);
  q.points.assign(points.begin(), points.end());
  // The designer's moves only (report/contour_moves.hpp): a line's points
  // stay, smooth nodes keep G1. None of the place's points may move: no
  // allowed move removes the finding.
  if (!moves.restrict(q)) {
    SeverityMove none;
    none.none_allowed = true;
    return none;
  }
  q.max_move = max_move;
  // The search judges each candidate on the place's own segments (a window:
  // the extrema of a segment are read from it, a joint's curvatures from
  // its two sides), its answer on the whole spline; where they disagree, or
  // with --segments (a range of the whole spline), the search judges the
  // whole spline.
  // Empty: judge the whole spline (the window's answer did not hold on it).
  auto search = [&](int first) -> std::optional<SeverityMove> {
    q.judge = [judge, v, first](const BSpline& s) { return violations_at(s, judge, v, first); };
    try {
      FixResult f = fix(spline, q);
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
  if (!options.segments && count < n)
    if (auto m = search(a)) return *m;
  return *search(-1);
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

}  // namespace cmr::report
