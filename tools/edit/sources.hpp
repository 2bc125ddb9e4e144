#pragma once
// What `cmr edit` opens (issue 21, item 5): a spline file, every contour of
// one glyph of a font (`--glyph X`, with the node names `cmr import` and the
// report use), or every subpath of an SVG file. Several curves are shown
// together; one is edited at a time (Editor::switch_curve).
#include <filesystem>
#include <string>
#include <vector>

#include "spline/bspline.hpp"
#include "spline/vec2.hpp"

namespace cmr::edit {

struct OpenedCurve {
  BSpline spline;
  std::vector<std::string> point_names;  ///< one per distinct point; empty: P0, P1, ...
  std::string name;                      ///< "O/c0", "drawing/path1/s0", the file's name
  std::filesystem::path save_as;         ///< the spline JSON "save" writes (cmr import's file name); a UFO glyph: its .glif
  /// A glyph's contour (a binary font's, or a UFO's, io/ufo.hpp): its index
  /// in the glyph, per distinct control point the font's point index (-1: a
  /// straight piece's added inner point, neither drawn nor moved by hand)
  /// and whether it is an on-curve node; empty otherwise.
  int contour = -1;
  std::vector<int> font_point{};
  std::vector<bool> node{};
  /// The positions the .glif holds now (as opened, then as last saved): a
  /// save writes the points that differ from them.
  std::vector<Vec2> in_source{};
  std::vector<double> source_knots{};  ///< the knots as opened (a .glif cannot hold others)
};

struct OpenedSource {
  std::vector<OpenedCurve> curves;
  std::string what;  ///< one line: "glyph O of DejaVuSans.ttf: 2 contours"
  std::filesystem::path font;  ///< a font: its path (the glyph picker loads others from it)
  /// A font source's glyph (a UFO folder with --glyph NAME, or a .glif): the
  /// .glif "save" writes back into (only the moved points' x and y), and the
  /// font's grid (1 font unit) that dragged points snap to and saved
  /// coordinates are rounded to.
  std::filesystem::path glif;
  double grid = 0;
};

/// Opens FILE: a font with `glyph` (one character, or U+hex: every contour of
/// that glyph, saved as GLYPH_cK.json in `out_dir`, as `cmr import` names
/// them), a UFO folder with `glyph` (a glyph name, io/ufo.hpp's read_ufo)
/// or a single .glif (every contour, named by the source: "O/c0/p3"; saved
/// back into the .glif: Editor::save_source), an SVG file (every subpath, STEM_K.json), else a spline file
/// (read_spline_file; its point_names). InputError (one line) for a font
/// without --glyph or a glyph it lacks or that has no contour, --glyph with
/// a file that is not a font, an SVG without paths, a UFO glyph that is
/// invalid (its file and line) or has no contour.
OpenedSource open_source(const std::filesystem::path& file, const std::string& glyph,
                         const std::filesystem::path& out_dir = ".");

/// Writes the spline JSON of `spline` (with "point_names" when there is one
/// per distinct point) atomically (io/output.hpp).
void write_curve_file(const std::filesystem::path& path, const BSpline& spline, const std::vector<std::string>& names);

}  // namespace cmr::edit
