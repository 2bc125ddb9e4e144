#pragma once
// Internal to cmr::report: what the glyph fix (report/glyph_fix.cpp) says of
// a contour it could not fix, beside why its search ended: how far it got.
#include <string>

#include "io/font.hpp"
#include "report/report.hpp"

namespace cmr::report::glyph_detail {

/// Why the search for contour `c` ended without a fix (`why`; "" when it
/// said nothing: "no fix passes every check"), and where it left the
/// contour: `stopped`, which fails `stopped_total` violations of the checks
/// of `o` against the source's `source_total`. When that is fewer, the places
/// still failing follow, named as the report names them (a segment by its
/// nodes, "p3-p6", a joint by its node, "p19"), gate by gate, at most
/// kShownPlaces of them: "...; where the search stopped, 3 of the source's 8
/// violations are left: g2-at-smooth-nodes:0.05 at p6, p12, p19".
std::string unfixed_reason(const std::string& why, const import::Contour& c, const BSpline& stopped,
                           const ReportOptions& o, int stopped_total, int source_total);

inline constexpr int kShownPlaces = 6;

}  // namespace cmr::report::glyph_detail
