#pragma once
/// The STEP importer's OpenCASCADE-typed entry (builds with OCCT only; tests
/// and the model generator use it): the curves of a shape already in memory.
#include <string>

#include <TopoDS_Shape.hxx>

#include "step/step.hpp"

namespace cmr::import {

/// As read_step_curves, on a shape: every distinct edge, converted or counted
/// in `skipped`. No curve is not an error here (curves may be empty).
/// `where` prefixes messages.
StepCurves shape_curves(const TopoDS_Shape& shape, const std::string& where);

}  // namespace cmr::import
