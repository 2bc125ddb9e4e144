#pragma once
// The editor's one doorway into the engine: regions, verdicts, curvature
// events. Every call into bezierize/region.hpp, bezierize/analyze.hpp and the
// report's root finding made by `cmr edit` is in engine.cpp, so an API change
// there is ported in one file.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "bezierize/analyze.hpp"
#include "bezierize/region.hpp"
#include "spline/bspline.hpp"

namespace cmr::edit {

/// What the region view shows: one layer per entry of `points` (each point
/// with its rigid companions `with` when there is one layer, alone when every
/// point is overlapped), judged as `cmr region` judges it.
struct RegionQuery {
  std::vector<int> points;  ///< one layer per point
  std::vector<int> with;    ///< rigid companions of points[0] (single layer only)
  Mode mode = Mode::cmrwi;
  std::optional<int> split;
  int max_depth = 12;
  bool depth_map = false;   ///< compute decision levels (Fig. 7 shading)
  View view;
  int width = 0, height = 0;
};

/// The label maps of a query, computed on the CPU (all cores), certified: each
/// equals `cmr region FILE --point K --view ... --size WxH` for the same state.
std::vector<RegionResult> compute_regions(const BSpline& spline, const RegionQuery& query);

/// RGBA bytes (row-major, row 0 at the top) of the layers, in the colours of
/// `cmr region --png` (tools/draw.hpp's legend: red increasing, blue
/// decreasing, overlaps darker, optional depth shading).
std::vector<uint8_t> region_rgba(const std::vector<RegionResult>& layers, bool split, bool depth_shading,
                                 int max_depth);

/// Verdicts of the spline as `cmr analyze` gives them (InputError for a split
/// joint the spline lacks).
SplineAnalysis verdicts(const BSpline& spline, int max_depth, std::optional<int> split, Mode mode);

/// Certified curvature extrema and inflections of the whole curve (as `cmr
/// report` finds them), for marking the comb and the plot.
struct CurvatureEvents {
  std::vector<double> maxima, minima, inflections;  ///< parameters
};
CurvatureEvents curvature_events(const BSpline& spline, int max_depth);

/// A knot operation by name on a copy of the spline: "insert" (a = u, b =
/// times, default 1), "remove" (a = u, b = tolerance), "elevate", "clamp",
/// "uniform". Returns the new spline and a status line; throws InputError when
/// the operation does not apply (a removal the shape does not allow within the
/// tolerance, a knot outside the domain, an operation this build lacks).
struct KnotResult {
  BSpline spline;
  std::string message;
};
KnotResult knot_operation(const BSpline& spline, const std::string& name, double a, double b);

}  // namespace cmr::edit
