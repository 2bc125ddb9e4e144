#pragma once
/// The STEP importer's OpenCASCADE-typed entry (builds with OCCT only; tests
/// and the model generator use it): the curves of a shape already in memory.
#include <string>
#include <unordered_map>

#include <TopoDS_Shape.hxx>

#include "step/step.hpp"

namespace cmr::import {

/// The STEP entities of a transferred model's shapes, keyed by the shape's
/// TopoDS_TShape (located instances of one product share it): edges, faces,
/// shells and products (with the product's edge count: the smallest wins).
struct StepTrace {
  struct Entity {
    long long id = 0;
    std::string name;
    int size = 0;  ///< products: edges in its shape
  };
  std::unordered_map<const void*, Entity> edges, faces, shells, products;
};

/// As read_step_curves, on a shape: every distinct edge, converted or counted
/// in `skipped`. No curve is not an error here (curves may be empty).
/// `where` prefixes messages; `trace` (may be null) names the edges' entities.
/// Chains (StepCurves::chains) with `tolerances`.
StepCurves shape_curves(const TopoDS_Shape& shape, const std::string& where, const StepTrace* trace = nullptr,
                        const ChainTolerances& tolerances = {});

}  // namespace cmr::import
