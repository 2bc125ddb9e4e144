#pragma once
/// Font outlines as closed B-splines (FreeType; Debian libfreetype-dev).
///
/// Each glyph is loaded unscaled (FT_LOAD_NO_SCALE: font units, the font's
/// own grid) and each contour of its outline becomes one closed spline
/// (BSpline::make_closed, io/chain.hpp):
///  * TrueType (quadratic, conic tags): degree 2. The off-curve points are
///    the control points and two off-curve points in a row meet at their
///    implied on-curve midpoint (a simple knot of a uniform quadratic
///    B-spline, C1). An explicit on-curve point is a control point with a
///    double knot, so the curve passes through it whatever its position.
///  * CFF / OpenType-CFF (cubic tags): degree 3, a chain of cubic Bezier
///    pieces, every on-curve point a triple knot.
///  * Two on-curve points in a row are a straight piece, made exact by inner
///    points at 1/d..(d-1)/d of the way (a uniformly parametrised line).
///    An on-curve point equal to the previous one (a zero-length line) is
///    dropped (kept as a segment of equal points when reading masters for
///    the interpolation gates: keep_zero_lines).
/// Every piece is one unit-length span: segment i of the spline is the i-th
/// piece of the contour, starting at the contour's first on-curve point (or,
/// when it has none, at its first off-curve point's leading implied node).
/// Points are named as a font editor shows them: "GLYPH/cC" for the spline;
/// TrueType: "GLYPH/cC/pP" for the font's point P (the numbers hinting and
/// editors use) and "GLYPH/cC/pP+pQ" for the points the importer adds (an
/// implied node, a straight piece's midpoint); CFF (cubic): the on-curve
/// nodes numbered along the contour, "GLYPH/cC/n0", "n1", ..., each handle
/// after its node ("n3.out" leaves n3, "n4.in" arrives at n4) and a straight
/// piece's inner points "n3+n4@1/3", "n3+n4@2/3". font_point keeps the
/// font's point index either way.
///
/// Errors: InputError for a file FreeType cannot open as a font ("FILE: not a
/// font FreeType can read (error 2)"), a glyph spec that does not parse, or an
/// outline that is not a chain of pieces (a lone cubic control point).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "spline/bspline.hpp"

namespace cmr::import {

/// One contour of a glyph as a closed spline.
struct Contour {
  int index = 0;                         ///< contour number in the glyph
  BSpline spline;                        ///< closed; named "GLYPH/cC"
  std::vector<std::string> point_names;  ///< one per distinct control point
  std::vector<int> font_point;           ///< the font's point index per control point; -1 where added
  std::vector<bool> node;                ///< the control point is an explicit on-curve point
  std::vector<std::string> joint_names;  ///< per segment i: the node that starts it ("A/c0/p3", implied "A/c0/p2+p3")
  /// Per control point: the source point it comes from (font_point, or for a
  /// line's added inner point the line's first node), for locating it in a
  /// source file (a .glif's <point> line).
  std::vector<int> source_point;
  std::vector<int> joint_source_point;  ///< per segment: the source point of the node that starts it
};

struct Glyph {
  std::string name;         ///< the font's glyph name (else "uniXXXX")
  std::uint32_t codepoint = 0;
  std::vector<Contour> contours;
  /// Sources (a UFO's .glif, io/ufo.hpp): the .glif's path, and per contour
  /// (Contour::index) and source point the line of its <point> element;
  /// empty for binary fonts.
  std::string source;
  std::vector<std::vector<int>> point_lines;
  /// Sources: per contour and source point, its `name` attribute ("" where
  /// it has none): shown beside the point's own name ("O/c0/p3 (top)").
  std::vector<std::vector<std::string>> point_labels;
  /// Sources: per contour and source point, its smooth="yes" flag (the
  /// designer's "smooth node"); empty for binary fonts.
  std::vector<std::vector<bool>> point_smooth;
  /// Why the glyph cannot be judged (a malformed or unsupported outline in a
  /// source): it becomes an invalid item of a report; empty when it is read.
  std::string error;
  /// What was read but not judged (components, anchors), one line each.
  std::vector<std::string> notes;
};

struct Font {
  std::string path;
  std::string family, style;
  int units_per_em = 0;
  bool cubic = false;  ///< CFF or Type 1 outlines (degree 3); else TrueType (degree 2)
  std::vector<Glyph> glyphs;  ///< in the order asked for; characters the font lacks are left out
  std::vector<std::uint32_t> missing;
};

/// A point of an outline as a font format lists it: on the curve, or an
/// off-curve point of a quadratic (conic) or cubic piece.
struct OutlinePoint {
  enum class Tag : std::uint8_t { on, conic, cubic };
  Vec2 p{0.0};
  Tag tag = Tag::on;
};

/// How a contour's points are named: `editor` as a font editor shows a
/// binary font (TrueType "pP", CFF "nN", "nN.out", ...); `source` by the
/// point's index in the source's own order ("pP") whatever the degree, as a
/// UFO's .glif lists them.
enum class PointNaming : std::uint8_t { editor, source };

/// One contour (its points in the format's order, contour-relative indices)
/// as a closed spline of `degree` (2: conic off-curve points, 3: cubic),
/// named "GLYPH/cC"; nothing when it has no piece (a lone point). InputError
/// ("GLYPH/cC: ...") for an outline that is not a chain of pieces.
/// keep_zero_lines: a line of zero length (a node equal to the node before
/// it, the closing line included) is kept as a segment whose points are all
/// that node, instead of dropped: the interpolation gates read masters so
/// (io/masters.hpp), where a line may shrink to zero length in one master
/// and not in the others.
std::optional<Contour> outline_contour(const std::vector<OutlinePoint>& points, int contour, int degree,
                                       const std::string& glyph, PointNaming naming, bool keep_zero_lines = false);

/// Parses "A-Z,a-z,0-9,U+00E9,x": characters and inclusive ranges of them,
/// comma separated (UTF-8; "U+hex" for any code point; "," itself as "U+002C").
std::vector<std::uint32_t> parse_glyph_spec(const std::string& spec);

/// Whether a path names a font file the importer reads (.ttf, .otf, .ttc,
/// .otc, .cff, .pfb, .pfa, .t1, .woff), by its extension.
bool is_font_path(const std::filesystem::path& path);

/// A variable font's instance: axis tag -> user value ("wght=700,opsz=14").
using Location = std::vector<std::pair<std::string, double>>;
/// Parses "TAG=VALUE,TAG=VALUE" (InputError "--location: ..." otherwise).
Location parse_location(const std::string& text);

/// Loads the glyphs of `codepoints` (unscaled, unhinted); none given: every
/// code point of the font's character map, in code point order. With a
/// `location`, the glyphs of that instance of a variable font (TrueType
/// gvar or CFF2, through FreeType's variation API: design coordinates, so
/// `avar` is applied), axes not named at their defaults; InputError for a
/// font without variations (no fvar), an axis it does not have or a value
/// outside the axis's range. Font::style then names the location.
///
/// With `blend` (one value per axis), the instance at those normalised
/// coordinates after avar (FreeType's blend coordinates, -1..1) instead:
/// the ends of the interpolation gates' pieces (io/masters.hpp).
/// keep_zero_lines: as outline_contour's.
Font read_font(const std::filesystem::path& path, const std::vector<std::uint32_t>& codepoints,
               const Location& location = {}, const std::vector<double>& blend = {}, bool keep_zero_lines = false);

/// A variable font's design space as the interpolation gates cut it
/// (io/masters.hpp).
struct Variations {
  struct Axis {
    std::string tag, name;
    double minimum = 0, default_value = 0, maximum = 0;  ///< user values (fvar)
    /// avar's segment map of the axis: (from, to) normalised values,
    /// ascending; empty: none (the identity).
    std::vector<std::pair<double, double>> avar{};
  };
  std::vector<Axis> axes;
  /// Per axis: the normalised coordinates (after avar) where some variation
  /// region starts, peaks or ends on it, with -1, 0 and 1; ascending,
  /// distinct. From gvar's tuple headers (shared and embedded peaks,
  /// intermediate regions) or CFF2's item variation store regions.
  std::vector<std::vector<double>> cuts;
  /// Every region's peak (one normalised value per axis), distinct.
  std::vector<std::vector<double>> peaks;
};
/// Reads fvar, avar and the regions of gvar or CFF2. InputError "FONT: no
/// fvar table: ..." for a font without variations, and for tables that do
/// not parse.
Variations read_variations(const std::filesystem::path& path);

/// The contour as a spline file (spline_to_json plus "point_names", and for
/// a source whose points have `name` attributes "point_labels": one per
/// control point, "" where none; `labels` are the glyph's, per source point).
nlohmann::json contour_json(const Contour& contour, const std::vector<std::string>* labels = nullptr);
/// The `name` attribute of each control point of `contour` ("" where none).
std::vector<std::string> contour_labels(const Contour& contour, const std::vector<std::string>& labels);

/// A file name for a glyph name: [A-Za-z0-9._-] kept, others as _XX hex.
std::string file_stem(const std::string& glyph_name);

}  // namespace cmr::import
