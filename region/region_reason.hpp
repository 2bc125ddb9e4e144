#pragma once
// Internal to cmr::region and the libraries above it: a library user includes
// `region/region.hpp` (space curves: `region/space_region.hpp`).
/// Why a point's region is empty or covers the whole view (issue 20, item 2):
/// one line naming the segment(s) responsible, for `cmr region`'s stderr
/// note, the region picture's caption and the editor. Exact: read from the
/// prepared problem (which judged segments the point acts on, and the
/// certified classes of those it does not act on), not from the pixels.
#include <optional>
#include <string>
#include <vector>

#include "region/region.hpp"

namespace cmr {

/// The judged segments the point (and its rigid group) acts on, ascending.
std::vector<int> acted_segments(const RegionProblem& problem);

/// The judged segments the point does not act on that fail for every
/// position (not monotone; in CMR mode also an inflection; or a pole).
std::vector<int> fixed_failing_segments(const RegionProblem& problem);

/// "segments 2..4", "segment 3", "segments 0, 2, 5".
std::string segment_list_text(const std::vector<int>& segments);

/// The one-line reason, or nothing when the region is neither empty nor full:
///  * "P0 does not act on segments 2..2: every position gives the same answer"
///    (no judged segment is in the point's support: all or nothing);
///  * "segment 0 is non-monotone whatever P5 does" (a judged segment outside
///    the support fails);
///  * for a closed curve judged over its whole period: "a closed curve's
///    curvature is never monotone over its period: judge the spans P3 acts on
///    (--segments 1..3)";
///  * otherwise "no monotone position of P3 in this view (the region may lie
///    outside it: try a larger --view)" or, when full, "P3's region covers
///    the whole view (it extends beyond it)".
std::optional<std::string> region_reason(const RegionProblem& problem, const RegionResult& result);

/// The support of point k (and `with`) on a closed spline as a range that
/// does not cross the seam, or nothing (the support wraps around the seam,
/// or the spline is open).
std::optional<SegmentRange> closed_support_range(const BSpline& spline, int point, const std::vector<int>& with = {});

}  // namespace cmr
