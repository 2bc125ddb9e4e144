#pragma once
/// A font source's glyph fixed for every required check on its grid: one
/// entry for `cmr fix FONT.ufo --glyph NAME` (tools/cmd_fix.cpp) and the
/// Python module's fix_glyph (python/cmr_module.cpp). It reads the glyph
/// (io/ufo.hpp: a UFO folder, or one .glif), resolves the named points
/// (named_points), runs fix_glyph (and, with GlyphFixOptions::add_nodes,
/// where it leaves a contour unfixed, fix_glyph again on the glyph with
/// nodes added: report/glyph_nodes.hpp) and writes the document's contours
/// (glyph_fix_json; a contour with nodes added has its "added_nodes"). Messages name their fields (spline/fields.hpp), which
/// each front end shows its own way.
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/ufo.hpp"
#include "report/glyph_fix.hpp"

namespace cmr::report {

/// Refuses (InputFieldError) a check the glyph fix cannot certify a fix
/// for: g3-at-smooth-nodes (the fix keeps g2 at most).
void check_fixable(const ReportOptions& checks);

/// The options of a source fix (`cmr fix FONT.ufo`, the Python module's
/// fix_glyph and fix_glyphs): the report's checks `require` judged at
/// `depth`, the grid step, the largest move (0: the contour's size), each
/// glyph's work (`cmr fix --work`; its guard in proportion, at least
/// kGlyphGuardSeconds). InputFieldError for a largest move that is not a
/// distance >= 0 or work outside 1..kMaxGlyphWork (the grid step:
/// fix_source_glyph and fix_source_glyphs check it).
GlyphFixOptions source_fix_options(const std::string& require, int depth, double grid, double max_move,
                                   long work = kGlyphWork);

struct SourceFix {
  import::Glyph glyph;                   ///< as read
  std::vector<std::string> points;       ///< the named points' whole names (GlyphFixOptions::points)
  nlohmann::ordered_json contours;       ///< glyph_fix_json: per contour its moves and re-judging
  std::vector<import::PointEdit> edits;  ///< the moved (and added) points, for import::rewrite_glif_points
  std::string failed;                    ///< the first unfixed contour's "GLYPH/cC: reason"; empty: a fix
};

/// Glyph `glyph` of `file` (empty for a .glif: the one it holds) fixed with
/// `options` (its `points` replaced by the whole names of `points`, which
/// may be tails or <point> name attributes). InputError (one line) for a
/// grid step below 0, a glyph the source lacks, a .glif holding another
/// glyph, a check with no fix, a point name that does not resolve, or a
/// glyph that cannot be read.
SourceFix fix_source_glyph(const std::string& file, const std::string& glyph, const std::vector<std::string>& points,
                           GlyphFixOptions options);

/// `cmr fix FONT.ufo --glyphs SPEC`: each selected glyph of a UFO fixed on
/// its own, as fix_source_glyph fixes one (its contours for every required
/// check, on the grid), the glyphs in parallel on up to `threads` threads
/// (0: every core). Each glyph's search is budgeted by work
/// (GlyphFixOptions::glyph_work), so the answers do not depend on the
/// threads.
struct SourceGlyphsFix {
  struct Item {
    SourceFix fix;          ///< as fix_source_glyph's (fix.glyph as read)
    bool already = false;   ///< every contour passed as it was
    /// Every finding's severity is below the threshold (the report passes
    /// the glyph as it is: its findings are `info`): not searched.
    bool below_severity = false;
    std::string error;      ///< the glyph could not be read or searched (one line); fix.contours empty
  };
  std::vector<Item> glyphs;  ///< the selection's glyphs with contours, in its order
  /// Selected glyphs without a contour to judge (components only, or empty),
  /// and selected code points no glyph has.
  std::vector<std::string> without_contours;
  std::vector<std::uint32_t> missing;
};

/// A glyph is searched only where `cmr report` fails it: with
/// `min_severity` >= 0 (the report's default for fonts,
/// kDefaultMinSeverity, half a font unit) a glyph whose every finding has a
/// certified move below it (report/severity.hpp: `info`, invisible at the
/// font's resolution) is left as it is (Item::below_severity); < 0 (the
/// report's --strict): every finding counts. A glyph that is searched is
/// fixed for every finding.
///
/// InputError (one line) as fix_source_glyph, and for a selection of no
/// glyph; a glyph's own failure (unreadable outline, or no fix) is its
/// item's, and the others go on. `progress` (when set) is called once per
/// glyph searched, one call at a time: glyphs done, glyphs in all, the
/// glyph's name.
using GlyphsProgress = std::function<void(std::size_t, std::size_t, const std::string&)>;
SourceGlyphsFix fix_source_glyphs(const std::string& ufo, const import::GlyphSelection& which,
                                  const GlyphFixOptions& options, double min_severity, int threads,
                                  const GlyphsProgress& progress = {});

/// What `cmr fix UFO --glyphs` prints and writes, and the Python module's
/// fix_glyphs returns: the document (file, require, grid; per glyph that
/// failed, "glyph", "fixed", its "contours" as for one glyph and, without a
/// fix, its "reason"; a "summary" of the counts), its messages with field
/// marks (spline/fields.hpp: each front end shows them its way), and the
/// new text of each fixed glyph's .glif (only the moved points' x and y).
struct SourceGlyphsOutput {
  nlohmann::ordered_json doc;
  std::vector<std::pair<std::string, std::string>> changed;  ///< .glif path, its new text
  std::vector<std::string> unfixed;                          ///< the glyphs with no fix
  int fixed = 0;
};
SourceGlyphsOutput source_glyphs_output(const SourceGlyphsFix& f, const std::string& ufo, const std::string& require,
                                        double grid);

}  // namespace cmr::report
