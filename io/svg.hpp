#pragma once
/// SVG path data as B-splines (SVG 1.1 §8.3, "paths"; arcs per Appendix F.6).
///
/// The document is read by an XML parser (pugixml): comments, CDATA,
/// processing instructions and the DOCTYPE are not elements, so a <path> in
/// a comment is not imported; attribute values are normalised and the five
/// predefined entities and character references expanded as XML says;
/// entities a DOCTYPE declares are never expanded (no internal or external
/// entity expansion, nothing is fetched). Every <path d="..."> element is
/// read (any namespace prefix; other elements and styles are ignored), with
/// the `transform` of the path and of every enclosing element applied
/// (SVG 1.1 §7.6: translate, scale, rotate with or without a centre, skewX,
/// skewY, matrix). By default the result is flipped to cmr's y-up frame
/// (x, y) -> (x, -y), so a drawing keeps its look in cmr's pictures;
/// SvgOptions::flip_y = false keeps SVG's y-down coordinates. Nothing here
/// recurses on the input: the element tree is walked with an explicit
/// stack and path data by a linear scanner. Commands M/L/H/V/C/S/Q/T/A/Z, absolute (upper
/// case) and relative (lower case, each coordinate pair relative to the
/// current point at the start of its own segment); repeated coordinate sets
/// continue the command (after M/m as L/l); S/T reflect the previous C/S
/// (Q/T) control point, else use the current point.
///
/// Each subpath becomes one spline: a chain of Bezier pieces, one unit-length
/// span per piece, every node a knot of multiplicity d (C0; smoothness is the
/// tangents'). All pieces are raised to the subpath's highest degree (lines
/// 1, Q/T 2, C/S 3, arcs 2), at least 2: a line as a uniformly parametrised
/// Bezier curve, a curve by degree elevation (in homogeneous coordinates
/// when rational). "Z" closes the subpath (a line back to its start when the
/// current point is elsewhere) and the spline is closed (BSpline::make_closed).
/// An arc is converted to rational quadratic pieces of at most 90 degrees
/// each: ends on the ellipse, middle point where the end tangents meet, with
/// weight cos(half the sweep) (the other weights 1). A subpath with an arc is
/// a rational spline: its file carries "weights", one per control point.
/// Degenerate arcs follow F.6.2: equal ends draw nothing, a zero radius a line.
///
/// Every computed coordinate and weight is checked finite (an arc or a sum
/// of relative moves can overflow although each number is finite).
///
/// Errors: InputError naming the file, the path's number and the offset in
/// its d attribute ("drawing.svg: path 2, d[14]: expected a number",
/// "drawing.svg: path 0, d[5]: the arc's coordinates are not finite"), or
/// the byte offset of a malformed document or transform
/// ("drawing.svg: not well-formed XML at byte 40: ...").
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "spline/bspline.hpp"

namespace cmr::import {

/// One subpath as a (possibly rational, possibly closed) B-spline.
struct PathSpline {
  std::string name;
  int degree = 2;
  bool closed = false;
  std::vector<double> knots;   ///< polar knots (open), or the m+1 period knots (closed)
  std::vector<Vec2> points;    ///< control points (closed: the m distinct ones)
  std::vector<double> weights; ///< one per point when rational; empty when every weight is 1
  bool rational() const { return !weights.empty(); }
};

/// How read_svg places the drawing.
struct SvgOptions {
  bool flip_y = true;  ///< (x, y) -> (x, -y): cmr's y-up frame; false keeps SVG's y-down coordinates
};

/// The 2x3 affine map x' = a x + c y + e, y' = b x + d y + f (SVG's matrix(a b c d e f)).
struct Affine {
  double a = 1, b = 0, c = 0, d = 1, e = 0, f = 0;
  Vec2 operator()(Vec2 p) const { return {a * p.x + c * p.y + e, b * p.x + d * p.y + f}; }
};
/// `outer` after `inner`: (outer * inner)(p) = outer(inner(p)).
Affine operator*(const Affine& outer, const Affine& inner);

/// A transform attribute (SVG 1.1 §7.6) as one affine map; the list's first
/// transform is the outermost. InputError "transform[K]: ..." at offset K.
Affine parse_transform(const std::string& text);

/// The subpaths of one d attribute; names are "PREFIX/sK". Coordinates as
/// written (no transform, no flip).
std::vector<PathSpline> parse_path_data(const std::string& d, const std::string& prefix);

/// Every path of an SVG document held in `text`; `name` is the file name used
/// in messages and `stem` the prefix of the spline names.
std::vector<PathSpline> read_svg_text(const std::string& text, const std::string& name, const std::string& stem,
                                      const SvgOptions& options = {});

/// Every path of an SVG file; names "STEM/pathN/sK" (or the path's id for pathN).
std::vector<PathSpline> read_svg(const std::filesystem::path& path, const SvgOptions& options = {});

/// Whether `path` names an SVG file (extension .svg, any case).
bool is_svg_path(const std::filesystem::path& path);

/// The spline file: degree, knots, points, name, "closed" when closed and
/// "weights" when rational.
nlohmann::json path_json(const PathSpline& s);

/// The spline itself (with its weights when rational, closed when closed).
BSpline to_bspline(const PathSpline& s);

/// Point at parameter t of a (rational) Bezier piece with homogeneous
/// weights: sum w_i P_i B_i(t) / sum w_i B_i(t) (de Casteljau on (wP, w)).
Vec2 rational_bezier_point(const std::vector<Vec2>& points, const std::vector<double>& weights, double t);

}  // namespace cmr::import
