#pragma once
// Spline files: {"degree": d, "knots": [...], "points": [[x,y],...], "name": "optional"}.
// Without "knots" the file is one Bezier curve of degree points-1 ("degree",
// if given, must agree). Knots are polar-form (points + degree - 1 of them).
// Every error is an InputError whose message names the file, the field and
// the index ("spline.json: points[2][1] is not a number").
#include <filesystem>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "spline/bspline.hpp"

namespace cmr {

BSpline spline_from_json(const nlohmann::json& doc);
/// Reads and validates a spline file; messages are prefixed with the path.
BSpline read_spline_file(const std::filesystem::path& path);
nlohmann::json spline_to_json(const BSpline& spline);
/// Writes atomically (temporary file, then rename).
void write_spline_file(const std::filesystem::path& path, const BSpline& spline);

}  // namespace cmr
