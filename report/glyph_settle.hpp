#pragma once
// Internal to cmr::report: the glyph fix's units of motion on the grid and
// the settling of a passing fix (report/glyph_fix.cpp; docs/fix.md "On the
// grid").
#include <algorithm>
#include <chrono>
#include <functional>
#include <optional>
#include <vector>

#include "bezierize/extract.hpp"
#include "design/fix_grid.hpp"
#include "io/font.hpp"
#include "report/report.hpp"
#include "spline/bspline.hpp"
#include "spline/cpu_clock.hpp"
#include "spline/vec2.hpp"

namespace cmr::report::glyph_detail {

/// The glyph fix's budget (GlyphFixOptions::glyph_work), counted in work,
/// not time, so that a fix that runs out of it is the same on any machine
/// and under any load: the segments judged, one unit per segment of each
/// judgement of a candidate position (the whole contour, or the window of
/// the run a step changes: RunJudge), of each quick estimate, and of each
/// evaluation of the fix search, the grid snap and the severity search
/// (their own counts times the segments each judges), and one per two
/// candidate combinations the grid snap orders. A guard on the calling
/// thread's CPU time (GlyphFixOptions::guard_seconds; spline/cpu_clock.hpp)
/// ends it sooner only on a machine too slow for the budget, not on a
/// loaded one; then, and only then, a fix can differ from run to run
/// (guarded()). The glyph's searches run on the calling thread.
class Work {
 public:
  Work(long units, double guard_seconds) : limit_(units), guard_(guard_seconds) {}
  /// The budget (or the stage's cap) is used up, or the guard has passed.
  bool spent() {
    if (used_ >= limit_) return true;
    return guard_.passed();
  }
  void charge(long units = 1) { used_ += units; }
  long used() const { return used_; }
  long left() const { return limit_ > used_ ? limit_ - used_ : 0; }
  /// A stage's share: at most `units` more until release(cap's value).
  long cap(long units) {
    const long was = limit_;
    limit_ = std::min(limit_, used_ + units);
    return was;
  }
  void release(long limit) { limit_ = limit; }
  /// The budget (or the stage's cap) is used up, not by the guard.
  bool ran_out() const { return left() == 0 && !guarded(); }
  /// The guard ended the budget (the time ran out before the work).
  bool guarded() const { return guard_.found_passed(); }
  /// CPU seconds of this thread to the guard (at least `floor`): the time
  /// limit handed to the fix search and the grid snap (on this thread's CPU
  /// clock: FixRequest::thread_cpu_clock, GridOptions::thread_cpu_clock),
  /// whose evaluation limits are left().
  double seconds_left(double floor = 0.05) const { return std::max(floor, guard_.left()); }

 private:
  long used_ = 0, limit_ = 0;
  ThreadCpuDeadline guard_;
};

/// A unit of the grid descent: points moved together by whole grid steps.
/// A slide (a handle of an exactly smooth node) moves along the node's
/// tangent by multiples of the primitive grid vector on it, so the node
/// stays exactly smooth; a node moves with its handles by grid translations
/// (the handles' directions are unchanged); any other point moves freely.
struct LatticeUnit {
  std::vector<int> points;
  bool slide = false;
  Vec2 step{0.0};   ///< slide: the primitive grid vector along the tangent
  int anchor = -1;  ///< slide: the smooth node it slides on (a turn's pivot)
};

/// Whether Bezier points `b` lie exactly on one line, as computed in double
/// (det(p - b_0, b_n - b_0) == 0 for every p: exact for font units, whose
/// products stay below 2^53): a line of a contour, whose points never move.
bool straight_bezier(const std::vector<Vec2>& b);
/// Per segment of `s`: straight_bezier of its Bezier points.
std::vector<char> straight_segments(const BSpline& s);
/// Whether node k of a closed contour's points `p` (its first m, cyclic) is
/// exactly smooth: its neighbours exactly collinear with it, on opposite
/// sides (exact for font units, whose products stay below 2^53).
bool exactly_smooth(const std::vector<Vec2>& p, int m, int k);
/// The primitive grid vector along `a` (a's grid coordinates divided by
/// their gcd, times `grid`): a sliding handle's step; nullopt where `a` is 0
/// or not a whole number of grid steps in x and y.
std::optional<Vec2> grid_vector(Vec2 a, double grid);

/// A judge of a move from a passing position `from` to `to` (the contour's
/// distinct points), whether `to` passes (local_judge; settle_nearer's `passes`).
using Judge = std::function<bool(const std::vector<Vec2>&, const std::vector<Vec2>&)>;

/// The settling of a passing fix (fix_glyph, after every contour's search): the cost
/// is the total squared move of every point from the source, and a move is
/// taken when it lowers the cost and the exact judge passes it
/// (`passes(at, t)`: whether t, which is `at` with some units moved, passes).
///  * Single units: every position of a unit's lattice (a slide: the
///    multiples of its step along its line; a translation: the grid vectors)
///    that lowers the cost, tried in order of the cost, the first that
///    passes taken; repeated until no unit moves. Then no single unit has a
///    nearer passing grid position, the others held. A unit's
///    positions are listed band by band of their distance from its cheapest
///    point (about kSettleCandidates a band: rings 36 cells wide, or 2048
///    slide steps), the next band only when none of one passes: a unit that
///    moved hundreds of cells (a glyph drawn at 20 times a font's size)
///    would otherwise list tens of millions of positions before judging one.
///  * Pairs of neighbouring units (within three points along the contour),
///    each up to kPairReach cells (a slide kPairSlideReach steps) from where
///    it is, in order of the cost; after a pair moves, the single units
///    again. The pairs are tried in turn until a whole round moves none.
///  * With `turns_from_settled` (where `at` is the end of a settling
///    without them, so its singles and pairs are done): turns of a smooth
///    node's tangent, its two sliding handles (two slide units on one
///    anchor, the node held) to positions exactly collinear with it on
///    either side: one handle up to kTurnReach cells from where it is, the
///    other on the new tangent through the node, N + b v (v the primitive
///    grid vector from the first through the node, b >= 1 a whole number,
///    the two nearest its source position), in order of the cost; after a
///    turn, the single units and the pairs again (those a moved point
///    frees), until no turn moves. (Slides and translations keep every
///    tangent's direction; only a turn changes one.) A level or upright
///    tangent is not turned: its node is at an x or y extremum, whose
///    handles designers keep so. The turns come last (glyph_fix.cpp,
///    settle) because a tangent turned early steers the chain search that
///    follows: URW Gothic `P` settled at 776 units² so, 724 without.
/// `src` and `at`: the contour's distinct points, the source's and the
/// fix's (which passes); a position farther than `max_move` from the source
/// is not tried. `depends_on(points)`: the points whose positions the
/// verdict on a move of `points` depends on (every point where it cannot
/// say less); a unit whose candidates were tried (none passed, or it moved
/// to the first that did, every nearer position having failed) and a pair
/// whose candidates all failed are not tried again until one of those
/// points moves, since their candidates' verdicts and costs are what they
/// were. It ends when `work` is spent (`passes` charges it). Returns
/// whether that end was reached (else the work ran out first); `at` holds
/// the best so far either way, and it passes.
inline constexpr int kPairReach = 2, kPairSlideReach = 4, kTurnReach = 3;
inline constexpr long kSettleCandidates = 4096;

/// The settling's cost: the sum over the distinct points of the squared
/// distance of `pts` from `src` (the first src.size() of pts are read).
double squared_move(const std::vector<Vec2>& src, const std::vector<Vec2>& pts);

/// `rejects(at, unit, steps)`: per step of a single unit's band, true where
/// `at` with the unit moved by it certainly fails a check
/// (extremum_rejects): such positions are passed over unjudged, as
/// failing, so the scan's order and its answer are those of judging them.
/// None when empty.
using Rejects =
    std::function<std::vector<char>(const std::vector<Vec2>&, const LatticeUnit&, const std::vector<Vec2>&)>;

bool settle_nearer(const std::vector<Vec2>& src, std::vector<Vec2>& at, const std::vector<LatticeUnit>& units,
                   double grid, double max_move, const Judge& passes,
                   const std::function<std::vector<int>(const std::vector<int>&)>& depends_on, const Rejects& rejects,
                   Work& work, bool turns_from_settled = false);

/// The settling's shortcut where `o` has the curvature-extrema gate: a
/// unit's candidate steps (each a whole number of `grid` steps, or of a
/// slide's grid vector) classified at once by the unit's region
/// (region/region.hpp: the unit's points moved rigidly, each piece on its
/// own, over the segments the unit shapes that are not straight in
/// `source`: one render whose pixel centres are the candidates, or one
/// classification each where that would be many more pixels than
/// candidates). A certified "fail" there is a sign change of lambda inside
/// a judged segment, a curvature extremum, and that is a violation of the
/// gate wherever the segment has no cusp and is not near constant
/// (violates_where_extremum: both shown from its Bezier points with a
/// margin), so the step is rejected; every other step is left to the judge.
/// Each region charges `work` kRegionSetupWork per judged segment and a
/// unit per kRegionPixelsPerWork pixels rendered or per position classified
/// alone. Empty (no shortcut) without that gate or for a rational contour.
/// GlyphFix.ExtremumRejectsAreFailures holds it to the judge.
inline constexpr long kRegionSetupWork = 40, kRegionPixelsPerWork = 16;
Rejects extremum_rejects(const BSpline& source, const ReportOptions& o, double grid, Work& work);

/// The checks of a move of a few points judged on the segments those points
/// shape. Where every check of `o` is local (the extremum gates read each
/// segment's own piece, g2 each joint's two sides; no requirement) and the
/// contour is closed, a move
/// from one position of the contour's distinct points to another changes a
/// cyclic run of segments, and every other segment and joint is the same
/// piece as before. `report` judges the run with one unchanged segment on
/// either side as a window of its own (segments_window: the same pieces, so
/// the same verdicts on them and on the joints between them) and keeps only
/// the run's violations: segments 1..length and joints 1..length + 1 of the
/// window. So a position's violations are the other position's, less those
/// `report` finds on the run there, plus those it finds on the run here.
/// GlyphFix.LocalJudgeIsTheWholeJudge holds both judges (local_judge, the
/// grid descent's violation counts) to the whole contour's.
class RunJudge {
 public:
  struct Run {
    int first = 0;   ///< the run's first segment
    int length = 0;  ///< its segments
  };
  RunJudge(const BSpline& contour, const ReportOptions& o);
  /// The run of segments that differ between positions `from` and `to`;
  /// nullopt where the whole contour is to be judged (a check that is not
  /// local, nothing changed, or a window that would hold every segment).
  std::optional<Run> run(const std::vector<Vec2>& from, const std::vector<Vec2>& to) const;
  /// gate_report of the run's window of `s` (the contour at some position)
  /// with only the run's violations; throws what gate_report throws.
  SplineReport report(const BSpline& s, const Run& r) const;
  /// The distinct points whose positions the verdict on a move of `points`
  /// depends on: those shaping the window of the run they change (the
  /// run's segments and one on either side, which also holds every
  /// neighbour of a node among them: what keeping smooth nodes smooth
  /// reads); every point where the whole contour is judged.
  std::vector<int> depends_on(const std::vector<int>& points) const;

 private:
  ReportOptions o_;
  bool local_ = false;
  int segments_ = 0;
  std::vector<std::vector<int>> touches_;  ///< per distinct point: the segments it shapes
  std::vector<std::vector<int>> shapes_;   ///< per segment: the distinct points that shape it
};

/// A judge of a position that differs from a passing one in a few points:
/// `passes(from, to)` (from passes every check of `o`; to is from with some
/// points moved, both the contour's distinct points) is whether `to` passes
/// every check and keeps every exactly smooth node exactly smooth, judged on
/// the changed run alone where RunJudge allows, else on the whole contour.
/// Defined in glyph_fix.cpp; GlyphFix.LocalJudgeIsTheWholeJudge.
Judge local_judge(const import::Contour& c, const ReportOptions& o);

/// `passes` preceded, where `runs` judges the move on a run of segments, by
/// proofs of failure a few times cheaper than the judge (each try charges
/// `work` a unit); where one holds, false, unjudged:
///  * curvature-extrema-at-nodes: a segment of the run, not straight in
///    `source`, that Algorithm 1 (classify_segment, certified: its
///    floating-point path with error bounds, else exact) finds not monotone
///    has a curvature extremum inside, a violation where
///    violates_where_extremum shows it is neither a cusp nor near constant;
///  * g2-at-smooth-nodes:tol: a joint of the run (its ends included) that
///    the gate judges wherever the judge passes (C1 by the knots, or a node
///    exactly smooth in `source`, which local_judge keeps so) whose
///    certified end curvatures (certified_end_curvature, as the gate's)
///    differ by more than tol times the larger, with a margin for their
///    rounding.
/// `runs` and `work` must outlive the judge.
/// GlyphFix.FailureProofsAreTheJudge holds it to the judge.
Judge with_failure_proofs(const BSpline& source, const ReportOptions& o, const RunJudge& runs, Judge passes,
                          Work& work);

/// Whether `o`'s curvature-extrema-at-nodes gate certainly fails on `s` at a
/// segment whose Bezier points differ from the same segment's in `before`
/// (bezier_segments of a spline with the same control structure, made once
/// for all the candidates), by with_failure_proofs' first proof:
/// Algorithm 1 finds it not monotone and violates_where_extremum shows it is
/// neither a cusp nor near constant. False where `o` has no such gate, for
/// rational curves, wherever no changed segment is proved to fail, and where
/// a classification throws (the judge then decides).
/// `classified` grows by the segments classified (the proof's work, in
/// segments judged). GlyphFix.ChangedSegmentProofsAreTheGate holds it to the gate.
bool proves_extremum_violation(const std::vector<BezierSegment>& before, const BSpline& s, const ReportOptions& o,
                               long& classified);

/// The moves of `f` in parts that share no segment: two moved points are in
/// one part when a segment has both (through others of the part).
std::vector<std::vector<PointMove>> parts_of(const import::Contour& c, const FixResult& f);

/// GridOptions::max_evaluations' default: the judgements of one snap.
inline constexpr long kSnapEvaluations = GridOptions{}.max_evaluations;

/// Where the grid snap of a whole fix finds nothing (each of many moved
/// units has a few candidate cells, and their product is cut to
/// kMaxCombinations: Nimbus S's extrema fix moves 15 handles), the fix's
/// parts that share no segment snapped one after another: each part's
/// units on the grid, judged with the parts before it on the grid and the
/// parts after it where the fix put them (the fix passes, and a part's
/// moves change only its own segments' verdicts): its units alone first,
/// then with their partners (GridOptions::partners), each snap at most
/// kSnapEvaluations judgements. Nothing where a part has no passing grid
/// position near its fix.
/// `partners(part)`: the unmoved points that may step with the part
/// (GridOptions::partners).
std::optional<BSpline> snap_by_parts(const import::Contour& c, const FixResult& f,
                                     const std::function<int(const BSpline&)>& snap_judge,
                                     const std::function<std::vector<int>(const FixResult&)>& partners, GridOptions g,
                                     Work& work);

}  // namespace cmr::report::glyph_detail
