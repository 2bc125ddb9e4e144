#pragma once
/// How much a finding matters (`cmr report --min-severity UNITS`, docs/report.md
/// "Severity"): the smallest certified move that removes it.
///
/// For each violation of a gate that has a fix (curvature-extrema-at-nodes and
/// max-extrema-per-segment: an extremum inside segment i; g2-at-smooth-nodes:
/// a jump at joint j), fix() (bezierize/fix.hpp) searches the nearest move of
/// the points of that segment (of the two segments meeting at that joint),
/// with smooth nodes kept G1, judged by the gate itself: the violation at that
/// place must be gone (others may come or go: this measures the one finding,
/// not a fix of the glyph). The severity is the fix's largest point
/// displacement, in the spline's units (font units for a font); +inf when the
/// search finds none within its time limit (kSeverityFixSeconds). A violation
/// whose severity is below ReportOptions::min_severity (half a grid unit by
/// default: a move the font's grid cannot even express) is `info`: reported,
/// but it does not fail its gate, unless ReportOptions::strict.
#include "report/report.hpp"

namespace cmr::report {

/// Time limit of one violation's search (seconds).
inline constexpr double kSeverityFixSeconds = 0.5;
/// The default threshold of `--min-severity`: half a font unit.
inline constexpr double kDefaultMinSeverity = 0.5;

/// Fills GateViolation::severity and ::info of report.gates (see above) and
/// report.pass again. Nothing when options.min_severity < 0.
void assess_severity(SplineReport& report, const ReportOptions& options);

}  // namespace cmr::report
