#pragma once
/// The smallest certified fix of each failing check of a report
/// (bezierize/fix.hpp): the requirement (cmrwi, cmr, split:S[:max|min]) and
/// the extrema-at-nodes gate. Each is fix() with the report's depth, the
/// spline's G1 joints kept, the end points of an open spline fixed, and a
/// time limit; its certificate is analyze on the moved spline. The other
/// gates (max-extrema-per-segment, g2-at-smooth-nodes, no-inflection) have
/// no fix requirement and get none.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bezierize/fix.hpp"

namespace cmr::report {

struct SplineReport;
struct ReportOptions;

/// One check's fix: which points move where, and the certificate.
struct CertifiedFix {
  std::string check;              ///< "cmr", "split:2:max", "extrema-at-nodes"
  bool found = false;             ///< a fix the certificate holds for
  std::vector<PointMove> moves;   ///< empty when none
  double size = 0;                ///< the curve size displacements are relative to
  std::string reason;             ///< why none (one line)
};

/// Time limit of each fix in a report (seconds).
inline constexpr double kReportFixSeconds = 2;

/// The fixes of a failing spline's requirement and extrema-at-nodes gate.
std::vector<CertifiedFix> certified_fixes(const SplineReport& report, const ReportOptions& options);

/// {"check", "found", "moves": [{"point", "from", "to", "distance", "relative"}], "reason"?}
nlohmann::ordered_json certified_fix_json(const CertifiedFix& fix);
/// One HTML paragraph: "Smallest certified fix (cmr): move P3 by (dx, dy) …".
std::string certified_fix_html(const CertifiedFix& fix);

}  // namespace cmr::report
