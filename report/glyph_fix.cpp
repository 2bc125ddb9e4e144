#include "report/glyph_fix.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <utility>
#include <limits>
#include <numeric>
#include <optional>

#include "bezierize/extract.hpp"
#include "report/batch.hpp"
#include "report/certified_fix.hpp"
#include "report/contour_moves.hpp"
#include "report/glyph_bowl.hpp"
#include "report/glyph_chains.hpp"
#include "report/glyph_joins.hpp"
#include "report/glyph_quick.hpp"
#include "report/glyph_settle.hpp"
#include "report/glyph_unfixed.hpp"
#include "report/severity.hpp"
#include "spline/errors.hpp"
#include "spline/format.hpp"

namespace cmr::report {
namespace {

using glyph_detail::Badness;
using glyph_detail::chain_search;
using glyph_detail::exactly_smooth;
using glyph_detail::grid_vector;
using glyph_detail::growing_chain_search;
using glyph_detail::LatticeUnit;
using glyph_detail::QuickJudge;
using glyph_detail::local_judge;
using glyph_detail::badness_of;
using glyph_detail::quick_badness;
using glyph_detail::quick_judge_of;
using glyph_detail::RunJudge;
using glyph_detail::settle_nearer;
using glyph_detail::straight_bezier;
using glyph_detail::straight_segments;
using glyph_detail::extremum_rejects;
using glyph_detail::with_failure_proofs;
using glyph_detail::proves_extremum_violation;
using glyph_detail::snap_by_parts;
using glyph_detail::squared_move;
using glyph_detail::refusal;
using glyph_detail::Work;

/// Violations of every check of `t` on a model (gate_model) built with the
/// options of a set of checks that holds t's (the same model options): the
/// requirement (one when it fails) first, then each gate's count.
std::vector<GateCount> counts_on(const SplineReport& model, const ReportOptions& t) {
  std::vector<GateCount> out;
  if (t.require) out.push_back({to_string(*t.require), model.requirement_pass ? 0 : 1, 0});
  for (const GateResult& g : check_gates(model, t.gates))
    out.push_back({to_string(g.gate), static_cast<int>(g.violations.size()), 0});
  return out;
}

/// Violations of every required check, per check: the requirement (one when
/// it fails) first, then each gate's count.
std::vector<GateCount> judge_counts(const BSpline& s, const ReportOptions& o) { return counts_on(gate_model(s, o), o); }

int total(const std::vector<GateCount>& counts) {
  int n = 0;
  for (const GateCount& c : counts) n += c.before;
  return n;
}

/// The search's guide: the requirement's own fix requirement, else the
/// first failing gate's.
FixRequirement guide(const ReportOptions& o, const SplineReport& r) {
  if (o.require && !r.requirement_pass) return requirement_of(*o.require);
  for (const GateResult& g : r.gates)
    if (!g.pass() && has_point_move_fix(g.gate)) return requirement_of(g.gate);
  return {};
}

/// The moves of contour c (contour_moves), only the points
/// GlyphFixOptions::points names where it names any.
ContourMoves moves_of(const import::Contour& c, const GlyphFixOptions& options) {
  ContourMoves rules = contour_moves(c);
  if (!options.points.empty())
    std::erase_if(rules.points, [&](int k) {
      return std::find(options.points.begin(), options.points.end(), c.point_names[k]) == options.points.end();
    });
  return rules;
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

/// The contour's spline with its distinct points at `pts`.
BSpline with_points(const import::Contour& c, const std::vector<Vec2>& pts) {
  return c.spline.with_points({pts.begin(), pts.begin() + c.spline.unique_point_count()});
}

/// Every node that is exactly smooth in the source (its neighbours on both
/// sides exactly collinear with it, on opposite sides) is so in `s` too.
/// Exact for coordinates below 2^26 (products below 2^53): font units.
bool smooth_kept(const import::Contour& c, const BSpline& s) {
  const int m = static_cast<int>(c.node.size());
  const std::vector<Vec2>& a = c.spline.points();
  const std::vector<Vec2>& b = s.points();
  for (int k = 0; k < m; ++k)
    if (c.node[k] && exactly_smooth(a, m, k) && !exactly_smooth(b, m, k)) return false;
  return true;
}

/// The units of the descent over the movable points (contour_moves).
std::vector<LatticeUnit> lattice_units(const import::Contour& c, const std::vector<int>& movable, double grid) {
  const int m = static_cast<int>(c.node.size());
  const std::vector<Vec2>& p = c.spline.points();
  std::vector<LatticeUnit> out;
  for (int k : movable) {
    LatticeUnit u;
    u.points = {k};
    if (c.node[k]) {
      for (int d : {m - 1, 1}) {
        const int j = (k + d) % m;
        if (!c.node[j] && c.font_point[j] >= 0) u.points.push_back(j);
      }
      out.push_back(u);
      continue;
    }
    int anchors = 0;
    for (int d : {m - 1, 1}) {
      const int j = (k + d) % m;
      if (!c.node[j] || !exactly_smooth(p, m, j)) continue;
      ++anchors;
      const std::optional<Vec2> step = grid_vector(p[k] - p[j], grid);
      if (!step) continue;
      u.slide = true, u.step = *step, u.anchor = j;
    }
    if (anchors >= 2 || (anchors == 1 && !u.slide)) continue;  // held by two tangents, or off its tangent's grid
    out.push_back(u);
  }
  return out;
}

/// A descent on the grid towards passing every check, for the glyphs where
/// the fix of one check breaks another (the nearest fix of each alone lies
/// in a region the other's excludes): from `start`, pattern search over the
/// units' grid coordinates with steps of 32, 16, ..., 1 grid cells, a step
/// taken when the Badness score falls (and every smooth node stays exactly
/// smooth), and where no unit's step lowers it, two neighbouring units one
/// cell each at once. It runs on QuickJudge's estimate where the checks
/// allow (then once more on the exact judge from where that ended, if the
/// exact judge still finds violations) and on the exact report otherwise.
/// Once nothing fails, each unit is pulled back towards the source while
/// everything still passes, so the moves stay as small as this local search
/// finds (a local minimum, not the nearest). The caller re-judges exactly.
std::optional<BSpline> descent_of(const import::Contour& c, const BSpline& start, const std::vector<LatticeUnit>& units,
                                  const ReportOptions& o, const GlyphFixOptions& options, Work& work) {
  const double grid = options.grid > 0 ? options.grid : 1;
  if (units.empty()) return std::nullopt;
  const std::vector<Vec2>& src = c.spline.points();
  const double max_move = options.max_move > 0 ? options.max_move : std::numeric_limits<double>::infinity();
  const std::optional<QuickJudge> quick = quick_judge_of(c.spline, o);
  const double size = curve_size(c.spline);  // the g2 excess's scale at a line join (as QuickJudge's)
  auto spline_of = [&](const std::vector<Vec2>& pts) { return with_points(c, pts); };
  // Badness of a position (nullopt: not allowed), exact or quick.
  auto allowed = [&](const std::vector<Vec2>& pts) {
    for (int k = 0; k < c.spline.unique_point_count(); ++k)
      if (std::hypot(pts[k].x - src[k].x, pts[k].y - src[k].y) > max_move) return false;
    return smooth_kept(c, spline_of(pts));
  };
  const long segments = c.spline.segment_count();
  auto score_of = [&](const std::vector<Vec2>& pts, bool exact) -> std::optional<Badness> {
    if (!allowed(pts)) return std::nullopt;
    work.charge(segments);
    try {
      const BSpline s = spline_of(pts);
      return exact || !quick ? badness_of(gate_report(s, o), o, size) : quick_badness(s, *quick);
    } catch (const InputError&) {
      return std::nullopt;
    }
  };
  // A step from `at` (whose badness is `now`) to `t`: t's badness where it
  // is lower, else nullopt. Exactly, a step that changes a run of segments
  // is judged on the run alone (RunJudge): t's violations are at's less
  // the run's there plus the run's here, and it is lower exactly when the
  // run's is. The run's badness at `at` is kept until `at` moves.
  const RunJudge runs(c.spline, o);
  std::map<std::pair<int, int>, std::optional<Badness>> at_runs;
  auto run_badness = [&](const std::vector<Vec2>& pts, const RunJudge::Run& r) -> std::optional<Badness> {
    work.charge(r.length + 2);  // the run's window
    try {
      return badness_of(runs.report(spline_of(pts), r), o, size);
    } catch (const InputError&) {
      return std::nullopt;
    }
  };
  auto step = [&](const std::vector<Vec2>& at, const std::vector<Vec2>& t, const Badness& now,
                  bool exact) -> std::optional<Badness> {
    const std::optional<RunJudge::Run> r = exact || !quick ? runs.run(at, t) : std::nullopt;
    if (!r) {
      const std::optional<Badness> b = score_of(t, exact);
      if (b && b->score() < now.score()) return b;
      return std::nullopt;
    }
    if (!allowed(t)) return std::nullopt;
    const auto key = std::make_pair(r->first, r->length);
    if (!at_runs.count(key)) at_runs[key] = run_badness(at, *r);
    const std::optional<Badness> was = at_runs[key], here = run_badness(t, *r);
    if (!was || !here || !(here->score() < was->score())) return std::nullopt;
    return Badness{now.count - was->count + here->count, now.excess - was->excess + here->excess};
  };
  // Whether `t` passes, `at` passing: on the run alone where RunJudge allows.
  auto still_passes = [&](const std::vector<Vec2>& at, const std::vector<Vec2>& t, bool exact) {
    const std::optional<RunJudge::Run> r = exact || !quick ? runs.run(at, t) : std::nullopt;
    if (!r) {
      const std::optional<Badness> b = score_of(t, exact);
      return b && b->count == 0;
    }
    const std::optional<Badness> here = allowed(t) ? run_badness(t, *r) : std::nullopt;
    return here && here->count == 0;
  };
  auto directions = [&](const LatticeUnit& u) {
    if (u.slide) return std::vector<Vec2>{u.step, -1.0 * u.step};
    return std::vector<Vec2>{Vec2(grid, 0), Vec2(-grid, 0), Vec2(0, grid), Vec2(0, -grid)};
  };
  auto expired = [&] { return work.spent(); };
  // Neighbouring units (within three points along the contour): the pairs.
  const int m = c.spline.unique_point_count();
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t a = 0; a < units.size(); ++a)
    for (std::size_t b = a + 1; b < units.size(); ++b) {
      const int d = std::abs(units[a].points.front() - units[b].points.front());
      if (std::min(d, m - d) <= 3) pairs.emplace_back(a, b);
    }
  auto descend = [&](std::vector<Vec2>& at, Badness& now, bool exact) {
    for (int s = 32; s >= 1 && now.count > 0 && !expired(); s /= 2) {
      bool improved = true;
      while (improved && now.count > 0 && !expired()) {
        improved = false;
        for (const LatticeUnit& u : units) {
          for (const Vec2 dir : directions(u)) {
            std::vector<Vec2> t = at;
            for (int k : u.points) t[k] = t[k] + static_cast<double>(s) * dir;
            const std::optional<Badness> b = step(at, t, now, exact);
            if (!b) continue;
            at = std::move(t), now = *b, improved = true, at_runs.clear();
            break;
          }
          if (now.count == 0 || expired()) break;
        }
        if (improved || s > 1 || now.count == 0) continue;
        // Stuck at single cells: two neighbouring units at once.
        for (const auto& [a, b] : pairs) {
          for (const Vec2 da : directions(units[a])) {
            for (const Vec2 db : directions(units[b])) {
              std::vector<Vec2> t = at;
              for (int k : units[a].points) t[k] = t[k] + da;
              for (int k : units[b].points) t[k] = t[k] + db;
              const std::optional<Badness> bb = step(at, t, now, exact);
              if (!bb) continue;
              at = std::move(t), now = *bb, improved = true, at_runs.clear();
              break;
            }
            if (improved || expired()) break;
          }
          if (improved || expired()) break;
        }
      }
    }
  };
  auto pull_back = [&](std::vector<Vec2>& at, bool exact) {
    for (int s = 32; s >= 1 && !expired(); s /= 2) {
      bool improved = true;
      while (improved && !expired()) {
        improved = false;
        for (const LatticeUnit& u : units) {
          const Vec2 off = at[u.points.front()] - src[u.points.front()];
          if (off == Vec2(0.0)) continue;
          for (const Vec2 dir : directions(u)) {
            const Vec2 d = static_cast<double>(s) * dir;
            if (dot(off + d, off + d) >= dot(off, off)) continue;
            std::vector<Vec2> t = at;
            for (int k : u.points) t[k] = t[k] + d;
            if (!still_passes(at, t, exact)) continue;
            at = std::move(t), improved = true;
            break;
          }
        }
      }
    }
  };
  std::vector<Vec2> at = start.points();
  std::optional<Badness> first = score_of(at, !quick.has_value());
  if (!first) return std::nullopt;
  Badness now = *first;
  if (quick) {
    descend(at, now, false);
    if (now.count == 0) {
      std::vector<Vec2> pulled = at;
      pull_back(pulled, false);
      const std::optional<Badness> exact_pulled = score_of(pulled, true);
      if (exact_pulled && exact_pulled->count == 0) return spline_of(pulled);
    }
    const std::optional<Badness> exact_now = score_of(at, true);
    if (!exact_now) return std::nullopt;
    now = *exact_now;
  }
  descend(at, now, true);
  if (now.count > 0) return std::nullopt;
  pull_back(at, true);
  return spline_of(at);
}

/// The descent (descent_of) with the handles alone first, so that a node,
/// whose move shifts the glyph's extremes and stems, moves only where the
/// handles cannot pass every check; then with every unit.
std::optional<BSpline> grid_descent(const import::Contour& c, const BSpline& start, const std::vector<int>& movable,
                                    const ReportOptions& o, const GlyphFixOptions& options, Work& work) {
  const std::vector<LatticeUnit> units = lattice_units(c, movable, options.grid > 0 ? options.grid : 1);
  std::vector<LatticeUnit> handles;
  for (const LatticeUnit& u : units)
    if (!c.node[u.points.front()]) handles.push_back(u);
  if (!handles.empty() && handles.size() < units.size())
    if (std::optional<BSpline> d = descent_of(c, start, handles, o, options, work)) return d;
  return descent_of(c, start, units, o, options, work);
}

/// The total count of violations of every check in `oi` (a spline that
/// cannot be judged counts as very many).
std::function<int(const BSpline&)> total_judge(const ReportOptions& oi) {
  return [oi](const BSpline& s) {
    try {
      return total(judge_counts(s, oi));
    } catch (const InputError&) {
      return std::numeric_limits<int>::max() / 2;
    }
  };
}

/// The checks of `o` that `s` fails, each alone (the requirement, each
/// gate), then all of them together when there are several: the rounds of
/// fix_contour try each in turn.
std::vector<ReportOptions> failing_checks(const BSpline& s, const ReportOptions& o) {
  std::vector<ReportOptions> out;
  const SplineReport r = gate_report(s, o);
  if (o.require && !r.requirement_pass) {
    ReportOptions t = o;
    t.gates.clear();
    out.push_back(t);
  }
  for (std::size_t g = 0; g < r.gates.size(); ++g)
    if (!r.gates[g].pass()) {
      ReportOptions t = o;
      t.require.reset();
      t.gates = {o.gates[g]};
      out.push_back(t);
    }
  if (out.size() > 1) out.push_back(o);
  return out;
}

/// A candidate fix `f` of check `t` (moved off the grid; or of one violation
/// when `t` is null) landed: snapped to the grid when there is one (where
/// `t` passes, when given); the contour it gives when every check's total
/// (`o`, whose total `judge` counts) falls below `current_total` and every
/// smooth node stays exactly smooth, else nothing (and `why` says why), with
/// its total. `off_grid` grows to the fix's distance; the snap's
/// evaluations are charged to `work`.
std::optional<std::pair<BSpline, int>> land(const import::Contour& c, const BSpline& current, int current_total,
                                            const FixResult& f, const ReportOptions* t, const ReportOptions& o,
                                            const ContourMoves& rules, const GlyphFixOptions& options,
                                            const std::function<int(const BSpline&)>& judge,
                                            Work& work, double& off_grid, std::string& why) {
  off_grid = std::max(off_grid, f.max_distance);
  BSpline next = *f.spline;
  // Off the grid it may still break another check; the grid snap (which
  // may move neighbouring handles too) then has to mend that.
  const bool off_grid_ok = judge(next) < current_total && smooth_kept(c, next);
  const std::string breaks = "the fix of " +
                             (!t                                    ? std::string("a violation")
                              : t->gates.size() == 1 && !t->require ? to_string(t->gates[0])
                                                                    : std::string("every check")) +
                             " breaks another check (no round lowers the count of violations)";
  if (!off_grid_ok && options.grid <= 0) {
    why = breaks;
    return std::nullopt;
  }
  if (options.grid > 0) {
    // On the grid: the check passes and the total falls (t's checks and
    // all of o's judged on one model of the position). Most candidates
    // fail t, and where a changed segment's curvature extremum proves it
    // (proves_extremum_violation) the model is not built; such a candidate
    // costs the segments it classified instead of the contour.
    long proved = 0, proof_work = 0;
    const std::vector<BezierSegment> pieces = bezier_segments(current);
    auto snap_judge = [&](const BSpline& s) {
      try {
        if (t && proves_extremum_violation(pieces, s, *t, proof_work)) return ++proved, 1;
        const SplineReport model = gate_model(s, o);
        const int own = t ? total(counts_on(model, *t)) : 0;
        if (own != 0) return own;
        return total(counts_on(model, o)) < current_total && smooth_kept(c, s) ? 0 : 1;
      } catch (const InputError&) {
        return std::numeric_limits<int>::max() / 2;
      }
    };
    GridOptions g;
    g.grid = options.grid;
    g.max_move = options.max_move;
    g.max_seconds = work.seconds_left();
    g.thread_cpu_clock = true;
    const long segments = current.segment_count();  // each evaluation judges the contour
    g.max_evaluations = std::min(g.max_evaluations, std::max(1L, work.left() / segments));
    g.partners = partners_of(c, f, rules.points);
    const GridFix snapped = snap_to_grid(current, f, snap_judge, g);
    // Its judgements (a proof's instead where one decided), and ordering its candidates.
    work.charge((snapped.evaluations - proved) * segments + proof_work + snapped.combinations / 2);
    std::optional<BSpline> on_grid = snapped.spline;
    if (!snapped.found && off_grid_ok && !work.spent()) on_grid = snap_by_parts(
          c, f, snap_judge, [&](const FixResult& part) { return partners_of(c, part, rules.points); }, g, work);
    if (!on_grid) {
      why = off_grid_ok ? snapped.reason : breaks;
      return std::nullopt;
    }
    next = *on_grid;
  }
  const int next_total = judge(next);
  if (next_total < current_total && smooth_kept(c, next)) return std::make_pair(std::move(next), next_total);
  return std::nullopt;
}

/// One attempt of a round: the nearest certified fix of check `t` alone
/// from `current` (design/fix.hpp with `t`'s judge), landed (land).
std::optional<std::pair<BSpline, int>> attempt_check(const import::Contour& c, const BSpline& current,
                                                     int current_total, const ReportOptions& t, const ReportOptions& o,
                                                     const ContourMoves& rules, const GlyphFixOptions& options,
                                                     const std::function<int(const BSpline&)>& judge,
                                                     Work& work, double& off_grid, std::string& why) {
  FixRequest q;
  q.requirement = guide(t, gate_report(current, t));
  q.max_depth = t.max_depth;
  q.max_seconds = work.seconds_left();
  const long segments = current.segment_count();  // each evaluation judges the contour
  q.max_evaluations = std::max(1L, work.left() / segments);
  q.threads = 1;
  q.thread_cpu_clock = true;
  q.max_move = options.max_move;
  q.judge = total_judge(t);
  rules.restrict(q);  // every movable point: with a judge every judged segment fails, so each acts on one
  const FixResult f = fix(current, q);
  work.charge(f.evaluations * segments);
  if (!f.fixed || f.already) {
    why = f.reason;
    return std::nullopt;
  }
  return land(c, current, current_total, f, &t, o, rules, options, judge, work, off_grid, why);
}

/// The move from `from` to `to` as a fix (every point that differs).
FixResult move_as_fix(const BSpline& from, const BSpline& to) {
  FixResult f;
  f.fixed = true;
  f.spline = to;
  for (int k = 0; k < from.unique_point_count(); ++k) {
    const Vec2 a = from.points()[k], b = to.points()[k];
    if (a == b) continue;
    const double d = std::hypot(b.x - a.x, b.y - a.y);
    f.moves.push_back({k, a, b, d});
    f.total_squared += d * d;
    f.max_distance = std::max(f.max_distance, d);
  }
  return f;
}

/// Where no check's fix as a whole lowers the count (several joints of one
/// gate that no single search of its points passes together): one
/// violation at a time, each removed by its severity's move (report/
/// severity.hpp: the nearest move of its own segments' points found, and
/// at a stem meeting a bowl the constructed move that puts the bowl's end
/// on the stem's line, which a search of the grid cannot hit), landed
/// (land) when every check's total falls. A move that removes its
/// violation but breaks another (the bowl's handle that reaches the stem's
/// line changes the curvature at the bowl's other end) is followed by the
/// move of each violation it leaves, with its own points held, and the two
/// landed together. The first that lands.
std::optional<std::pair<BSpline, int>> attempt_violations(const import::Contour& c, const BSpline& current,
                                                          int current_total, const ReportOptions& o,
                                                          const ContourMoves& rules, const GlyphFixOptions& options,
                                                          const std::function<int(const BSpline&)>& judge,
                                                          Work& work, double& off_grid, std::string& why) {
  // Each violation of a gate with a severity on `s`, with its move from
  // there (by `moves`), in order, until `act` returns true.
  const auto each_move = [&](const BSpline& s, const ContourMoves& moves, const auto& act) {
    const SplineReport r = gate_report(s, o);
    for (const GateResult& g : r.gates) {
      if (g.pass() || !has_severity(g.gate)) continue;
      for (const GateViolation& v : g.violations) {
        if (work.spent()) return false;
        // In the glyph's work and guard: a severity's own clock would make
        // the fix depend on the machine's load.
        const SeverityMove sm = severity_move(s, g.gate, v, o, moves, options.max_move,
                                              std::clamp(work.left() / 3, 1L, kSeverityEvaluations), work.seconds_left());
        work.charge(sm.evaluations * 3);  // its window: a segment, or the two at a joint and one more
        if (sm.moved && act(*sm.moved)) return true;
      }
    }
    return false;
  };
  std::optional<std::pair<BSpline, int>> out;
  each_move(current, rules, [&](const BSpline& first) {
    const FixResult f = move_as_fix(current, first);
    out = land(c, current, current_total, f, nullptr, o, rules, options, judge, work,
               off_grid, why);
    if (out || judge(first) > current_total || !smooth_kept(c, first)) return out.has_value();
    ContourMoves held = rules;  // the first move's points stay where it put them
    for (const PointMove& m : f.moves) std::erase(held.points, m.point);
    return each_move(first, held, [&](const BSpline& second) {
      out = land(c, current, current_total, move_as_fix(current, second), nullptr, o, rules, options, judge, work,
                 off_grid, why);
      return out.has_value();
    });
  });
  return out;
}

/// The certificate of a contour fix: `fixed` re-judged check by check (none
/// may be worse, all must pass), its moves by the source's point names.
/// False (and out.reason) when a check fails.
bool certify_contour_fix(const import::Contour& c, const BSpline& fixed, const ReportOptions& o, ContourFix& out) {
  const std::vector<GateCount> after = judge_counts(fixed, o);
  bool all_pass = true;
  for (std::size_t i = 0; i < out.rejudged.size() && i < after.size(); ++i) {
    out.rejudged[i].after = after[i].before;
    all_pass = all_pass && after[i].before == 0;
  }
  if (!all_pass) {
    out.reason = "the fix fails a check when re-judged";
    return false;
  }
  out.fixed = true;
  out.moves = move_as_fix(c.spline, fixed).moves;
  for (const PointMove& m : out.moves) {
    std::string name = "P";  // appended: GCC 12 warns (-Wrestrict) on "P" + to_string
    out.names.push_back(m.point < static_cast<int>(c.point_names.size()) ? c.point_names[m.point]
                                                                         : name.append(std::to_string(m.point)));
    out.source_points.push_back(m.point < static_cast<int>(c.font_point.size()) ? c.font_point[m.point] : -1);
  }
  return true;
}

}  // namespace

namespace glyph_detail {

Judge local_judge(const import::Contour& c, const ReportOptions& o) {
  const std::function<int(const BSpline&)> whole = total_judge(o);
  return [c, whole, runs = RunJudge(c.spline, o)](const std::vector<Vec2>& from, const std::vector<Vec2>& to) {
    const BSpline s = with_points(c, to);
    if (!smooth_kept(c, s)) return false;
    const std::optional<RunJudge::Run> run = runs.run(from, to);
    if (!run) return whole(s) == 0;
    try {
      const SplineReport r = runs.report(s, *run);
      return std::all_of(r.gates.begin(), r.gates.end(), [](const GateResult& g) { return g.violations.empty(); });
    } catch (const InputError&) {
      return false;
    }
  };
}

}  // namespace glyph_detail

namespace {

/// settle_nearer on a contour's passing fix `fixed` (updated), judged by local_judge (every check of `o`, smooth
/// nodes kept) after the shortcuts that prove a failure (extremum_rejects, with_failure_proofs). Then, where the
/// chain search applies (glyph_chains.hpp), every chain's nearest handles in the settling's box around the fix
/// (kChainSettleBox), its nodes held where the fix put them: taken where that lowers the total squared move (the
/// whole gate re-judges it) and settled again, up to kChainSettleRounds times. Then the same rounds with each
/// chain's inner nodes moving too (kChainNodeReach cells each way, with their handles; a contour with a corner),
/// each taken only where it is cheaper and the settling after it ends (else the fix stays as it was settled).
/// Last, the turns of slanted tangents (settle_nearer's turns_from_settled): where one lowers the cost and they
/// end within the work, all of this again from there (else the fix stays as settled). Returns whether the end
/// was reached: no single unit or pair has a nearer passing position, and (where the chain search applies)
/// every chain's handles are the nearest in its box, within the work.
constexpr int kChainSettleRounds = 4;
bool settle(const import::Contour& c, BSpline& fixed, const std::vector<int>& movable, const GlyphFixOptions& options,
            const ReportOptions& o, Work& work) {
  const int distinct = c.spline.unique_point_count();
  const std::vector<Vec2> src(c.spline.points().begin(), c.spline.points().begin() + distinct);
  std::vector<Vec2> at(fixed.points().begin(), fixed.points().begin() + distinct);
  const double reach = options.max_move > 0 ? options.max_move : std::numeric_limits<double>::infinity();
  const RunJudge runs(c.spline, o);
  const auto judge = local_judge(c, o);
  const long segments = c.spline.segment_count();
  // Each judgement charged its segments: the run's window, or the contour.
  auto passes = [&](const std::vector<Vec2>& from, const std::vector<Vec2>& to) {
    const std::optional<RunJudge::Run> r = runs.run(from, to);
    work.charge(r ? r->length + 2 : segments);
    return judge(from, to);
  };
  const auto settle_units = [&](bool turns = false) {
    return settle_nearer(src, at, lattice_units(c, movable, options.grid), options.grid, reach,
                         with_failure_proofs(c.spline, o, runs, passes, work),
                         [&runs](const std::vector<int>& points) { return runs.depends_on(points); },
                         extremum_rejects(c.spline, o, options.grid, work), work, turns);
  };
  bool done = settle_units();
  for (int round = 0; done && round < kChainSettleRounds; ++round) {
    const std::optional<glyph_detail::ChainResult> r =
        chain_search(c, src, at, movable, o, options.grid, options.max_move, work, glyph_detail::kChainSettleBox, true);
    if (!r) break;  // not a contour it applies to
    done = r->solved == r->chains && !work.spent();
    if (!done || !(squared_move(src, r->points) < squared_move(src, at))) break;
    const BSpline s = with_points(c, r->points);
    if (total_judge(o)(s) != 0 || !smooth_kept(c, s)) {
      done = false;
      break;
    }
    at.assign(r->points.begin(), r->points.end());
    done = settle_units();
    if (done && round + 1 == kChainSettleRounds) done = false;  // it moved every round: not shown nearest
  }
  // Settled with nodes held: each chain again with its inner nodes moving a cell each way (with their
  // handles), taken where that is nearer and the settling after it ends; else the fix stays as settled.
  std::vector<int> nodes;
  for (int k = 0; k < distinct; ++k)
    if (c.node[k]) nodes.push_back(k);
  glyph_detail::ChainBox box = glyph_detail::kChainSettleBox;
  box.node_reach = glyph_detail::kChainNodeReach;
  for (int round = 0; done && round < kChainSettleRounds; ++round) {
    const std::optional<glyph_detail::ChainResult> r =
        chain_search(c, src, at, movable, o, options.grid, options.max_move, work, box, true, false, nodes);
    if (!r || r->solved != r->chains || work.spent() || !(squared_move(src, r->points) < squared_move(src, at)))
      break;
    const BSpline s = with_points(c, r->points);
    if (total_judge(o)(s) != 0 || !smooth_kept(c, s)) break;
    const std::vector<Vec2> settled = at;
    at.assign(r->points.begin(), r->points.end());
    if (!settle_units()) {
      at = settled;
      break;
    }
  }
  const std::vector<Vec2> before_turns = at;
  if (done && settle_units(true) && squared_move(src, at) < squared_move(src, before_turns))
    return settle(c, fixed = with_points(c, at), movable, options, o, work);
  at = before_turns;  // no turn is nearer, or the work ran out first: the fix as settled
  fixed = with_points(c, at);
  return done;
}

/// The reason of a contour that none of GlyphFixOptions::points is on.
constexpr const char* kNoNamedPoint = "none of the points named may move on this contour: left as it is";

ContourFix fix_contour(const import::Contour& c, const GlyphFixOptions& options, Work& work) {
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
  const std::function<int(const BSpline&)> judge = total_judge(o);
  const ContourMoves rules = moves_of(c, options);  // the rules every search of a contour's points keeps
  const std::vector<int>& movable = rules.points;
  if (movable.empty() && !options.points.empty()) {  // none of the named points is one of this contour's
    out.untouched = true;
    out.reason = kNoNamedPoint;
    for (GateCount& g : out.rejudged) g.after = g.before;
    return out;
  }
  // No refusal (glyph_joins.hpp) applies: fix_glyph checks every contour's before searching any.
  BSpline current = c.spline;
  int current_total = total(out.rejudged);
  std::string why;
  // Several checks: the grid descent first, in half the budget (the rounds' fix of one check
  // mostly breaks another); the rounds after it, in half of what is left where it found a fix
  // (both_searches), and the nearer of the two fixes (total squared move) is kept: the
  // descent's is found sooner, the rounds' is often nearer, and the settling then has less to do.
  const bool several = o.gates.size() + (o.require ? 1 : 0) > 1;
  // The chain search first (glyph_chains.hpp: nodes held, each failing chain's nearest handles in a box):
  // where it answers every chain the contour passes; where it answers some, the searches below start there.
  // Cubic contours only: on quadratic ones (TrueType) its answer led the searches after it to farther
  // fixes (DejaVu Sans G, both type gates: 3,962 -> 4,076 units^2); they get the growing box below.
  const int distinct = c.spline.unique_point_count();
  const std::vector<Vec2> src(c.spline.points().begin(), c.spline.points().begin() + distinct);
  // A fix found by a chain search that answers every chain (the bowl search on cubic contours, the growing
  // chain search on quadratic ones): the searches below then get half of what is left, and where they find
  // a fix too both are settled and the nearer is kept.
  std::optional<BSpline> chained;
  bool settled_here = false;  // the fix was settled to the end here (both fixes found, each settled)
  // Where the chain search leaves a chain with a unit that no position passes, its nodes held, the chains
  // it leaves are searched again from there with those units' nodes moving a cell each way
  // (glyph_chains.hpp): P052 (URW's Palatino) A, whose stem line meets a curve smoothly at p30, needs p33
  // a unit sideways for the line and p33's tangent to cross on the grid.
  if (several && options.grid > 0 && c.spline.degree() == 3) {
    const auto take = [&](const std::optional<glyph_detail::ChainResult>& r) {
      if (!r || r->solved == 0) return;
      const BSpline s = with_points(c, r->points);
      if (const int left = judge(s); left < current_total && smooth_kept(c, s)) current = s, current_total = left;
    };
    glyph_detail::ChainCache kept;  // the default box's units' states, for the bowl search too
    glyph_detail::ChainBox box;
    box.cache = &kept;
    const auto r = chain_search(c, src, src, movable, o, options.grid, options.max_move, work, box);
    take(r);
    if (r && r->solved < r->chains && !r->stuck.empty() && !work.spent()) {
      const std::vector<Vec2> at(current.points().begin(), current.points().begin() + distinct);
      const glyph_detail::ChainBox nodes_box{glyph_detail::kChainReach, glyph_detail::kChainSlideReach,
                                             glyph_detail::kChainNodeReach};
      take(chain_search(c, src, at, movable, o, options.grid, options.max_move, work, nodes_box, false, false,
                        r->stuck));
    }
    // Where a unit is stuck, a chain is left unanswered or the contour is smooth all round, the bowl search
    // moves nodes along their normals until each unit has a passing position and two units' curvatures can
    // meet at each smooth node (glyph_bowl.hpp; C059 Q's tail: no unit stuck, g2 failing at p6), in up to a
    // third of the work, a quarter before its last resort (a quarter in all ran out one try short of P052
    // e's last-resort node move; a third in all left Nimbus Sans s's settling short): a passing answer is
    // kept aside (`chained`; URW Gothic O). Not the start of the searches below: from there they settled
    // farther on fonts they fixed before (Nimbus Roman: 101,742 -> 111,431 units^2 over A-Z a-z). Only
    // with both_searches (`cmr fix`), as the growing search below.
    if ((!r || !r->stuck.empty() || r->solved < r->chains) && current_total > 0 && options.both_searches &&
        !work.spent()) {
      const long part = work.cap(work.left() / 3);
      const std::vector<Vec2> at(current.points().begin(), current.points().begin() + distinct);
      if (const auto bowl =
              glyph_detail::bowl_search(c, src, at, movable, o, options.grid, options.max_move, work, kept)) {
        const BSpline s = with_points(c, *bowl);
        if (judge(s) == 0 && smooth_kept(c, s)) chained = s;
      }
      work.release(part);
    }
  }
  // Quadratic contours: the chain search with a growing box (glyph_chains.hpp), in up to half the
  // contour's work. Where it answers every chain it is a fix (nodes held), and the searches below then get
  // half of what is left; where they find a fix too, both are settled in the rest and the nearer is kept.
  // Theirs move nodes too, and settle nearer on DejaVu Sans G; on Noto Serif's C, S and s, whose runs of
  // three off-curve points move far, no search but this one finds a fix. Only with both_searches (`cmr
  // fix`): in a report's budget its half left the other searches too little on two random glyphs
  // (tests/report/random_glyphs_test.py seeds 1013 and 1019 lost their suggested fixes).
  if (several && options.grid > 0 && c.spline.degree() == 2 && options.both_searches) {
    const long whole = work.cap(work.left() / 2);
    if (const auto at = growing_chain_search(c, src, movable, o, options.grid, options.max_move, work)) {
      const BSpline s = with_points(c, *at);
      if (judge(s) == 0 && smooth_kept(c, s)) chained = s;
    }
    work.release(whole);
  }
  const long searches_end = chained ? work.cap(work.left() / 2) : 0;
  std::optional<BSpline> descended;
  if (several && options.grid > 0 && current_total > 0) {
    const long whole = work.cap(work.left() / 2);
    if (std::optional<BSpline> d = grid_descent(c, current, movable, o, options, work))
      if (judge(*d) == 0 && smooth_kept(c, *d)) descended = std::move(*d);
    work.release(whole);
  }
  if (descended && !options.both_searches) current = std::move(*descended), current_total = 0, descended.reset();
  const long search_end = descended ? work.cap(work.left() / 2) : work.cap(work.left());
  // The grid descent from where the rounds left the contour: a passing end
  // ends the search, any other says why in `why`. descended_here: it ran
  // from `current` to its end.
  bool descended_here = false;
  const auto descend_from_here = [&] {
    if (std::optional<BSpline> d = grid_descent(c, current, movable, o, options, work)) {
      if (judge(*d) == 0 && smooth_kept(c, *d)) current = std::move(*d), current_total = 0;
      else why = "the grid descent ends with violations";
    } else if (why.empty()) {
      why = "the grid descent finds no position that passes every check";
    }
  };
  // Rounds: each tries to fix one failing check alone (its own judge and
  // search guide), then all of them at once, from where the last round
  // left the contour, snapped to the grid; a round is taken when the total
  // count of violations of every check falls and every smooth node stays
  // exactly smooth. So the total falls each round and the loop ends.
  for (int round = 0; round < kGlyphFixRounds && current_total > 0 && !work.spent(); ++round) {
    bool improved = false;
    for (const ReportOptions& t : failing_checks(current, o)) {
      if (work.spent()) break;
      if (auto next = attempt_check(c, current, current_total, t, o, rules, options, judge, work, out.off_grid_distance,
                                    why)) {
        current = std::move(next->first);
        current_total = next->second;
        improved = true;
        break;
      }
    }
    if (!improved) break;
    // Where the descent from the source found nothing, it may from here: the
    // round brought the contour nearer to passing (Nimbus Sans `S` under both
    // type gates: no descent from the source, a passing one after the first
    // round, for a tenth of the work a second round took). It gets 3/4 of what
    // is left: DejaVu Sans `s` needs 826,000 units here, more than half left.
    descended_here = false;
    if (several && options.grid > 0 && !descended && current_total > 0 && !work.spent()) {
      const long part = work.cap(work.left() / 4 * 3);
      descend_from_here();
      descended_here = !work.spent();  // it ended within its part: from here it would end the same
      work.release(part);
    }
  }
  work.release(search_end);
  if (descended) {
    if (current_total > 0 || squared_move(src, descended->points()) <= squared_move(src, current.points())) {
      current = std::move(*descended), current_total = 0;
      out.off_grid_distance = 0;  // the descent is on the grid throughout
    }
  }
  // The rounds lowered the count but no round ends it: the descent from
  // where they left the contour (unless it ran from there already).
  if (current_total > 0 && options.grid > 0 && current_total < total(out.rejudged) && !work.spent() &&
      !descended_here)
    descend_from_here();
  // Last, one violation at a time (a search for each), from where the
  // rounds left the contour, in what is left of the search's work.
  while (current_total > 0 && !work.spent()) {
    auto next = attempt_violations(c, current, current_total, o, rules, options, judge, work, out.off_grid_distance, why);
    if (!next) break;
    current = std::move(next->first);
    current_total = next->second;
  }
  if (chained) {
    work.release(searches_end);
    if (current_total > 0) {
      current = std::move(*chained), current_total = 0, out.off_grid_distance = 0;
    } else {  // both fixes, each settled in half of what is left: the nearer kept (settled, the order can change)
      const long half = work.cap(work.left() / 2);
      const bool current_settled = settle(c, current, movable, options, o, work);
      work.release(half);
      const bool chained_settled = settle(c, *chained, movable, options, o, work);
      settled_here = current_settled;
      if (squared_move(src, chained->points()) < squared_move(src, current.points()))
        current = std::move(*chained), out.off_grid_distance = 0, settled_here = chained_settled;
    }
  }
  if (current_total > 0) {
    // Where the work ran out, the last search's own reason (often its count
    // of evaluations, as few as the work had left) says nothing: the work does.
    if (work.ran_out()) why = "no certified fix found";
    out.reason = glyph_detail::unfixed_reason(why, c, current, o, current_total, total(out.rejudged));
    return out;
  }
  if (!certify_contour_fix(c, current, o, out)) return out;
  out.settled = settled_here;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace

import::Contour contour_of(const BSpline& spline, const std::vector<std::string>& names) {
  const int m = spline.unique_point_count();
  import::Contour c{0, spline, {}, {}, {}, {}, {}, {}};
  c.node.assign(m, false);
  for (const BezierSegment& b : bezier_segments(spline))
    for (const bool first : {true, false}) {
      const Vec2 end = first ? b.points.front() : b.points.back();
      if (spline.multiplicity(first ? b.segment.a : b.segment.b) < spline.degree()) continue;
      for (int k = 0; k < m; ++k)
        if (spline.points()[k] == end) c.node[k] = true;
    }
  std::vector<char> added(m, 0);
  for (int k = 0; k < m && k < static_cast<int>(names.size()); ++k) added[k] = names[k].find('+') != std::string::npos;
  for (const Segment& seg : spline.segments()) {
    const std::vector<int> pts = segment_points(spline, seg);
    const long nodes = std::count_if(pts.begin(), pts.end(), [&](int k) { return c.node[k]; });
    if (straight_bezier(bezier_segment(spline, seg).points) && nodes >= 2)
      for (int k : pts)
        if (!c.node[k]) added[k] = 1;
  }
  for (int k = 0; k < m; ++k) {
    std::string name = "P";  // appended: GCC 12 warns (-Wrestrict) on "P" + to_string
    c.point_names.push_back(k < static_cast<int>(names.size()) && !names[k].empty() ? names[k]
                                                                                  : name.append(std::to_string(k)));
    c.font_point.push_back(added[k] ? -1 : k);
  }
  c.source_point = c.font_point;
  return c;
}

namespace {

/// Notes on each of the glyph's fixes the work it took and whether the guard ended it.
void finish(std::vector<ContourFix>& out, const Work& work) {
  for (ContourFix& f : out) f.glyph_work = work.used(), f.guarded = work.guarded();
}

}  // namespace

std::vector<ContourFix> fix_glyph(const import::Glyph& glyph, const GlyphFixOptions& options) {
  if (!glyph.error.empty()) throw InputError(glyph.error);
  if (!(options.glyph_work > 0) || !(options.guard_seconds > 0))
    throw InputError("a glyph fix needs work and time: glyph_work and guard_seconds must be positive");
  std::vector<ContourFix> out;
  Work work(options.glyph_work, options.guard_seconds);
  const std::size_t n = glyph.contours.size();
  const ReportOptions o = judge_only(options.judge);
  // A contour as it is, not searched: it passes, or none of the named points is on it, or another
  // contour has no fix (so neither has the glyph).
  const auto as_it_is = [&](std::size_t i) {
    const import::Contour& c = glyph.contours[i];
    ContourFix f;
    f.contour = c.index, f.rejudged = judge_counts(c.spline, o);
    for (GateCount& g : f.rejudged) g.after = g.before;
    f.already = f.fixed = total(f.rejudged) == 0;  // else it would need a fix of its own
    if (f.fixed) return f;
    if (moves_of(c, options).points.empty() && !options.points.empty())
      f.untouched = true, f.reason = kNoNamedPoint;
    else
      f.reason = "not searched: another contour has no fix", f.not_searched = true;
    return f;
  };
  // Where one contour is proved to have no fix (refusal), so is the glyph: said at once, nothing searched.
  std::vector<std::string> refused(n);
  for (std::size_t i = 0; i < n; ++i) {
    const import::Contour& c = glyph.contours[i];
    const std::vector<int> movable = moves_of(c, options).points;
    if (total(judge_counts(c.spline, o)) > 0 && !(movable.empty() && !options.points.empty()))
      refused[i] = refusal(c, o, options.grid, movable);
  }
  if (std::any_of(refused.begin(), refused.end(), [](const std::string& r) { return !r.empty(); })) {
    for (std::size_t i = 0; i < n; ++i) {
      out.push_back(as_it_is(i));
      if (!refused[i].empty()) out.back().reason = refused[i], out.back().not_searched = false;
    }
    finish(out, work);
    return out;
  }
  bool lost = false;  // a contour has no fix, so neither has the glyph: the rest is not searched
  for (std::size_t i = 0; i < n; ++i) {
    if (lost) {
      out.push_back(as_it_is(i));
      continue;
    }
    // Each contour its share of what is left of the glyph's work (none where it passes as it is).
    const long whole = work.cap(work.left() / static_cast<long>(n - i));
    out.push_back(fix_contour(glyph.contours[i], options, work));
    lost = !out.back().fixed && !out.back().untouched;
    out.back().out_of_work = lost && work.ran_out();
    work.release(whole);
  }
  // Then each fix found is settled (settle_nearer), in what is left of the work: after every
  // contour's search, so settling one never takes what another's search needs; and only when
  // every contour is fixed (a glyph with one contour unfixed has no fix to settle). A fix that fix_contour
  // settled to the end and that this leaves where it was stays settled where the work runs out (Nimbus Sans s).
  if (!(options.grid > 0) ||
      std::any_of(out.begin(), out.end(), [](const ContourFix& f) { return !f.fixed && !f.untouched; }))
  {
    finish(out, work);
    return out;
  }
  long left = std::count_if(out.begin(), out.end(), [](const ContourFix& f) { return f.fixed && !f.already; });
  for (std::size_t i = 0; i < n; ++i) {
    ContourFix& f = out[i];
    if (!f.fixed || f.already) continue;
    const import::Contour& c = glyph.contours[i];
    const long whole = work.cap(work.left() / left--);
    const auto start = std::chrono::steady_clock::now();
    BSpline fixed = c.spline;
    for (const PointMove& m : f.moves) fixed = fixed.with_point(m.point, m.to);
    ContourFix settled = f;
    settled.moves.clear(), settled.names.clear(), settled.source_points.clear();
    const std::vector<Vec2> was = fixed.points();
    settled.settled = settle(c, fixed, moves_of(c, options).points, options, o, work) ||
                      (f.settled && fixed.points() == was);
    work.release(whole);
    const bool certified = certify_contour_fix(c, fixed, o, settled);  // it passes: settle moves only to passing positions
    settled.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (certified) f = std::move(settled);
  }
  finish(out, work);
  return out;
}

}  // namespace cmr::report
