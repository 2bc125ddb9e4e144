#include "report/source_fix.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>

#include "report/batch.hpp"
#include "report/contour_moves.hpp"
#include "report/fix_json.hpp"
#include "report/glyph_nodes.hpp"
#include "report/severity.hpp"
#include "spline/errors.hpp"
#include "spline/fields.hpp"
#include "spline/format.hpp"
#include "spline/parallel.hpp"
#include "spline/spline_json.hpp"

namespace cmr::report {

void check_fixable(const ReportOptions& checks) {
  for (const Gate& g : checks.gates)
    if (g.kind == Gate::Kind::g3_at_smooth_nodes)
      throw InputFieldError(field("require") + " " + to_string(g) +
                            ": cmr fix has no certified fix for G3 (it keeps g2 at most)");
}

GlyphFixOptions source_fix_options(const std::string& require, int depth, double grid, double max_move,
                                   long work) {
  if (!(max_move >= 0) || !std::isfinite(max_move))
    throw InputFieldError(field("max_move") + ": " + format_number(max_move) + " is not a distance >= 0");
  if (work < 1 || work > kMaxGlyphWork)
    throw InputFieldError(field("glyph_work") + ": " + std::to_string(work) + " is outside 1.." +
                          std::to_string(kMaxGlyphWork) + " work units");
  GlyphFixOptions o;
  o.glyph_work = work;
  o.guard_seconds = std::max(kGlyphGuardSeconds, kGlyphGuardSeconds * static_cast<double>(work) / kGlyphWork);
  parse_require_list(require, o.judge);
  o.judge.max_depth = depth;
  o.grid = grid;
  o.max_move = max_move;
  return o;
}

namespace {

void check_grid_and_checks(const GlyphFixOptions& options) {
  if (!(options.grid >= 0) || !std::isfinite(options.grid))
    throw InputFieldError(field("grid") + ": " + format_number(options.grid) + " is not a step >= 0");
  check_fixable(options.judge);
  if (options.add_nodes && !(options.grid > 0))
    throw InputFieldError(field("add_nodes") + " needs the grid (" + field("grid") + " > 0): its new nodes land on it");
}

/// The glyph's fixes, where a contour found none in its share of the work
/// saying that a larger budget searches further (DejaVu Sans `s` under both
/// type gates needs 4.8 M units: `cmr fix --work 6000000`).
std::vector<ContourFix> noting_work(std::vector<ContourFix> fixes, long budget) {
  for (ContourFix& f : fixes)
    if (f.out_of_work)
      f.reason += "; its share of the glyph's work ran out (" + std::to_string(budget) + " units a glyph): a larger " +
                  field("glyph_work") + " searches further";
  return fixes;
}

/// The glyph's fix into `out` (its contours, edits and failure), and with
/// options.add_nodes, where it leaves a contour unfixed, the glyph fixed
/// again with nodes added (report/glyph_nodes.hpp): taken where that fixes
/// every contour, else the first failure stays, with why the second did not
/// help. True where every contour passed as it was.
bool fix_into(const import::Glyph& g, const GlyphFixOptions& options, SourceFix& out) {
  const std::vector<ContourFix> fixes = noting_work(fix_glyph(g, options), options.glyph_work);
  out.contours = glyph_fix_json(g, fixes, options.grid, out.edits, out.failed);
  const bool already = std::all_of(fixes.begin(), fixes.end(), [](const ContourFix& f) { return f.already; });
  if (!options.add_nodes || out.failed.empty()) return already;
  const std::string text = read_input_file(g.source);
  std::optional<NodesAdded> added = add_nodes(g, text, fixes, options);
  if (!added) {
    out.failed += "; " + field("add_nodes") + " finds no segment to split (no curvature extremum inside a cubic, "
                  "nor a cubic's smooth join with a line failing g2)";
    return already;
  }
  std::vector<import::PointEdit> edits;
  std::string failed;
  nlohmann::ordered_json contours;
  auto fix_added = [&] {
    edits.clear(), failed.clear();
    contours = glyph_fix_json(added->glyph, noting_work(fix_glyph(added->glyph, options), options.glyph_work),
                              options.grid, edits, failed);
  };
  fix_added();
  if (!failed.empty())
    out.failed += "; with " + std::to_string(added->nodes.size()) + " nodes added, no fix either: " + failed;
  if (!failed.empty() && splits_a_join(*added)) {  // two nodes at each failing line join instead of one
    added = add_nodes(g, text, fixes, options, 2);
    fix_added();
    if (!failed.empty())
      out.failed += "; nor with two at each line join (" + std::to_string(added->nodes.size()) + " nodes): " + failed;
  }
  if (!failed.empty()) return already;
  // An added node where the fix leaves it (moved, or where the split put it).
  auto final_at = [&](const AddedNode& n) {
    for (const import::PointEdit& e : edits)
      if (e.contour == n.contour && e.point == n.point) return nlohmann::ordered_json::array({e.x, e.y});
    return nlohmann::ordered_json::array({n.at.x, n.at.y});
  };
  for (auto& c : contours) {
    nlohmann::ordered_json nodes = nlohmann::ordered_json::array();
    for (const AddedNode& n : added->nodes)
      if (c.value("contour", -1) == n.contour)
        nodes.push_back({{"point", g.name + "/c" + std::to_string(n.contour) + "/p" + std::to_string(n.point)},
                         {"splits", n.segment},
                         {"t", n.t},
                         {"at", final_at(n)},
                         {"why", n.why}});
    if (!nodes.empty()) c["added_nodes"] = nodes;
  }
  out.contours = contours;
  out.edits = source_edits(*added, edits);
  out.failed.clear();
  return false;
}

}  // namespace

SourceFix fix_source_glyph(const std::string& file, const std::string& glyph, const std::vector<std::string>& points,
                           GlyphFixOptions options) {
  const bool glif = std::filesystem::path(file).extension() == ".glif";
  if (glyph.empty() && !glif) throw InputFieldError(file + ": a font source; name the glyph with " + field("glyph") + " NAME");
  check_grid_and_checks(options);
  import::GlyphSelection which;
  if (!glif) which.names = {glyph};
  const import::Font font = import::read_ufo(file, which);
  if (font.glyphs.empty()) throw InputError(file + ": no glyph '" + glyph + "'");
  SourceFix out;
  out.glyph = font.glyphs.front();
  const import::Glyph& g = out.glyph;
  if (glif && !glyph.empty() && glyph != g.name)
    throw InputError(file + ": holds the glyph '" + g.name + "', not '" + glyph + "'");
  if (!points.empty() && options.add_nodes)
    throw InputFieldError(field("add_nodes") + " with " + field("points") +
                          ": the named points are the source's, and added nodes renumber them; choose one");
  if (!points.empty()) out.points = options.points = named_points(g, points);
  fix_into(g, options, out);
  return out;
}

namespace {

enum class ReportVerdict { passes, passes_with_info, fails };

/// `cmr report`'s verdict of the glyph at `min_severity` (>= 0): each
/// contour judged with its findings' severities (report/severity.hpp);
/// passes_with_info where it passes with some info finding.
ReportVerdict report_verdict(const import::Glyph& g, const ReportOptions& checks, double min_severity) {
  ReportOptions o = judge_only(checks);
  o.min_severity = min_severity;
  bool info = false;
  for (const import::Contour& c : g.contours) {
    SplineReport r = judged_report(c.spline, o);
    assess_severity(r, o);
    if (!r.pass) return ReportVerdict::fails;
    for (const GateResult& gate : r.gates)
      info = info || std::any_of(gate.violations.begin(), gate.violations.end(),
                                 [](const GateViolation& v) { return v.info; });
  }
  return info ? ReportVerdict::passes_with_info : ReportVerdict::passes;
}

}  // namespace

SourceGlyphsFix fix_source_glyphs(const std::string& ufo, const import::GlyphSelection& which,
                                  const GlyphFixOptions& options, double min_severity, int threads,
                                  const GlyphsProgress& progress) {
  if (std::filesystem::path(ufo).extension() == ".glif")
    throw InputFieldError(ufo + ": one glyph's .glif; " + field("glyphs") + " selects glyphs of a UFO folder");
  check_grid_and_checks(options);
  const import::Font font = import::read_ufo(ufo, which);
  SourceGlyphsFix out;
  out.missing = font.missing;
  for (const import::Glyph& g : font.glyphs) {
    if (g.error.empty() && g.contours.empty()) {
      out.without_contours.push_back(g.name);
      continue;
    }
    SourceGlyphsFix::Item item;
    item.fix.glyph = g;
    item.error = g.error;
    out.glyphs.push_back(std::move(item));
  }
  if (out.glyphs.empty() && out.without_contours.empty())
    throw InputError(ufo + ": the selection names no glyph of the font");
  std::mutex reporting;
  std::size_t done = 0;
  parallel_for(out.glyphs.size(), threads, [&](std::size_t i) {
    SourceGlyphsFix::Item& item = out.glyphs[i];
    const import::Glyph& g = item.fix.glyph;
    if (item.error.empty()) {
      try {
        const ReportVerdict v = min_severity >= 0 ? report_verdict(g, options.judge, min_severity) : ReportVerdict::fails;
        if (v != ReportVerdict::fails) {  // as fix_glyph would find: every contour passes (or only info fails)
          item.already = v == ReportVerdict::passes;
          item.below_severity = v == ReportVerdict::passes_with_info;
        } else {
          item.already = fix_into(g, options, item.fix);
        }
      } catch (const InputError& e) {  // this glyph's own (one line); the others go on
        item.error = e.what();
      }
    }
    if (progress) {
      const std::lock_guard<std::mutex> lock(reporting);
      progress(++done, out.glyphs.size(), g.name);
    }
  });
  return out;
}

SourceGlyphsOutput source_glyphs_output(const SourceGlyphsFix& f, const std::string& ufo, const std::string& require,
                                        double grid) {
  using Json = nlohmann::ordered_json;
  SourceGlyphsOutput out;
  Json items = Json::array();
  Json below = Json::array();
  int already = 0;
  for (const SourceGlyphsFix::Item& it : f.glyphs) {
    if (it.already) {
      ++already;
      continue;
    }
    if (it.below_severity) {
      below.push_back(it.fix.glyph.name);
      continue;
    }
    Json item = {{"glyph", it.fix.glyph.name}};
    if (!it.error.empty() || !it.fix.failed.empty()) {
      item["fixed"] = false;
      item["reason"] = !it.error.empty() ? it.error : it.fix.failed;
      out.unfixed.push_back(it.fix.glyph.name);
    } else {
      ++out.fixed;
      item["fixed"] = true;
      if (!it.fix.edits.empty()) {
        const std::string& glif = it.fix.glyph.source;
        out.changed.emplace_back(glif, import::rewrite_glif_points(read_input_file(glif), it.fix.edits, glif));
      }
    }
    if (!it.fix.contours.is_null()) item["contours"] = it.fix.contours;
    items.push_back(item);
  }
  Json missing = Json::array();
  for (const std::uint32_t c : f.missing) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "U+%04X", static_cast<unsigned>(c));
    missing.push_back(buf);
  }
  out.doc = {{"file", ufo},
             {"require", require},
             {"grid", grid},
             {"glyphs", items},
             {"summary",
              {{"judged", f.glyphs.size()},
               {"already", already},
               {"below_severity", below},
               {"fixed", out.fixed},
               {"unfixed", out.unfixed.size()},
               {"without_contours", f.without_contours},
               {"missing", missing}}}};
  return out;
}

}  // namespace cmr::report
