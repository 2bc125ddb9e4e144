#pragma once
/// Font sources in: UFO 2 and 3 folders, single .glif files and
/// .designspace documents (format 4 and 5), read as XML by pugixml and
/// their property lists as XML plists. Nothing is fetched, no entity is
/// expanded. And fixes out: a .glif's point coordinates rewritten in place,
/// every other byte of the file kept.
///
/// A UFO (unified font object, unifiedfontobject.org): `metainfo.plist`
/// (formatVersion 2 or 3), `fontinfo.plist` (unitsPerEm, familyName,
/// styleName), UFO 3's `layercontents.plist` (layer names and folders; the
/// default layer is the folder `glyphs`), the layer's `contents.plist`
/// (glyph name -> .glif file name, which carries the UFO's file-name
/// escaping: it is followed, never recomputed) and one .glif per glyph.
///
/// A .glif contour is a cyclic list of <point>s: on-curve points typed
/// `line`, `curve` or `qcurve` and off-curve points (no type, or
/// `offcurve`). A `curve` point ends a cubic piece (the two off-curve points
/// before it; none: a straight piece), a `qcurve` point ends a TrueType-style
/// quadratic run (any number of off-curve points, two in a row meeting at
/// their implied midpoint), a `line` point a straight piece. Contours become
/// the same closed splines as a binary font's (io/font.hpp,
/// outline_contour): cubic contours degree 3, quadratic ones degree 2,
/// contours of lines only the font's degree (2 when the source has quadratic
/// and no cubic pieces, else 3). Points are named by the .glif's own order,
/// "GLYPH/cC/pP" (contour C, point P of that contour), and a straight
/// piece's added inner points "GLYPH/cC/pP+pQ@1/3" (they are not in the
/// source and never move).
///
/// Not judged, with a note on the glyph: components (their base glyphs are
/// judged as themselves), open contours (a first point typed `move`; a
/// one-point `move` contour is a UFO 2 anchor and is skipped silently).
///
/// Errors name the file and the line ("a/glyphs/O_.glif:12: ..."): a
/// malformed plist, .glif or designspace; a glyph file listed in
/// contents.plist but missing; a `curve` point with 1 or more than 2
/// off-curve points before it (a "super Bezier" is not read); a contour that
/// mixes `curve` and `qcurve`; an off-curve point before a `line` or `move`
/// point; a coordinate that is not a finite number; two layers with the same
/// name. In a UFO, a glyph's own error makes that glyph invalid
/// (Glyph::error) and the others are read; a broken font-level file (a
/// plist) is an InputError for the whole source.
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "io/font.hpp"

namespace cmr::import {

/// Whether `path` names a font source cmr reads: a folder NAME.ufo, a file
/// NAME.glif or NAME.designspace (by its extension, any case).
bool is_source_path(const std::filesystem::path& path);
/// A UFO folder (NAME.ufo) or a single .glif file.
bool is_ufo_path(const std::filesystem::path& path);
bool is_designspace_path(const std::filesystem::path& path);

/// Which glyphs of a source to read.
struct GlyphSelection {
  bool all = false;                      ///< every glyph of the layer
  std::vector<std::uint32_t> codepoints; ///< glyphs with these code points (<unicode hex>), in this order
  std::vector<std::string> names;        ///< and glyphs by name (missing ones are an InputError)
};

/// A selection as `--glyphs SPEC` gives it (cmr report, cmr fix): "all", or
/// characters and ranges (parse_glyph_spec).
GlyphSelection parse_glyph_selection(const std::string& spec);

/// Reads a UFO folder (its default layer) or a single .glif file (then every
/// selection reads its one glyph, with unitsPerEm 0). Glyph::source is the
/// .glif's path and Glyph::point_lines its points' lines. Font::missing
/// lists the selected code points no glyph has. InputError as above.
/// keep_zero_lines: as outline_contour's (io/font.hpp).
Font read_ufo(const std::filesystem::path& path, const GlyphSelection& which, bool keep_zero_lines = false);

/// A designspace document: its axes and its sources (masters).
struct Designspace {
  struct Axis {
    std::string tag, name;
    double minimum = 0, maximum = 0, default_value = 0;  ///< user values
    /// A discrete axis (format 5 `values="0 1"`): its values, ascending
    /// (minimum and maximum are the first and last); empty for a continuous one.
    std::vector<double> values{};
    /// <map input="USER" output="DESIGN"/>, ascending in user value; empty:
    /// design values are user values. Sources' locations are design values.
    std::vector<std::pair<double, double>> map{};
    /// The map as a piecewise-linear function (either way; the ends extended).
    double to_design(double user) const;
    double to_user(double design) const;
  };
  struct Source {
    std::filesystem::path path;  ///< the source UFO, resolved against the document's folder
    std::string name;            ///< its `name` attribute (else the file name)
    std::map<std::string, double> location;  ///< axis name -> design value (missing axes at their default)
    bool is_default = false;     ///< at every axis's default
    int line = 0;                ///< of its <source> element
    std::string layer{};         ///< its `layer` attribute (a sparse master in a UFO's other layer); "" for the default layer
  };
  std::vector<Axis> axes;
  std::vector<Source> sources;
};
/// Reads a .designspace (format 4 or 5, discrete axes' `values` too: a
/// source's location on one is one of them, given as `xvalue` or, the same
/// on a discrete axis, `uservalue`; an axis's <map> is read). InputError
/// naming the file and line for a malformed document, an axis whose default
/// lies outside its range (on a discrete axis: is none of its values), a map
/// that is not increasing, two axes with one name, a source naming an
/// unknown axis or at no value of a discrete one, or a source UFO that does
/// not exist.
Designspace read_designspace(const std::filesystem::path& path);

/// A point added to a .glif contour (`cmr fix --add-nodes`): an off-curve
/// point, or a smooth on-curve one (type="curve" smooth="yes").
struct NewPoint {
  double x = 0, y = 0;
  bool node = false;
};
/// A new position for one source point of a .glif, and the points added
/// right after it.
struct PointEdit {
  int contour = 0;  ///< the contour's index in the .glif
  int point = 0;    ///< the point's index in its contour
  double x = 0, y = 0;
  bool move = true;                 ///< false: x and y stay as written (only `then` is added)
  std::vector<NewPoint> then = {};  ///< added after this point, in this order
};
/// The .glif text with the `x` and `y` attributes of the named points set to
/// the new values (integers without a decimal point, other values as the
/// shortest decimal that reads back as the double) and every other byte
/// unchanged, but for the added points: each a `<point x=".." y=".."/>`
/// element (with type="curve" smooth="yes" for a node) after its point's
/// element, each preceded by the whitespace that precedes that element.
/// InputError for a point the text does not have or a text that is not a
/// glyph.
std::string rewrite_glif_points(const std::string& text, const std::vector<PointEdit>& edits,
                                const std::string& file_name);

/// The glyph of a .glif's text, read as read_ufo reads a .glif named
/// `file_name` (its source), cubic when it has no off-curve point.
/// InputError as read_ufo's.
Glyph read_glif_text(const std::string& text, const std::string& file_name);

/// A coordinate as a .glif writes it: "455", "455.5", "-0.25".
std::string glif_number(double v);

}  // namespace cmr::import
