#pragma once
// Internal to cmr::design's kappa-curves: what the solver (kcurve.cpp) and the
// splines and notes of a solved curve (kcurve_chain.cpp) share.
#include <span>

#include "spline/vec2.hpp"

namespace cmr::kcurve_detail {

/// Consecutive points closer than this share of the extent are coincident.
constexpr double kCoincidentRelative = 1e-9;

// The diagonal of the points' bounding box (kcurve.cpp).
double extent_of(std::span<const Vec2> points);

}  // namespace cmr::kcurve_detail
