#pragma once
// What `cmr edit` opens (issue 21, item 5): a spline file, every contour of
// one glyph of a font (`--glyph X`, with the node names `cmr import` and the
// report use), or every subpath of an SVG file. Several curves are shown
// together; one is edited at a time (Editor::switch_curve).
#include <filesystem>
#include <string>
#include <vector>

#include "spline/bspline.hpp"

namespace cmr::edit {

struct OpenedCurve {
  BSpline spline;
  std::vector<std::string> point_names;  ///< one per distinct point; empty: P0, P1, ...
  std::string name;                      ///< "O/c0", "drawing/path1/s0", the file's name
  std::filesystem::path save_as;         ///< the spline JSON "save" writes (cmr import's file name)
};

struct OpenedSource {
  std::vector<OpenedCurve> curves;
  std::string what;  ///< one line: "glyph O of DejaVuSans.ttf: 2 contours"
  std::filesystem::path font;  ///< a font: its path (the glyph picker loads others from it)
};

/// Opens FILE: a font with `glyph` (one character, or U+hex: every contour of
/// that glyph, saved as GLYPH_cK.json in `out_dir`, as `cmr import` names
/// them), an SVG file (every subpath, STEM_K.json), else a spline file
/// (read_spline_file; its point_names). InputError (one line) for a font
/// without --glyph or a glyph it lacks or that has no contour, --glyph with
/// a file that is not a font, an SVG without paths.
OpenedSource open_source(const std::filesystem::path& file, const std::string& glyph,
                         const std::filesystem::path& out_dir = ".");

/// Writes the spline JSON of `spline` (with "point_names" when there is one
/// per distinct point) atomically (io/output.hpp).
void write_curve_file(const std::filesystem::path& path, const BSpline& spline, const std::vector<std::string>& names);

}  // namespace cmr::edit
