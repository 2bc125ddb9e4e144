#pragma once
/// How much a finding matters (on by default for fonts; `cmr report
/// --min-severity UNITS`, `--no-severity`; docs/report.md "Severity"): the
/// smallest certified move found that removes it.
///
/// For each violation of a gate that has a fix (curvature-extrema-at-nodes and
/// max-extrema-per-segment: an extremum inside segment i; g2-at-smooth-nodes:
/// a jump at joint j), fix() (design/fix.hpp) searches the nearest move of
/// the points of that segment (of the two segments meeting at that joint)
/// that a designer can make, judged by the gate itself: the violation at
/// that place must be gone (others may come or go: this measures the one
/// finding, not a fix of the glyph). The moves are those of `cmr fix` on a
/// font (report/contour_moves.hpp, the one rule set): a line's implied
/// points never move, nor a line's end nodes (the line stays straight), and
/// smooth nodes keep G1. The severity is the move's largest point
/// displacement, in the spline's units (font units for a font); +inf when
/// there is none: no point of the place may move (SeverityOutcome::
/// no_allowed_move: e.g. a g2 jump between a line and a curve whose handle
/// is held by a smooth node at its other end), or the search found none
/// within its evaluation limit (kSeverityEvaluations, or the time guard
/// kSeverityFixSeconds on a slow machine; none_found). A violation
/// whose severity is below ReportOptions::min_severity (half a grid unit by
/// default: a move the font's grid cannot even express) is `info`:
/// reported, but it does not fail its gate, unless ReportOptions::strict;
/// +inf is never info.
///
/// A g2 jump where a straight piece meets a curve (a stem meeting a bowl)
/// is not searched but constructed (severity.cpp, line_join_move): the
/// line's curvature is exactly 0, so only the curve's end Bezier points B0,
/// B1, B2 exactly collinear remove it, a line no grid search hits; for a
/// line parallel to an axis each allowed point that moves B2 alone goes
/// there (along the normal, or along its node's tangent for a smooth node's
/// handle); for a slanted line (an italic stem) the point that is B2
/// itself, unless it is a smooth node's handle, goes to the point of the
/// line (a multiple of 2^-20 of its primitive direction from B0) nearest
/// its foot; each re-judged on the whole spline; no_allowed_move where no
/// allowed point reaches B0..B2, none_found where no construction passes.
///
/// Cost: each candidate is judged on a window, the violation's own segments
/// cut out as an open spline with the same polar knots and points (the same
/// polynomial pieces; a segment's extrema are read from it, a joint's
/// curvatures from its two sides), and the answer is re-judged on the whole
/// spline (searched again judging the whole where that fails). Coarse to
/// fine: fix()'s first grids are 1/16 of the curve's size, so a move below
/// the threshold can lie between their cells; a violation whose first
/// answer is below kRefineBelow times the threshold, or none found, is
/// searched again within the threshold alone. The number is an upper bound
/// (a local search), certified. Not yet: a line's end node moving with its
/// line (a translation of the whole line, or a slide along it), and every
/// joint the moved points touch must pass fix()'s own g2 check (a failing
/// neighbour raises a g2 finding's number).
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "report/contour_moves.hpp"
#include "report/report.hpp"

namespace cmr::report {

/// Limit of one violation's search, in evaluations: it ends there on any
/// machine and under any load, so a finding's severity is the same run to
/// run (the largest search of DejaVu's and Nimbus' Latin UFOs takes about
/// 19,000, in 0.02 s on this project's VM).
inline constexpr long kSeverityEvaluations = 200000;
/// A wall-clock guard on one violation's search (seconds), for a machine
/// too slow for kSeverityEvaluations: only where it ends a search can a
/// severity differ from run to run.
inline constexpr double kSeverityFixSeconds = 2;
/// A finding whose search found no move below kRefineBelow times the
/// threshold (or none) is searched again within the threshold alone.
inline constexpr double kRefineBelow = 8;
/// The default threshold of `--min-severity`: half a font unit.
inline constexpr double kDefaultMinSeverity = 0.5;

/// A report's severity options, checked (`cmr report`'s --min-severity,
/// --no-severity and --strict; the Python module's min_severity=,
/// severity=False and strict=): `min_severity` a distance >= 0 or none
/// (fonts then get kDefaultMinSeverity), `severity` false for none at all
/// (every finding fails), `strict` for info findings failing too.
/// InputFieldError (naming the fields) for a threshold that is not a
/// distance >= 0, a threshold without severity, or strict without severity.
void set_severity_options(ReportOptions& options, std::optional<double> min_severity, bool severity, bool strict);

/// Whether a gate's violations get a severity (and severity_move a search):
/// curvature-extrema-at-nodes, max-extrema-per-segment and g2-at-smooth-nodes.
bool has_severity(const Gate& gate);

/// One violation's severity and the move that has it.
struct SeverityMove {
  double distance = std::numeric_limits<double>::infinity();  ///< largest point displacement; +inf: none
  std::optional<BSpline> moved;  ///< the moved spline (found): the violation's place passes on it
  bool none_allowed = false;     ///< +inf because none of the place's points may move (`moves`)
  long evaluations = 0;          ///< the search's evaluations (judge calls): its work
};

/// The search behind a violation's severity (see above), at most `max_move`
/// (0: the curve size), moving only what `moves` allows. Each candidate is
/// judged on the violation's own segments (its segment, or the two meeting
/// at its joint, as a spline of their own with the same pieces); the answer
/// is re-judged on the whole spline, and searched again judging the whole
/// spline where that fails. Each search ends after `max_evaluations`
/// evaluations, or `max_seconds` of wall-clock time (the guard); the glyph
/// fix passes what is left of its own work and guard, so that no clock of
/// the severity's decides its fix.
SeverityMove severity_move(const BSpline& spline, const Gate& gate, const GateViolation& violation,
                           const ReportOptions& options, const ContourMoves& moves, double max_move = 0,
                           long max_evaluations = kSeverityEvaluations, double max_seconds = kSeverityFixSeconds);
/// The same with the moves of the spline as a contour
/// (contour_moves(contour_of(spline, {})): nodes from its knots, a straight
/// piece between two nodes a line).
SeverityMove severity_move(const BSpline& spline, const Gate& gate, const GateViolation& violation,
                           const ReportOptions& options, double max_move = 0);

/// The severities found in one run, by spline: a spline with the same
/// degree, knots, points and weights, bit for bit, as one already assessed
/// (an accented glyph's copy of its base letter's contour: Nimbus Sans'
/// Latin UFO has 631 contours, 432 distinct) gets its numbers without a
/// second search. The numbers are those the search gave the first copy,
/// so a run's numbers are what they are without the memo. For one run's
/// options only (the gates and threshold decide the findings); thread-safe.
class SeverityMemo {
 public:
  struct Entry {
    double severity = 0;
    SeverityOutcome outcome = SeverityOutcome::moved;
  };
  /// The entries of `spline` (one per violation of the gates that have a
  /// severity, in order), or empty when it was not assessed.
  std::optional<std::vector<Entry>> find(const BSpline& spline) const;
  void store(const BSpline& spline, std::vector<Entry> entries);

 private:
  mutable std::mutex mutex_;
  std::unordered_map<std::string, std::vector<Entry>> entries_;
};

/// Fills GateViolation::severity, ::severity_outcome and ::info of report.gates (see above) and
/// report.pass again. Nothing when options.min_severity < 0. With `memo`,
/// a spline assessed before in the run takes its numbers from there.
void assess_severity(SplineReport& report, const ReportOptions& options, SeverityMemo* memo = nullptr);

}  // namespace cmr::report
