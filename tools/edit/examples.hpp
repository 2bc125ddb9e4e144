#pragma once
/// Splines the editor carries in its binary (an installed cmr reads nothing
/// from the source tree).
#include "spline/bspline.hpp"

namespace cmr::edit {

/// The Fig. 8 spline of examples/figures/fig8.json (embedded at build time):
/// what `cmr edit --bench` drags without a FILE.
BSpline fig8_spline();

}  // namespace cmr::edit
