#pragma once
/// The smallest certified fix of each failing check of a report
/// (design/fix.hpp): the requirement (cmrwi, cmr, split:S[:sharpest|
/// flattest]) and every failing gate, each through a fix requirement that
/// implies it (curvature-extrema-at-nodes and max-extrema-per-segment:N: every segment
/// monotone; each-piece; no-inflection; g2-at-smooth-nodes:tol: g2 at every
/// smooth joint; curvature-extrema-at-nodes:runs: each-run, every run between on-curve
/// nodes monotone, and where that has no fix the valleys' own handles
/// searched with the gate itself as fix()'s judge, FixRequest::judge). Each is fix() with the report's depth, the spline's G1
/// joints kept, the end points of an open spline fixed, and a time limit;
/// its certificate is analyze on the moved spline, and a gate's fix is
/// re-judged by the gate itself (found = false, with the violation, when
/// it still fails). This replaces the old tangent line search (one handle
/// along a tangent, on a grid): the fix looks in every direction, moves
/// several points where one cannot, and is proved.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "design/fix.hpp"
#include "report/gates.hpp"

namespace cmr::report {

struct SplineReport;
struct ReportOptions;

/// One check's violations before and after a fix.
struct GateCount {
  std::string check;
  int before = 0, after = 0;
};

/// One check's fix: which points move where, and the certificate.
struct CertifiedFix {
  std::string check;              ///< "cmr", "split:2:sharpest", "curvature-extrema-at-nodes", "no-inflection"
  /// The fix requirement searched when it differs from the check (a gate's:
  /// "curvature-extrema-at-nodes" for max-extrema-per-segment:N, "each-run" for
  /// curvature-extrema-at-nodes:runs); empty otherwise.
  std::string requirement;
  bool found = false;             ///< a fix the certificate holds for
  std::vector<PointMove> moves;   ///< empty when none
  double size = 0;                ///< the curve size displacements are relative to
  double seconds = 0;             ///< time of the search
  std::string reason;             ///< why none (one line)
  std::vector<int> failing_segments;  ///< of the input, for this check
  std::optional<BSpline> fixed;   ///< the moved spline (found)
  SplineAnalysis certificate;     ///< analyze(*fixed) (found)
  /// The glyph fix's (a font contour's gate fix, or every required check at
  /// once): each check's violations before and after, re-judged; empty for
  /// the fix search's.
  std::vector<GateCount> rejudged;
};

/// The fix requirement that implies a gate (docs/fix.md, "In the report"):
/// every segment monotone has no extremum inside (max-extrema-per-segment:N
/// for any N); each run between on-curve nodes monotone has rising, then
/// falling peaks (curvature-extrema-at-nodes:runs); no-inflection and g2 are their own.
FixRequirement requirement_of(const Gate& gate);

struct Requirement;  // report/report.hpp (which includes this header)

/// The fix requirement of a report's check (cmrwi, cmr, split:S with its
/// extremum).
FixRequirement requirement_of(const Requirement& check);

/// A gate some move of points can fix (not g3-at-smooth-nodes: the fix
/// keeps g2 at most; not xy-extrema-at-nodes: it needs a node added; not
/// the interpolation gates: a move of another master).
bool has_point_move_fix(const Gate& gate);

struct ReportOptions;  // report/report.hpp

/// The checks of a report that `cmr fix FONT.ufo` fixes on the grid, by
/// their names (to_string): the gates with a point-move fix, then the
/// required check (cmrwi, cmr, split:S) when one is. A gate without one is
/// left out: cmr fix refuses g3, and no move passes xy-extrema-at-nodes.
std::vector<std::string> fixable_checks(const ReportOptions& options);
/// fixable_checks as the --require list of the page's and the Markdown
/// summary's command ("" when there is none).
std::string fixable_require(const ReportOptions& options);

/// The fix search's request for one gate as a report runs it (the gate
/// fixes and the severity search): requirement_of(gate), G1 kept, one
/// thread, a first grid of 16, tolerance 1e-4, at most `max_seconds`.
FixRequest gate_fix_request(const Gate& gate, int max_depth, double max_seconds);

/// Time limit of each fix in a report (seconds).
inline constexpr double kReportFixSeconds = 2;

/// The fixes of a failing spline: one per failing check (the requirement,
/// then each failing gate in order), and, where several checks are required
/// and the spline is closed and polynomial, one more for all of them at once
/// (check "all: A, B"), found by the glyph fix's engine (report/glyph_fix.hpp,
/// as `cmr fix --require A,B`) and re-judged check by check
/// (CertifiedFix::rejudged). A font contour (closed, polynomial, every
/// point that may move at an integer) gets its fixes on the grid of 1
/// unit, from the glyph fix: with one check the gate's, with several only
/// the "all:" fix (a gate's own fix mostly breaks another), besides the
/// entries of gates the glyph fix does not search (g3, xy-extrema, the
/// interpolation gates: a reason each). Other fixes are the fix search's.
std::vector<CertifiedFix> certified_fixes(const SplineReport& report, const ReportOptions& options);

/// The largest displacement over the curve size (0 without moves).
double largest_relative_move(const CertifiedFix& fix);

/// {"check", "found", "moves": [{"point", "name", "from", "to", "displacement",
/// "distance", "relative"}], "max_relative", "seconds", "failing_segments",
/// "certificate": {"cmrwi", "cmr", "split"?}} with "reason" when none was
/// found. `names`: one name per distinct control point (a font's), else "P<k>".
nlohmann::ordered_json certified_fix_json(const CertifiedFix& fix, const std::vector<std::string>* names = nullptr);

/// Signed curvature against the parameter, before (the input) and after (the
/// fixed spline), as two panels of one inline SVG on one kappa scale; the
/// segments the check failed on are shaded in the "before" panel. `id`
/// (unique in the page, optional): the "after" panel reuses the "before"
/// panel's segment joints through `<use>` where they are the same.
std::string kappa_before_after_svg(const BSpline& before, const BSpline& after,
                                   const std::vector<int>& failing_segments, const std::string& id = {});

/// One HTML block: "Smallest certified fix (cmr): move P3 by (dx, dy) …" and,
/// when found, the before/after curvature plots of `original`.
std::string certified_fix_html(const CertifiedFix& fix, const BSpline& original,
                               const std::vector<std::string>* names = nullptr);

}  // namespace cmr::report
