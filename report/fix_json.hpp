#pragma once
/// `cmr fix`'s JSON document (docs/fix.md) from a finished fix: the moves,
/// the units tried, the certificate (the fixed curve re-judged by analyze,
/// as `cmr analyze` prints its verdicts) and the counts. One writer for the
/// command (tools/cmd_fix.cpp, which adds "out" and "png") and the Python
/// module (python/cmr_module.cpp).
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "design/fix.hpp"
#include "design/space_fix.hpp"
#include "io/ufo.hpp"
#include "report/glyph_fix.hpp"

namespace cmr::report {

/// The document of `f`, the answer to `request`; "file" comes first when
/// given (the command names its input file; the Python module has none).
nlohmann::ordered_json fix_json(const std::optional<std::string>& file, const FixRequest& request, const FixResult& f);

/// The same for a space curve's fix (docs/fix.md, "Space curves"): 3D
/// moves with their planes, "dimension": 3, "joint_conflicts", and the
/// certificate's verdict of `cmr analyze` (analyze_space). `require` is
/// "cmr" or "cmrwi" as given.
nlohmann::ordered_json space_fix_document(const std::optional<std::string>& file, const std::string& require,
                                          const SpaceFixRequest& request, const SpaceFixResult& f);

/// The `contours` of a glyph fix's document (`cmr fix FONT.ufo --glyph
/// NAME`, the Python module's fix_glyph): per contour its moves by name
/// (with the <point>'s name attribute as "label", and "source": [contour,
/// point] in the .glif's order), every check re-judged, and why a contour
/// is not fixed (an untouched one, GlyphFixOptions::points naming none of
/// its points, is none of `failed`). Appends the source edits of the moved points to `edits`;
/// `failed` becomes the first unfixed contour's "GLYPH/cC: reason" (empty
/// when all are fixed). Reasons keep their field marks (spline/fields.hpp).
nlohmann::ordered_json glyph_fix_json(const import::Glyph& g, const std::vector<ContourFix>& fixes, double grid,
                                      std::vector<import::PointEdit>& edits, std::string& failed);

}  // namespace cmr::report
