// cmr fix FILE --require cmr|cmrwi|split:S[:sharpest|flattest]|each-piece|curvature-extrema-at-nodes|no-inflection|g2-at-smooth-nodes[:tol]|each-run [--segments A..B]
// [--points K,...] [--keep g1|g2|none] [--max-move D] [--out FIXED.json]:
// the nearest certified repair (design/fix.hpp, docs/fix.md); and
// cmr fix MODEL.step --chain N [--require cmr|cmrwi|each-piece] [--keep none|g1|g2|g3] [--out DIR]:
// a chain of STEP edges fixed with its junctions kept (step/chain_fix.hpp).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <utility>
#include <vector>

#include <unistd.h>

#include <CLI/CLI.hpp>

#include "design/fix.hpp"
#include "bezierize/segments.hpp"
#include "region/region.hpp"
#include "draw/draw.hpp"
#include "io/output.hpp"
#include "io/ufo.hpp"
#include "report/gates.hpp"
#include "bezierize/extract.hpp"
#include "report/contour_moves.hpp"
#include "report/glyph_fix.hpp"
#include "report/severity.hpp"
#include "report/source_fix.hpp"
#include "report/interpolation.hpp"
#include "report/fix_json.hpp"
#include "spline/errors.hpp"
#include "spline/spline_json.hpp"
#include "tools/cli_common.hpp"
#include "tools/cmd_space.hpp"

namespace cmr::cli {

namespace {

using Json = nlohmann::ordered_json;

/// Before and after: the first moved point's region (its unit's group
/// moving with it, the requirement's labels) on the original curve with the
/// move drawn, the fixed curve, and both curvature plots.
std::string before_after_png(const BSpline& before, const FixResult& f, const FixRequest& request) {
  const bool split = request.requirement.kind == FixRequirement::Kind::split;
  RegionRequest rr;
  rr.point = f.moves.empty() ? 0 : f.moves.front().point;
  rr.mode = request.requirement.kind == FixRequirement::Kind::cmr ? Mode::cmr : Mode::cmrwi;
  if (split) rr.split = request.requirement.split;
  rr.max_depth = request.max_depth;
  rr.width = rr.height = 400;
  rr.depth = false;
  for (const PointMove& m : f.moves)
    if (m.point != rr.point && m.to - m.from == f.moves.front().to - f.moves.front().from) rr.with.push_back(m.point);
  const RegionResult image_before = CpuRegionBackend().render(RegionProblem::make(before, rr));
  rr.view = image_before.view;
  const RegionResult image_after = CpuRegionBackend().render(RegionProblem::make(*f.spline, rr));
  draw::RegionPicture pb, pa;
  pb.spline = &before, pb.layers = {&image_before}, pb.split = split, pb.points = {rr.point};
  pa.spline = &*f.spline, pa.layers = {&image_after}, pa.split = split, pa.points = {rr.point};
  if (!f.moves.empty()) pb.moved = std::make_pair(f.moves.front().from, f.moves.front().to);
  const SplineAnalysis ab = analyze(before, fix_analyze_options(request.requirement, request.max_depth));
  draw::Figure fig;
  fig.title = "cmr fix --require " + to_string(request.requirement);
  fig.rows = {{draw::Panel{pb, "before: P" + std::to_string(rr.point) + "'s region and the move"},
               draw::Panel{pa, "after (certified)"}},
              {draw::Panel{draw::CurvaturePlot{&before, &ab}, "curvature before"},
               draw::Panel{draw::CurvaturePlot{&*f.spline, &f.certificate}, "curvature after"}}};
  fig.legend = draw::legend_for(pb);
  std::string moved;
  for (const PointMove& m : f.moves) moved += (moved.empty() ? "" : ", ") + std::string("P") + std::to_string(m.point);
  fig.caption = f.moves.empty() ? "nothing to move: the curve meets the requirement"
                                : "moved " + moved + "; largest move " + std::to_string(f.max_distance / f.size * 100) +
                                      "% of the curve size";
  return draw::figure_png(fig);
}

/// `cmr fix FONT.ufo|GLYPH.glif --glyph NAME --require GATES [--grid G]
/// [--out NEW.ufo | --in-place]` (report/glyph_fix.hpp, docs/fix.md "Font
/// sources"): one fix for every required check, on the grid, written back
/// as new x/y attributes of the moved <point>s and nothing else.
struct SourceFixArgs {
  std::string file, glyph, require, out, points;
  double grid = 1, max_move = 0;
  bool in_place = false, pretty = false;
  int depth = kDefaultDepth;
  long work = report::kGlyphWork;
  bool add_nodes = false;  ///< --add-nodes (report/glyph_nodes.hpp)
};

/// A .glif's path and its new text.
using ChangedGlif = std::pair<std::string, std::string>;

/// Stages a copy of the source folder `src` (a UFO) as the new folder `out`,
/// with each .glif of `changed` replaced by its new text.
void stage_source_copy(const std::string& src_text, const std::string& out, const std::vector<ChangedGlif>& changed,
                       OutputSet& outputs) {
  namespace fs = std::filesystem;
  const fs::path src = src_text, dst = out;
  std::error_code ec;
  if (fs::exists(dst, ec)) throw InputError(out + ": exists (a copy of the source goes to a new folder)");
  outputs.create_folder(dst);
  for (auto it = fs::recursive_directory_iterator(src); it != fs::recursive_directory_iterator(); ++it) {
    const fs::path rel = it->path().lexically_relative(src);
    if (it->is_directory()) {
      outputs.create_folder(dst / rel);
    } else if (it->is_regular_file()) {
      const auto glif = std::find_if(changed.begin(), changed.end(),
                                     [&](const ChangedGlif& c) { return fs::equivalent(it->path(), c.first, ec); });
      outputs.stage(dst / rel, glif != changed.end() ? glif->second : read_input_file(it->path()));
    }
  }
}

/// `cmr fix FONT.ufo --glyphs SPEC --require GATES [--grid G] [--out
/// NEW.ufo | --in-place] [--min-severity U | --strict]`: every selected
/// glyph that the report fails (at its severity threshold) fixed on its own
/// (report/source_fix.hpp fix_source_glyphs), the fixed ones written back
/// together (all files or none). Exit 1 when some glyph has no fix (each
/// says why); the others are still written.
int run_source_glyphs_fix(const SourceFixArgs& a, const std::string& glyphs, double min_severity) {
  if (a.in_place && !a.out.empty()) throw InputError("--in-place and --out: choose one");
  report::GlyphFixOptions o = report::source_fix_options(a.require, a.depth, a.grid, a.max_move, a.work);
  o.add_nodes = a.add_nodes;
  std::error_code ec;
  if (!a.out.empty() && std::filesystem::exists(a.out, ec))  // before the searches, not after
    throw InputError(a.out + ": exists (a copy of the source goes to a new folder)");
  const import::GlyphSelection which = import::parse_glyph_selection(glyphs);
  // On a terminal, a line that counts the glyphs searched (a Latin font
  // takes minutes); none in CI logs or pipes.
  const bool bar = ::isatty(STDERR_FILENO) == 1 && std::getenv("CI") == nullptr;
  const auto progress = [](std::size_t done, std::size_t total, const std::string& glyph) {
    constexpr std::size_t kWidth = 24;
    const std::size_t filled = done * kWidth / total;
    std::cerr << "\rfix [" << std::string(filled, '#') << std::string(kWidth - filled, '-') << "] " << done << '/'
              << total << " glyphs " << glyph << "\033[K" << std::flush;
  };
  const report::SourceGlyphsFix f =
      report::fix_source_glyphs(a.file, which, o, min_severity, 0,
                                bar ? report::GlyphsProgress(progress) : report::GlyphsProgress{});
  if (bar) std::cerr << "\r\033[K" << std::flush;
  report::SourceGlyphsOutput r = report::source_glyphs_output(f, a.file, a.require, a.grid);
  Json& doc = r.doc;
  show_fields_in(doc, show_fields);  // the reasons' fields as flags
  // All outputs or none (io/output.hpp): the copy of the whole source, or
  // the changed .glif files in place.
  OutputSet outputs;
  if (a.in_place) {
    Json written = Json::array();
    for (const auto& [glif, text] : r.changed) {
      outputs.stage(glif, text);
      written.push_back(glif);
    }
    doc["written"] = written;
  } else if (!a.out.empty()) {
    stage_source_copy(a.file, a.out, r.changed, outputs);
    doc["out"] = a.out;
  }
  outputs.commit();
  print_json(doc, a.pretty);
  if (r.unfixed.empty()) return kOk;
  std::string names;
  for (std::size_t i = 0; i < r.unfixed.size() && i < 10; ++i) names += (i ? ", " : "") + r.unfixed[i];
  if (r.unfixed.size() > 10) names += ", ...";
  std::cerr << "cmr: " << a.file << ": " << r.unfixed.size() << " of " << (r.unfixed.size() + r.fixed)
            << " failing glyphs have no certified fix (" << names << "; each entry says why)"
            << (r.fixed > 0 && (a.in_place || !a.out.empty()) ? "; the fixed ones are written" : "") << "\n";
  return kFail;
}

/// `cmr fix FAMILY.designspace --glyph NAME --require g1-between-masters
/// [--out NEW.ufo | --in-place]` (report/interpolation.hpp
/// fix_g1_between_masters): the kinks between the two masters fixed by
/// moving handles in one master on the grid; --out: a copy of that master's
/// UFO, --in-place: its .glif rewritten (only the moved points' x and y).
void run_masters_fix(const std::string& file, const std::string& glyph, const std::string& require,
                     const std::string& out, bool in_place, bool pretty) {
  if (glyph.empty()) throw InputError(file + ": a designspace; name the glyph with --glyph NAME");
  const std::optional<report::Gate> gate = report::parse_gate(require);
  if (!gate || gate->kind != report::Gate::Kind::g1_between_masters)
    throw InputError(file + ": a designspace is fixed for --require g1-between-masters[:DEG] (other gates: cmr fix MASTER.ufo)");
  if (in_place && !out.empty()) throw InputError("--in-place and --out: choose one");
  const report::MastersG1Fix f = report::fix_g1_between_masters(file, glyph, gate->turn_degrees);
  if (f.kinks_after != 0)
    throw InputError(file + ": " + glyph + ": the moves leave " + std::to_string(f.kinks_after) + " kinks (not certified)");
  Json moves = Json::array();
  for (const report::MastersG1Fix::Move& m : f.moves)
    moves.push_back({{"point", m.point},
                     {"from", Json::array({m.from.x, m.from.y})},
                     {"to", Json::array({m.to.x, m.to.y})},
                     {"distance", m.distance}});
  Json doc = {{"file", file},     {"glyph", glyph},       {"require", require},
              {"master", f.master}, {"ufo", f.ufo},       {"moves", moves},
              {"distance", f.distance},     {"least", f.least},
              {"rejudged", Json::array({{{"check", report::to_string(*gate)}, {"before", f.kinks_before}, {"after", f.kinks_after}}})}};
  OutputSet outputs;
  const std::string text = read_input_file(f.glif);
  const std::string changed = f.edits.empty() ? text : import::rewrite_glif_points(text, f.edits, f.glif);
  if (in_place) {
    if (!f.edits.empty()) outputs.stage(f.glif, changed);
    doc["written"] = f.glif;
  } else if (!out.empty()) {
    stage_source_copy(f.ufo, out, {{f.glif, changed}}, outputs);
    doc["out"] = out;
  }
  outputs.commit();
  print_json(doc, pretty);
}

void run_source_fix(const SourceFixArgs& a) {
  if (a.in_place && !a.out.empty()) throw InputError("--in-place and --out: choose one");
  report::GlyphFixOptions o = report::source_fix_options(a.require, a.depth, a.grid, a.max_move, a.work);
  o.add_nodes = a.add_nodes;
  report::SourceFix f =
      report::fix_source_glyph(a.file, a.glyph, a.points.empty() ? std::vector<std::string>{} : comma_items(a.points), o);
  const import::Glyph& g = f.glyph;
  const std::vector<import::PointEdit>& edits = f.edits;
  const bool glif = std::filesystem::path(a.file).extension() == ".glif";
  show_fields_in(f.contours, show_fields);  // the reasons' fields as flags
  if (!f.failed.empty()) throw InputError(a.file + ": " + show_fields(f.failed));
  Json doc = {{"file", a.file}, {"glyph", g.name}, {"require", a.require}, {"grid", a.grid}, {"contours", f.contours}};
  if (!f.points.empty()) doc["points"] = f.points;
  // All outputs or none (io/output.hpp): the copy of the whole source, or
  // the changed .glif in place.
  OutputSet outputs;
  const std::string glif_text = read_input_file(g.source);
  const std::string changed = edits.empty() ? glif_text : import::rewrite_glif_points(glif_text, edits, g.source);
  if (a.in_place) {
    if (!edits.empty()) outputs.stage(g.source, changed);
    doc["written"] = g.source;
  } else if (!a.out.empty()) {
    if (glif) {
      outputs.stage(a.out, changed);
    } else {
      stage_source_copy(a.file, a.out, {{g.source, changed}}, outputs);
    }
    doc["out"] = a.out;
  }
  outputs.commit();
  print_json(doc, a.pretty);
}


/// `cmr fix FILE.json --require A,B[,...]` (a plain spline file, e.g. one
/// `cmr import` made from a font): the glyph fix's engine (report/glyph_fix)
/// on the file's one closed contour (report::contour_of: nodes from the
/// knots, a straight piece's inner points never move). On the grid (--grid, default
/// 1 when every coordinate is an integer, as in a font's import; else 0:
/// off-grid, the rounds without the grid descent).
void run_spline_multi_fix(const std::string& file, const std::string& require, const std::string& points,
                          const std::string& out, double grid, bool grid_given, double max_move, int depth, bool pretty) {
  const nlohmann::json document = read_spline_document(file);
  const BSpline spline = spline_from_document(document, file);
  if (!spline.closed()) throw InputError(file + ": several checks at once (--require A,B) need a closed spline");
  if (spline.is_rational()) throw InputError(file + ": several checks at once (--require A,B) need a polynomial spline");
  if (!(grid >= 0) || !std::isfinite(grid)) throw InputError("--grid: " + std::to_string(grid) + " is not a step >= 0");
  std::vector<std::string> names;
  if (document.is_object() && document.contains("point_names") && document["point_names"].is_array())
    for (const auto& n : document["point_names"]) names.push_back(n.is_string() ? n.get<std::string>() : std::string());
  import::Glyph g;
  g.name = std::filesystem::path(file).stem().string();
  import::Contour c = report::contour_of(spline, names);
  bool integral = true;
  for (const Vec2 p : spline.points()) integral = integral && p.x == std::floor(p.x) && p.y == std::floor(p.y);
  g.contours.push_back(std::move(c));
  report::GlyphFixOptions o;
  report::parse_require_list(require, o.judge);
  report::check_fixable(o.judge);
  o.judge.max_depth = depth;
  o.grid = grid_given ? grid : (integral ? 1.0 : 0.0);
  o.max_move = max_move;
  // --points: indices or the file's names (parse_point_list), as the
  // contour's names; each one the glyph fix may move.
  const import::Contour& contour = g.contours.front();
  std::vector<std::string> named;
  for (int k : points.empty() ? std::vector<int>{} : parse_point_list(points, names)) {
    if (k < 0 || k >= static_cast<int>(contour.point_names.size()))
      throw InputError("--points: " + std::to_string(k) + " is outside 0.." + std::to_string(contour.point_names.size() - 1));
    named.push_back(contour.point_names[k]);
  }
  o.points = report::named_points(g, named);
  const std::vector<report::ContourFix> fixes = report::fix_glyph(g, o);
  std::vector<import::PointEdit> edits;
  std::string failed;
  Json contours = report::glyph_fix_json(g, fixes, o.grid, edits, failed);
  show_fields_in(contours, show_fields);  // the reasons' fields as flags
  if (!failed.empty()) throw InputError(file + ": " + show_fields(failed));
  Json doc = {{"file", file}, {"require", require}, {"grid", o.grid}, {"contours", contours}};
  if (!o.points.empty()) doc["points"] = o.points;
  OutputSet outputs;
  if (!out.empty()) {
    BSpline fixed = spline;
    for (const report::ContourFix& f : fixes)
      for (const PointMove& mv : f.moves) fixed = fixed.with_point(mv.point, mv.to);
    nlohmann::json j = spline_to_json(fixed);
    if (!names.empty()) j["point_names"] = names;
    outputs.stage(out, j.dump(2) + "\n");
    doc["out"] = out;
  }
  outputs.commit();
  print_json(doc, pretty);
}

}  // namespace

void add_fix_command(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand(
      "fix", "Move the fewest control points the least distance so that the curve meets a requirement (certified)");
  struct Args {
    std::string file, require = "cmr", points, keep = "g1", out, png, segments, plane, glyph, glyphs;
    double max_move = 0, tolerance = 1e-6, grid = 1, min_severity = report::kDefaultMinSeverity;
    bool in_place = false, strict = false, add_nodes = false;
    int depth = kDefaultDepth;
    int chain = 0;
    long work = report::kGlyphWork;
    bool pretty = false;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("FILE", args->file, "spline file (JSON)")->required();
  cmd->add_option("--require", args->require,
                  "cmr (default), cmrwi, split:S, split:S:sharpest|flattest, each-piece, curvature-extrema-at-nodes "
                  "(alias: extrema-at-nodes), no-inflection, g2-at-smooth-nodes[:tol], each-run");
  cmd->add_option("--points", args->points,
                  "points that may move (K,K2,... or the file's point names: O/c0/p3 or p3; a font source: the report's names, O/c0/p3, "
                  "c0/p3 or p3, or a <point>'s name); several move together. Default: every point but an open "
                  "spline's ends, the best single one reported");
  cmd->add_option("--keep", args->keep,
                  "ties kept at joints: g1 (default), g2, none; a STEP chain: the continuity its junctions keep, none, g1, "
                  "g2 (its default) or g3")
      ->check(CLI::IsMember({"g1", "g2", "g3", "none"}));
  cmd->add_option("--segments", args->segments,
                  "judge only spans A..B (inclusive): only they must meet the requirement (as cmr analyze --segments)");
  CLI::Option* max_move = cmd->add_option(
      "--max-move", args->max_move, "largest displacement of any point, a distance > 0 (default: the curve size)");
  cmd->add_option("--tolerance", args->tolerance, "distance tolerance relative to the curve size (default 1e-6)");
  in_range(cmd->add_option("--depth", args->depth, "maximum subdivision depth"), 0, kMaxDepth);
  cmd->add_option("--out", args->out, "write the fixed spline here (JSON, atomically)");
  cmd->add_option("--png", args->png, "a before/after picture: the moved point's region, both curves and curvature plots");
  cmd->add_option("--plane", args->plane,
                  "space curves: the plane each point moves in, through it (xy, yz, zx or OX,OY,OZ,UX,UY,UZ,VX,VY,VZ: "
                  "its U, V); default: the plane of its neighbours' directions");
  add_pretty_flag(*cmd, args->pretty);
  cmd->add_option("--glyph", args->glyph,
                  "font sources (NAME.ufo, .glif; a two-master .designspace with --require g1-between-masters): the "
                  "glyph to fix");
  cmd->add_option("--glyphs", args->glyphs,
                  "UFO sources: fix every selected glyph that fails, each on its own (as the report selects them: "
                  "A-Z,a-z, U+hex, or all); exit 1 when some glyph has no fix");
  CLI::Option* min_severity = cmd->add_option(
      "--min-severity", args->min_severity,
      "with --glyphs: leave a glyph whose every finding has a certified move below this many font units (the "
      "report's info findings; default 0.5)");
  cmd->add_flag("--strict", args->strict, "with --glyphs: every finding counts, info ones too (as cmr report --strict)");
  cmd->add_option("--grid", args->grid, "font sources: the grid the moved points land on (default 1 font unit; 0: off-grid)");
  cmd->add_flag("--in-place", args->in_place, "font sources: rewrite the glyph's .glif (only the moved points' x and y)");
  cmd->add_flag("--add-nodes", args->add_nodes,
                "font sources: where moves find no fix, split the failing cubics (at their curvature extrema, and "
                "at a smooth join with a line) with new smooth nodes on the grid and fix again; the .glif gets "
                "the new points");
  cmd->add_option("--work", args->work,
                  "UFO sources: each glyph's search budget in work units (default 2000000: 3-9 s for a glyph that uses "
                  "it all on a 2-core VM; the same fix on any machine); a glyph that runs out of it says so, and a "
                  "larger budget searches further");
  cmd->add_option("--chain", args->chain,
                  "STEP models (.step, .stp): the chain of edges to fix, by the number cmr import gives it; --out is then "
                  "a folder for the chain's edges");
  cmd->callback([args, cmd, max_move, min_severity, &exit_code] {
    // 0 would mean "no point may move": no fix at all. Refused rather than
    // read as the default (it was: issue 42), so that it never means "unlimited".
    if (max_move->count() > 0 && !(args->max_move > 0 && std::isfinite(args->max_move)))
      throw InputError("--max-move: " + max_move->as<std::string>() + " is not a distance > 0 (leave it out for the default, the curve size)");
    std::string ext = std::filesystem::path(args->file).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".step" || ext == ".stp") {  // a chain of edges (step/chain_fix.hpp, docs/fix.md)
      if (cmd->count("--chain") == 0)
        throw InputError(args->file + ": a STEP model; name the chain to fix with --chain N (cmr import lists them)");
      if (!args->plane.empty() || !args->segments.empty() || !args->png.empty() || !args->points.empty() ||
          !args->glyph.empty() || cmd->count("--grid") > 0 || args->in_place)
        throw InputError(args->file + ": a STEP chain; --plane, --segments, --png, --points, --glyph, --grid and --in-place are not for it");
      run_chain_fix({args->file, args->require, cmd->count("--keep") > 0 ? args->keep : "g2", args->out, args->chain,
                     args->max_move, args->tolerance, args->depth, args->pretty});
      exit_code = kOk;
      return;
    }
    if (cmd->count("--chain") > 0) throw InputError("--chain: only for STEP models (.step, .stp), not for " + args->file);
    if (cmd->count("--work") > 0 && !import::is_ufo_path(args->file))
      throw InputError("--work: for UFO sources (NAME.ufo, .glif), not for " + args->file);
    if (args->keep == "g3") throw InputError("--keep g3: only for a STEP chain (cmr fix MODEL.step --chain N); a spline keeps g2 at most");
    if (import::is_designspace_path(args->file)) {
      if (!args->plane.empty() || !args->segments.empty() || !args->png.empty() || cmd->count("--keep") > 0 ||
          !args->points.empty() || cmd->count("--grid") > 0 || args->add_nodes)
        throw InputError(args->file + ": a designspace; --plane, --segments, --png, --keep, --points, --grid and "
                                      "--add-nodes are not for it");
      run_masters_fix(args->file, args->glyph, args->require, args->out, args->in_place, args->pretty);
      exit_code = kOk;
      return;
    }
    if (import::is_ufo_path(args->file)) {
      if (!args->plane.empty() || !args->segments.empty() || !args->png.empty() || cmd->count("--keep") > 0)
        throw InputError(args->file + ": a font source; --plane, --segments, --png and --keep are for spline files");
      const SourceFixArgs a{args->file, args->glyph,
                            cmd->count("--require") > 0 ? args->require : "curvature-extrema-at-nodes",
                            args->out, args->points, args->grid, args->max_move, args->in_place, args->pretty, args->depth,
                            args->work, args->add_nodes};
      if (cmd->count("--glyphs") > 0) {
        if (!args->glyph.empty()) throw InputError("--glyph and --glyphs: choose one");
        if (!args->points.empty()) throw InputError("--points: for one glyph (--glyph NAME), not with --glyphs");
        if (!(args->min_severity >= 0) || !std::isfinite(args->min_severity))
          throw InputError("--min-severity: " + min_severity->as<std::string>() + " is not a distance >= 0");
        if (args->strict && min_severity->count() > 0) throw InputError("--strict: not with --min-severity");
        exit_code = run_source_glyphs_fix(a, args->glyphs, args->strict ? -1 : args->min_severity);
        return;
      }
      if (min_severity->count() > 0 || args->strict)
        throw InputError(std::string(args->strict ? "--strict" : "--min-severity") +
                         ": with --glyphs (a glyph named with --glyph is fixed for every finding)");
      run_source_fix(a);
      exit_code = kOk;
      return;
    }
    if (cmd->count("--glyphs") > 0 || min_severity->count() > 0 || args->strict || args->add_nodes)
      throw InputError(std::string(cmd->count("--glyphs") > 0 ? "--glyphs"
                                   : args->strict               ? "--strict"
                                   : args->add_nodes            ? "--add-nodes"
                                                                : "--min-severity") +
                       ": for UFO sources (NAME.ufo), not for " + args->file);
    const bool several = args->require.find(',') != std::string::npos;
    if (!args->glyph.empty() || args->in_place || (cmd->count("--grid") > 0 && !several))
      throw InputError(args->file + ": --glyph, --grid and --in-place are for font sources (.ufo, .glif)" +
                       std::string(several ? "" : " and several checks (--require A,B)"));
    if (spline_file_dimension(args->file) == 3) {  // [x, y, z] points: a space curve (docs/fix.md, "Space curves")
      if (!args->segments.empty())
        throw InputError(args->file + ": a space curve; --segments is for planar splines");
      run_space_fix({args->file, args->require, args->points, args->keep, args->plane, args->out, args->png,
                     args->max_move, args->tolerance, args->depth, args->pretty});
      exit_code = kOk;
      return;
    }
    if (!args->plane.empty()) throw InputError(args->file + ": a planar spline; --plane is for space curves");
    if (several) {  // every check at once: the glyph fix's engine (report/glyph_fix.hpp)
      if (!args->segments.empty() || !args->png.empty() || cmd->count("--keep") > 0)
        throw InputError(args->file + ": several checks (--require A,B): --segments, --png and --keep are for one");
      if (!args->out.empty()) check_output_path(args->out, "--out");
      run_spline_multi_fix(args->file, args->require, args->points, args->out, args->grid, cmd->count("--grid") > 0, args->max_move,
                           args->depth, args->pretty);
      exit_code = kOk;
      return;
    }
    if (!args->out.empty()) check_output_path(args->out, "--out");
    if (!args->png.empty()) check_output_path(args->png, "--png");
    if (!(args->max_move >= 0) || !std::isfinite(args->max_move))
      throw InputError("--max-move: " + std::to_string(args->max_move) + " is not a distance >= 0");
    FixRequest request;
    request.requirement = parse_fix_requirement(args->require);
    if (!args->segments.empty()) request.requirement.segments = parse_segment_range(args->segments);
    // A spline file from `cmr import` names its points ("point_names"):
    // --points takes those names, and --out keeps them.
    const nlohmann::json document = read_spline_document(args->file);
    const BSpline spline = spline_from_document(document, args->file);
    std::vector<std::string> names;
    if (document.is_object() && document.contains("point_names") && document["point_names"].is_array())
      for (const auto& n : document["point_names"]) names.push_back(n.is_string() ? n.get<std::string>() : std::string());
    if (!args->points.empty()) request.points = parse_point_list(args->points, names);
    request.together = request.points.size() > 1;
    request.keep = args->keep == "g2" ? Keep::g2 : args->keep == "none" ? Keep::none : Keep::g1;
    request.max_move = args->max_move;
    request.tolerance = args->tolerance;
    request.max_depth = args->depth;
    const FixResult f = fix(spline, request);
    if (!f.fixed) throw InputError(args->file + ": " + show_fields(f.reason));
    Json doc = report::fix_json(args->file, request, f);
    // All outputs or none (io/output.hpp).
    OutputSet outputs;
    if (!args->out.empty()) {
      nlohmann::json fixed = spline_to_json(*f.spline);
      if (!names.empty()) fixed["point_names"] = names;
      outputs.stage(args->out, fixed.dump(2) + "\n");
      doc["out"] = args->out;
    }
    if (!args->png.empty()) {
      outputs.stage(args->png, before_after_png(spline, f, request));
      doc["png"] = args->png;
    }
    outputs.commit();
    // With --out - (or --png -) stdout is the file alone (a pipe: cmr fix F --out - | cmr analyze -): the JSON goes to stderr.
    if (is_stdout_path(args->out) || is_stdout_path(args->png)) std::cerr << json_text(doc, args->pretty);
    else print_json(doc, args->pretty);
    exit_code = kOk;
  });
}

}  // namespace cmr::cli
