#pragma once
/// The report of a font (`cmr report FONT`): its glyph contours as report
/// items (one closed spline each, io/font.hpp) and one page a type
/// designer works from: an overview table with one row per glyph (thumbnail
/// with curvature comb, pass/fail per gate, sortable by any column and
/// filterable by name and status), then per glyph and contour the gate
/// violations located by node names and the smallest certified fix of each
/// failing check (report/certified_fix.hpp): the points to move by name,
/// their displacement, the curvature before and after, and the fixed outline
/// beside the original.
#include <cstdint>
#include <string>
#include <vector>

#include "io/font.hpp"
#include "report/report.hpp"

namespace cmr::report {

/// A font's glyphs and which report items are their contours.
struct FontInfo {
  std::string path, family, style;
  int units_per_em = 0;
  bool cubic = false;
  struct GlyphEntry {
    std::string name;
    std::uint32_t codepoint = 0;
    std::vector<std::size_t> items;                     ///< indices of its contours among the report items
    std::vector<std::vector<std::string>> joint_names;  ///< per contour: node name starting each segment
    std::vector<std::vector<std::string>> point_names;  ///< per contour: name of each distinct control point
    /// Sources (a UFO's .glif): its path, and per contour the line of each
    /// control point's and each segment's starting node's <point>; empty
    /// for binary fonts.
    std::string source;
    std::vector<std::vector<int>> point_lines, joint_lines;
  };
  std::vector<GlyphEntry> glyphs;
  std::vector<std::uint32_t> missing;
};

/// A point's name without the glyph and contour that a glyph section's
/// heading says: "g/c0/n6+n7@1/3" -> "n6+n7@1/3" (the whole rest of the
/// name, which may hold a '/' of its own). A name without that prefix is
/// kept whole.
std::string local_name(const std::string& name, const std::string& glyph, std::size_t contour);

/// `word` as one word of a POSIX shell command: as it is when it is plain,
/// else in single quotes (the commands the page and the Markdown print).
std::string shell_word(const std::string& word);

/// The one count of a font every page uses (font page, summary page):
/// "318 glyphs: 120 pass, 198 fail; 643 contours: 319 pass, 324 fail" (a
/// glyph passes when all its contours do; invalid contours fail).
std::string glyph_count_text(int glyphs, int glyphs_fail, int contours, int contours_fail);

/// Appends one report item per contour of `font` to `inputs` (file
/// "FONT:GLYPH/cC") and returns where they went.
FontInfo font_inputs(const import::Font& font, std::vector<ReportInput>& inputs);

/// One glyph's part of a font page: its row of the overview table and its
/// section, with what the page's counts take of it (the report's resume
/// cache keeps it: report/report_cache.hpp).
struct GlyphHtml {
  std::string row, details;
  bool pass = true;  ///< every contour valid and passing
  int contours = 0, contours_fail = 0;
};
/// Glyph `glyph` of `font`, the `font_index`-th font of its page.
GlyphHtml font_glyph_html(const FontInfo& font, std::size_t font_index, std::size_t glyph,
                          const std::vector<SplineReport>& reports, const ReportOptions& options);
/// The page of `fonts` from their glyphs' parts (glyphs[f][g]: glyph g of font f).
std::string font_page_html(const std::vector<FontInfo>& fonts, const std::vector<std::vector<GlyphHtml>>& glyphs,
                           const ReportOptions& options);

/// One self-contained page (no network) for the fonts' glyphs. Thumbnails
/// (inline SVG, curvature comb) are drawn when options.regions is on (they
/// are what --no-thumbnails leaves out).
std::string font_report_html(const std::vector<FontInfo>& fonts, const std::vector<SplineReport>& reports,
                             const ReportOptions& options);

}  // namespace cmr::report
