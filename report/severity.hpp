#pragma once
/// How much a finding matters (on by default for fonts; `cmr report
/// --min-severity UNITS`, `--no-severity`; docs/report.md "Severity"): the
/// smallest certified move found that removes it.
///
/// For each violation of a gate that has a fix (curvature-extrema-at-nodes and
/// max-extrema-per-segment: an extremum inside segment i; g2-at-smooth-nodes:
/// a jump at joint j), fix() (design/fix.hpp) searches the nearest move of
/// the points of that segment (of the two segments meeting at that joint),
/// with smooth nodes kept G1, judged by the gate itself: the violation at that
/// place must be gone (others may come or go: this measures the one finding,
/// not a fix of the glyph). The severity is the fix's largest point
/// displacement, in the spline's units (font units for a font); +inf when the
/// search finds none within its time limit (kSeverityFixSeconds). A violation
/// whose severity is below ReportOptions::min_severity (half a grid unit by
/// default: a move the font's grid cannot even express) is `info`: reported,
/// but it does not fail its gate, unless ReportOptions::strict.
///
/// Cost (about 4 ms of CPU a DejaVu finding, 7 ms a Nimbus one; 14-18 ms
/// when every candidate was judged on the whole contour): each candidate is
/// judged on a window, the violation's own segments cut out as an open
/// spline with the same polar knots and points (the same polynomial
/// pieces; a segment's extrema are read from it, a joint's curvatures from
/// its two sides), and the answer is re-judged on the whole spline (searched
/// again judging the whole where that fails). Coarse to fine: fix()'s first
/// grids are 1/16 of the curve's size, so a move below the threshold can
/// lie between their cells; a violation whose first answer is below
/// kRefineBelow times the threshold, or none, is searched again within the
/// threshold alone. The number is an upper bound (a local search), certified.
/// Not yet: a line's implied points may move (lines are not kept straight,
/// unlike report/glyph_fix), and every joint the moved points touch must
/// pass fix()'s own g2 check (a failing neighbour raises a g2 finding's
/// number).
#include <limits>
#include <optional>

#include "report/report.hpp"

namespace cmr::report {

/// Time limit of one violation's search (seconds).
inline constexpr double kSeverityFixSeconds = 0.5;
/// A finding whose search found no move below kRefineBelow times the
/// threshold (or none) is searched again within the threshold alone.
inline constexpr double kRefineBelow = 8;
/// The default threshold of `--min-severity`: half a font unit.
inline constexpr double kDefaultMinSeverity = 0.5;

/// One violation's severity and the move that has it.
struct SeverityMove {
  double distance = std::numeric_limits<double>::infinity();  ///< largest point displacement; +inf: none found
  std::optional<BSpline> moved;  ///< the moved spline (found): the violation's place passes on it
};

/// The search behind a violation's severity (see above), at most `max_move`
/// (0: the curve size). Each candidate is judged on the violation's own
/// segments (its segment, or the two meeting at its joint, as a spline of
/// their own with the same pieces); the answer is re-judged on the whole
/// spline, and searched again judging the whole spline where that fails.
SeverityMove severity_move(const BSpline& spline, const Gate& gate, const GateViolation& violation,
                           const ReportOptions& options, double max_move = 0);

/// Fills GateViolation::severity and ::info of report.gates (see above) and
/// report.pass again. Nothing when options.min_severity < 0.
void assess_severity(SplineReport& report, const ReportOptions& options);

}  // namespace cmr::report
