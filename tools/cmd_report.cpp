// cmr report FILES... --out DIR [--require cmrwi|cmr|split:S[:sharpest|:flattest],GATES...] [--segments A..B]
// [--depth D] [--no-thumbnails] [--backend auto|vulkan|cpu] [--device NAME] [--region-size N]
// [--angle-tol DEG] [--curvature-tol REL] [--glyphs A-Z,a-z]: QA reports (DIR/report.json,
// DIR/index.html) and a gate on their verdicts. A font file among FILES is imported
// (io/font.hpp): each glyph contour is one closed spline, fixes are suggested
// on the font's unit grid, and DIR/font.html holds the per-glyph overview. An
// SVG file (.svg) is read as cmr import reads it (io/svg.hpp, y-up): each
// subpath is one spline.
#include <unistd.h>

#include <iostream>

#include <CLI/CLI.hpp>

#include "spline/errors.hpp"
#include "spline/limits.hpp"
#include "tools/cli_common.hpp"
#include "tools/cmd_space.hpp"
#include "report/font_report.hpp"
#include "io/font.hpp"
#include "io/svg.hpp"
#include "report/report.hpp"
#include "report/batch.hpp"

namespace cmr::cli {

namespace {

struct ReportArgs {
  std::vector<std::string> files;
  ContinuityTolerances continuity;  // G1/G2 at joints, as cmr analyze
  std::string out;
  std::string require;
  std::string segments;
  int depth = kDefaultDepth;
  bool no_thumbnails = false;
  std::string backend = "auto";
  std::string device;
  int region_size = 96;
  bool pretty = false;
  std::string glyphs = "A-Z,a-z";
  double constant_tolerance = report::kDefaultConstantTolerance;
};

// "[#####-----] 12/40 name" rewritten in place; only on a terminal.
void show_progress(int done, int total, const std::string& name) {
  constexpr int kWidth = 30;
  const int filled = total > 0 ? done * kWidth / total : kWidth;
  std::cerr << "\r[" << std::string(filled, '#') << std::string(kWidth - filled, '-') << "] " << done << '/' << total
            << ' ' << name.substr(0, 40) << "\033[K" << std::flush;
}

/// Writes dir/index.html (and font.html for fonts) and dir/report.json as one cmr::OutputSet (both or
/// neither; dir is created, and removed again on failure if it was new).
/// report.json is renamed last: it is the report's commit marker, so a
/// report.json is always accompanied by the index.html of the same run, and
/// two runs into one folder (serialised by the set's folder lock) never mix.
void write_report(const std::filesystem::path& dir, const std::vector<report::SplineReport>& reports,
                  const report::ReportOptions& options, const std::vector<report::FontInfo>& fonts, bool pretty) {
  OutputSet out;
  out.create_folder(dir);
  out.own_folder(dir);  // a reused folder keeps only this run's files (font.html of an earlier font run goes)
  out.stage(dir / "index.html", report::report_html(reports, options));
  if (!fonts.empty()) out.stage(dir / "font.html", report::font_report_html(fonts, reports, options));
  out.stage(dir / "report.json", json_text(report::report_json(reports, options), pretty));
  out.commit();
}

static_assert(report::kExitPass == kOk && report::kExitFail == kFail && report::kExitInvalid == kInvalid);

}  // namespace

void add_report_command(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<ReportArgs>();
  auto* cmd = app.add_subcommand("report", "QA report of spline files: JSON and a self-contained HTML page");
  cmd->add_option("FILES", args->files, "spline files (JSON), fonts (.ttf, .otf, ...) or SVG files (.svg)")->required();
  cmd->add_option("--out", args->out, "output folder for report.json and index.html")->required();
  cmd->add_option("--require", args->require,
                  "gates, comma separated: exit 1 when a spline fails cmrwi, cmr, split:S (a curvature extremum at "
                  "joint S: the parts before and after monotone in opposite directions), split:S:sharpest, split:S:flattest (by |curvature|), "
                  "extrema-at-nodes, max-extrema-per-segment:N, g2-at-smooth-nodes[:tol] or no-inflection");
  cmd->add_option("--segments", args->segments, "judge only spans A..B (inclusive); the others are reported as ignored");
  cmd->add_option("--glyphs", args->glyphs, "characters of the fonts among FILES (A-Z,a-z,U+00E9)")->capture_default_str();
  in_range(cmd->add_option("--depth", args->depth, "maximum subdivision depth D (level 0 = whole span)"), 0,
           kMaxDepth)
      ->capture_default_str();
  cmd->add_flag("--no-thumbnails", args->no_thumbnails, "skip the regions (fix search and thumbnails)");
  add_backend_options(*cmd, args->backend, args->device);
  in_range(cmd->add_option("--region-size", args->region_size, "fix-search image size in pixels per side"), 8, 1024)
      ->capture_default_str();
  add_continuity_options(*cmd, args->continuity);
  in_range(cmd->add_option("--constant-tol", args->constant_tolerance,
                           "relative curvature spread below which a segment is an arc of constant curvature: the "
                           "extremum gates skip its stationary points (rounded circle arcs); 0: exact constants only"),
           0.0, 1.0)
      ->capture_default_str();
  add_pretty_flag(*cmd, args->pretty);
  cmd->callback([args, &exit_code] {
    // Space curves ([x, y, z] points) get their own report (tools/cmd_space.hpp, docs/space.md).
    std::string space, planar;
    for (const std::string& f : args->files)
      if (import::is_font_path(f) || std::filesystem::is_regular_file(f))  // unreadable: that report names it
        (!import::is_font_path(f) && spline_file_dimension(f) == 3 ? space : planar) = f;
    if (!space.empty() && !planar.empty())
      throw InputError(space + " is a space curve and " + planar + " is planar: report them separately");
    if (!space.empty()) {
      if (!args->segments.empty() || (!args->require.empty() && args->require != "cmrwi"))
        throw InputError(space + ": a space curve; its report takes --require cmrwi only, and no --segments");
      exit_code = run_space_report(args->files, args->out, args->depth, true, args->continuity,
                                   args->require == "cmrwi", args->pretty);
      return;
    }
    validate(args->continuity);  // before the batch: a bad tolerance is a usage error, not a bad file
    report::ReportOptions o;
    o.continuity = args->continuity;
    o.constant_tolerance = args->constant_tolerance;
    if (!args->require.empty()) report::parse_require_list(args->require, o);
    if (!args->segments.empty()) o.segments = parse_segment_range(args->segments);
    o.max_depth = args->depth;
    o.regions = !args->no_thumbnails;
    o.region_size = args->region_size;
    o.backend = make_region_backend(args->backend, "fp64", args->device);

    std::vector<report::ReportInput> inputs;
    std::vector<report::FontInfo> fonts;
    const auto codepoints = import::parse_glyph_spec(args->glyphs);
    for (const std::string& f : args->files) {
      if (import::is_svg_path(f)) {  // each subpath one item, as cmr import would write it
        for (const import::PathSpline& s : import::read_svg(f)) {
          report::ReportInput in{f + ":" + s.name, {}, {}};
          try {
            in.spline = import::to_bspline(s);
          } catch (const InputError& e) {
            in.error = in.file + ": " + e.what();
          }
          inputs.push_back(std::move(in));
        }
        continue;
      }
      if (!import::is_font_path(f)) {
        inputs.push_back(report::read_input(f));
        continue;
      }
      fonts.push_back(report::font_inputs(import::read_font(f, codepoints), inputs));
      o.grid = 1;  // the font's unit
    }
    const bool terminal = ::isatty(STDERR_FILENO) == 1;
    const auto reports = report::report_batch(std::move(inputs), o, terminal ? show_progress : report::Progress{});
    if (terminal) std::cerr << "\r\033[K" << std::flush;
    write_report(args->out, reports, o, fonts, args->pretty);

    int pass = 0, fail = 0, invalid = 0;
    for (const report::SplineReport& r : reports) {
      if (!r.error.empty()) {
        ++invalid;
        std::cerr << "cmr: " << r.error << '\n';  // read_spline_file names the file
      } else {
        ++(r.pass ? pass : fail);
      }
    }
    std::cout << reports.size() << (reports.size() == 1 ? " spline: " : " splines: ") << pass << " pass, " << fail
              << " fail, " << invalid << " invalid; wrote "
              << (std::filesystem::path(args->out) / "index.html").string() << " and "
              << (std::filesystem::path(args->out) / "report.json").string()
              << (fonts.empty() ? "" : " and " + (std::filesystem::path(args->out) / "font.html").string()) << '\n';
    exit_code = report::exit_code(reports, o);
  });
}

}  // namespace cmr::cli
