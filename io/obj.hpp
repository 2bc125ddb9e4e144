#pragma once
/// Space curves from Wavefront OBJ files (issue 25): free-form curves and
/// polylines as cmr::SpaceSpline.
///
/// Read:
///   v x y z [w]          vertices (w, the weight of rational curves, default 1)
///   cstype [rat] bspline | bezier, deg D, curv U0 U1 I1 I2 ..., parm u K0 K1 ..., end
///       a free-form curve: control vertices I (1-based; negative counts back
///       from the last vertex), the full (conventional) knot vector of
///       points + D + 1 values for bspline; for bezier, the breakpoints of a
///       piecewise Bezier curve (points = pieces * D + 1) or none (one piece on
///       [U0, U1]). [U0, U1] must be the curve's whole domain.
///   l I1 I2 ...          a polyline, read as the control polygon of a clamped
///       uniform B-spline of degree min(3, vertices - 1) (at least 3 vertices).
///   o NAME / g NAME      names the curves that follow (else "curv" or "l")
/// Everything else (faces, normals, texture vertices, surfaces' statements
/// outside a curve) is skipped. Vertex coordinates are Cartesian and w a
/// separate weight (the spec: C(t) = sum N_i w_i P_i / sum N_i w_i): a `rat`
/// curve becomes a rational spline with its vertices' weights, which must be
/// given (`v x y z w`) and positive; equal weights are the polynomial curve
/// (written without weights). A non-rational curve ignores w. Errors are
/// InputError "FILE:LINE: what" (LINE: the curv statement; a weight's error
/// also names the vertex's line).
#include <filesystem>
#include <string>
#include <vector>

#include "spline/space.hpp"

namespace cmr::import {

struct ObjCurve {
  SpaceSpline spline;
  std::string kind;  ///< "curv" (free-form) or "l" (polyline)
  int line = 0;      ///< where it starts in the file
};

/// The curves of OBJ text; `where` prefixes messages (the file name).
/// InputError when there is none: "FILE: no curves (cstype/curv or l elements)".
std::vector<ObjCurve> parse_obj_curves(const std::string& text, const std::string& where);
/// The curves of an OBJ file (read_input_file's checks).
std::vector<ObjCurve> read_obj_curves(const std::filesystem::path& path);

}  // namespace cmr::import
