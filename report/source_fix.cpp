#include "report/source_fix.hpp"

#include <cmath>
#include <filesystem>

#include "report/contour_moves.hpp"
#include "report/fix_json.hpp"
#include "spline/errors.hpp"
#include "spline/fields.hpp"

namespace cmr::report {

void check_fixable(const ReportOptions& checks) {
  for (const Gate& g : checks.gates)
    if (g.kind == Gate::Kind::g3_at_smooth_nodes)
      throw InputFieldError(field("require") + " " + to_string(g) +
                            ": cmr fix has no certified fix for G3 (it keeps g2 at most)");
}

SourceFix fix_source_glyph(const std::string& file, const std::string& glyph, const std::vector<std::string>& points,
                           GlyphFixOptions options) {
  const bool glif = std::filesystem::path(file).extension() == ".glif";
  if (glyph.empty() && !glif) throw InputFieldError(file + ": a font source; name the glyph with " + field("glyph") + " NAME");
  if (!(options.grid >= 0) || !std::isfinite(options.grid))
    throw InputFieldError(field("grid") + ": " + std::to_string(options.grid) + " is not a step >= 0");
  check_fixable(options.judge);
  import::GlyphSelection which;
  if (!glif) which.names = {glyph};
  const import::Font font = import::read_ufo(file, which);
  if (font.glyphs.empty()) throw InputError(file + ": no glyph '" + glyph + "'");
  SourceFix out;
  out.glyph = font.glyphs.front();
  const import::Glyph& g = out.glyph;
  if (glif && !glyph.empty() && glyph != g.name)
    throw InputError(file + ": holds the glyph '" + g.name + "', not '" + glyph + "'");
  if (!points.empty()) out.points = options.points = named_points(g, points);
  const std::vector<ContourFix> fixes = fix_glyph(g, options);
  out.contours = glyph_fix_json(g, fixes, options.grid, out.edits, out.failed);
  return out;
}

}  // namespace cmr::report
