#pragma once
/// One fix for every gate of a glyph, on the font's grid (`cmr fix
/// FONT.ufo --glyph NAME --require GATES`, docs/fix.md "Font sources").
///
/// Per contour that fails: the judge is every required check at once (the
/// report's model and gates, gate_report: the count of violations of all
/// of them, plus one when the requirement fails), handed to fix() as its
/// judge (FixRequest::judge) with the requirement that implies the first
/// failing gate as the search's guide; the moves are the designer's
/// (report/contour_moves.hpp, the rules the report's severity keeps too):
/// G1 kept at smooth nodes (Keep::g1), only the source's own points move,
/// and never a straight piece: a line's added inner points are no source
/// points, and a node at either end of a line stays where it is (so a line
/// stays a line). The
/// off-grid fix is then snapped to the grid (design/fix_grid.hpp: the
/// cheapest grid positions near it that the same judge passes). The result
/// is re-judged gate by gate, before and after, and a fix that makes any
/// required gate worse is none.
///
/// Rounds: each takes the first of these whose landing (snapped to the
/// grid) lowers the total count of violations and keeps every smooth node
/// smooth: the fix of each failing check alone, then of all of them; else,
/// one violation at a time, the move behind its severity (report/
/// severity.hpp: the nearest move of its own segments' points found; at a
/// stem meeting a bowl under g2 the constructed move that puts the bowl's
/// end on the stem's line, which no search of the grid hits), and where
/// that move removes its violation but breaks another (the bowl's handle
/// that reaches the line changes the curvature at the bowl's other end),
/// followed by the move of each violation it leaves with its own points
/// held, the two landed together (glyph_fix.cpp, attempt_violations).
///
/// Several checks at once, on a cubic contour under the two type gates:
/// first the chain search (report/glyph_chains.hpp: nodes held, each
/// failing chain's nearest certified handle positions in a box, an exact
/// shortest path); where it leaves a chain unanswered, the bowl search
/// (report/glyph_bowl.hpp: nodes moved along their normals until every unit
/// has a passing position and neighbouring units' curvatures can meet, then
/// wider boxes for free handles), whose passing answer is kept aside as a
/// second candidate; where it leaves violations, from there a descent on the
/// grid (glyph_fix.cpp, grid_descent). Units: a handle of an exactly smooth node slides by k
/// times the primitive grid vector (dx, dy) / gcd(dx, dy) of its tangent
/// (so the node stays exactly smooth, checked in integer arithmetic); a
/// node moves with its handles by grid translations; other handles freely.
/// Objective, per violation (0 when it passes): an extremum inside a
/// segment at local parameter u: min(u, 1 - u); a g2 jump kl | kr:
/// |kl - kr| / max(|kl|, |kr|) - tol, or where one side is a line (0):
/// |k| s / (1 + |k| s) of the other (s: curve_size); plus 1e-3 per
/// violation. Estimated in doubles (kappa sampled at 49 parameters a
/// segment, g2 at 0.9 tol), decided by the exact report. Pattern search
/// with steps 32..1 cells, pairs of neighbouring units at 1 cell; handles
/// alone first, then nodes too; then each unit pulled back towards the
/// source while everything passes. A local search: passing, not nearest.
/// Where the descent from the source finds nothing, it is tried again after
/// each round that lowers the count, from there (half the work left).
/// On the grid, the passing fix (from the descent or the rounds) is then
/// settled (glyph_fix.cpp, settle_nearer; ContourFix::settled): with cost
/// the total squared move from the source, each moved unit goes to the
/// passing position of its lattice that lowers the cost most (every such
/// position tried in order of cost), then pairs of neighbouring units each
/// up to 2 cells (a slide 4 steps), until nothing moves; then, on a cubic
/// contour, every chain's nearest handles in a box around the fix
/// (glyph_chains.hpp, kChainSettleBox), taken where cheaper and settled
/// again; then the same with each chain's inner smooth nodes moving a cell
/// each way with their handles (on a contour with a corner), taken where
/// cheaper and the settling after it ends; last, turns of a smooth node's
/// slanted tangent (one handle up to 3 cells), and where one is cheaper,
/// all of the settling again.
/// A quadratic contour's smooth line-to-curve join under g2 cannot pass
/// (a quadratic's end curvature is 0 only when it is straight): said at
/// once. Nor can a cubic's, under g2 and the extremum gate together, where
/// the curve's far node is exactly smooth with a tangent square to the line
/// (g2 puts the second handle at the lines' crossing, and such a cubic has
/// a curvature extremum inside: derived in glyph_joins.hpp,
/// square_cubic_line_join), or where it ends at a held line's end that
/// leaves no monotone cubic (held_cubic_line_join, and on the grid
/// held_cubic_line_join_on_grid): said at once too. Budget:
/// GlyphFixOptions::glyph_work per glyph, in work, not time.
#include <string>
#include <vector>

#include "design/fix_grid.hpp"
#include "io/font.hpp"
#include "report/report.hpp"

namespace cmr::report {

/// GlyphFixOptions::glyph_work's default (`cmr fix`).
inline constexpr long kGlyphWork = 2000000;
/// The largest glyph_work a source fix takes (`cmr fix --work`): 500 times
/// the default, half an hour to several hours a glyph.
inline constexpr long kMaxGlyphWork = 1000000000;
/// GlyphFixOptions::guard_seconds' default, for kGlyphWork: a larger budget
/// gets a guard in proportion (source_fix_options).
inline constexpr double kGlyphGuardSeconds = 9.5;
/// The work of a report's fix of every check at once on a glyph's contour
/// (report/certified_fix.hpp), about kReportFixSeconds on this project's
/// VM; twice that is its time guard.
inline constexpr long kReportGlyphWork = kGlyphWork / 4;

struct GlyphFixOptions {
  ReportOptions judge;     ///< the requirement and gates (regions and fixes off)
  double grid = 1;         ///< the font's grid; 0: off-grid (the fix as found)
  double max_move = 0;     ///< largest move of any point (font units); 0: the contour's size
  /// The whole glyph's budget, in work (glyph_settle.hpp, Work: exact
  /// judgements of candidate positions and the searches' evaluations), so
  /// that a glyph gets the same fix on any machine and under any load: each
  /// contour gets its share of what is left (a contour that passes as it is
  /// takes none), and the settling what the searches leave. A contour out of
  /// work is reported without a fix, with the reason of its last attempt.
  /// The default takes 3–9 s on this project's 2-core VM where a glyph
  /// uses all of it (a unit takes about 1.5–4.5 µs there: docs/fix.md).
  long glyph_work = kGlyphWork;
  /// A guard on the glyph (CPU seconds of the thread that fixes it, not
  /// wall-clock ones, so a loaded machine does not reach it first): ends its
  /// work sooner on a machine too slow for it (ContourFix::guarded; only
  /// then can a fix differ from run to run).
  double guard_seconds = kGlyphGuardSeconds;
  /// Several checks on the grid: where the grid descent finds a fix, run
  /// the rounds too (in half the work left) and keep the nearer fix (total
  /// squared move). `cmr fix` does; a report's fix suggestions, found in
  /// the report's time, do not.
  bool both_searches = true;
  /// The points that may move, by name (import::Contour::point_names, e.g.
  /// "o/c0/p9"); empty: every point the contour's rules allow
  /// (contour_moves). Each must be one those rules allow; a named node
  /// moves with its handles, as any node does. A contour with none of them
  /// (none that may move) is left as it is (ContourFix::untouched), even
  /// where it fails.
  std::vector<std::string> points;
  /// Source fixes (report/source_fix.hpp): where a contour has no fix by
  /// moves, the glyph is fixed again with nodes added (report/glyph_nodes.hpp;
  /// `cmr fix --add-nodes`). Needs a grid and no `points`.
  bool add_nodes = false;
};


struct ContourFix {
  int contour = 0;          ///< Contour::index
  bool already = false;     ///< passes as it is
  bool fixed = false;
  /// GlyphFixOptions::points names none of its points that may move: left as it is, not
  /// fixed, and not the glyph fix's failure (rejudged: after = before).
  bool untouched = false;
  std::string reason;       ///< why not fixed (one line)
  bool not_searched = false;  ///< not fixed: not searched, since another contour of the glyph has no fix
  std::vector<PointMove> moves;         ///< control point indices of the contour's spline
  std::vector<std::string> names;       ///< per move: the point's name
  std::vector<int> source_points;       ///< per move: its index in the source contour
  std::vector<GateCount> rejudged;      ///< every required check, before and after
  double off_grid_distance = 0;         ///< the largest move of the off-grid fix
  /// On the grid, the fix as settled (glyph_fix.cpp settle_nearer): no
  /// moved point (a node with its handles, a handle sliding on its tangent,
  /// a free handle) has a passing grid position that lowers the total
  /// squared move, the rest held, and no two neighbouring ones a few cells
  /// each; on a cubic contour (or a quadratic one with an on-curve point),
  /// no chain's handles in the settling's box (nodes held, and the inner
  /// points of a run of four or more off-curve points) pass with a smaller
  /// total move. False where the work ran out first (the fix still passes),
  /// unless the fix was settled to the end in its contour's search and the
  /// glyph's last settling left it where it was.
  /// (After that the settling also tries each chain with its inner nodes a
  /// cell each way, then turns of each smooth node's slanted tangent, one
  /// handle up to 3 cells and the other on the new tangent, glyph_fix.cpp
  /// settle; where that ends in time, none of those is nearer either, but
  /// `settled` does not say whether it did.)
  bool settled = false;
  double seconds = 0;
  long glyph_work = 0;   ///< the work its glyph's fix took (GlyphFixOptions::glyph_work)
  bool guarded = false;  ///< the glyph's time guard ended its work (GlyphFixOptions::guard_seconds)
  /// Not fixed, and its share of the glyph's work was used up (not by the
  /// guard): more work may find a fix (`cmr fix --work`).
  bool out_of_work = false;
};

/// A closed polynomial spline as a contour of the glyph fix (a plain spline
/// file, or a report's spline): its nodes are the control points the curve
/// passes through (a knot of multiplicity >= the degree), and the inner
/// points of an exactly straight piece between two nodes, or of a point
/// `names` calls "...+..." (import's name of a line's added point), are no
/// source points (they never move). Point names from `names`, else "P<k>".
import::Contour contour_of(const BSpline& spline, const std::vector<std::string>& names);

/// Fixes every failing contour of `glyph` (see the header comment).
std::vector<ContourFix> fix_glyph(const import::Glyph& glyph, const GlyphFixOptions& options);

}  // namespace cmr::report
