#pragma once
/// The picture of the region of a weight (region/weight_region.hpp).
#include <string>

#include "region/weight_region.hpp"
#include "spline/bspline.hpp"

namespace cmr {

/// The picture of a weight region: above, the curves of a handful of weights
/// of [A, B] (equally spaced, and each interval's middle) drawn thin in their
/// label's colour, with the spline's own curve and control polygon; below, a strip coloured by label (the colours and
/// legend of region pictures, draw/draw.hpp) over a weight axis with ticks,
/// the spline's current weight w_K marked. `svg`: SVG text, else PNG bytes.
std::string weight_region_picture(const BSpline& spline, const WeightRegionRequest& request,
                                  const WeightRegion& region, bool svg, int width = 800, int height = 520);

}  // namespace cmr
