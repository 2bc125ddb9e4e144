#pragma once
/// The moves a designer can make on a font contour (issue 36, item 5): one
/// rule set for every search that moves a glyph's points, the glyph fix
/// (report/glyph_fix.hpp: `cmr fix` on font inputs, the report's "all"
/// fix) and the report's severity (report/severity.hpp).
///
///  - Only the source's own points move. A straight piece's inner points
///    (a UFO line's implied third-points, a TrueType line's midpoint) are no
///    source points: they never move, so a line stays a line.
///  - A node at either end of a straight piece stays where it is: moving it
///    alone would bend the line (its inner points stay), and moving the
///    line's inner points with it is not a move of source points. (So a
///    line's end node moves only together with what keeps the line
///    straight, which today means: not at all.)
///  - Smooth nodes keep G1 (FixRequest::keep = Keep::g1: a smooth node
///    moves with both handles, a handle slides along its node's tangent).
///
/// Which points are which comes from the contour (import::Contour: its
/// nodes and font points); for a bare spline, report::contour_of infers
/// them (nodes from the knots, a straight piece between two nodes as a line).
#include <string>
#include <vector>

#include "design/fix.hpp"
#include "io/font.hpp"

namespace cmr::report {

struct ContourMoves {
  /// The control points (indices into the contour's spline) that may move,
  /// ascending: source points that are not a straight piece's end node.
  std::vector<int> points;
  Keep keep = Keep::g1;  ///< smooth nodes keep G1
  /// Whether point k may move.
  bool movable(int k) const;
  /// `request` restricted to these moves: its points become those of
  /// request.points (every point when empty) that may move, its keep this
  /// keep. Returns false (request.points then empty) when none may.
  bool restrict(FixRequest& request) const;
};

/// The moves of contour `c` (see above).
ContourMoves contour_moves(const import::Contour& c);

/// The points of glyph `g` that `items` name, as whole names
/// (import::Contour::point_names): each item by its whole name ("o/c0/p9"),
/// a tail of it after a "/" ("c0/p9", or "p9" where one contour has it), or
/// its <point>'s name attribute (Glyph::point_labels). InputError (one
/// line, the field "points") for an item that names no point or several,
/// a line's inner point, or a point contour_moves does not let move.
std::vector<std::string> named_points(const import::Glyph& g, const std::vector<std::string>& items);

}  // namespace cmr::report
