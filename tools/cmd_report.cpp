// cmr report FILES... --out DIR [--require cmrwi|cmr|split:S[:sharpest|:flattest],GATES...] [--segments A..B]
// [--depth D] [--no-thumbnails] [--backend auto|vulkan|cpu] [--device NAME] [--region-size N]
// [--angle-tol DEG] [--curvature-tol REL] [--glyphs A-Z,a-z] [--include GLOB] [--exclude GLOB]
// [--junit FILE] [--sarif FILE] [--markdown FILE] [--baseline OLD/report.json] [--source-root DIR]
// [--quiet] [--shard i/N] [--jobs N], and cmr report --merge DIRS... --out DIR (report/merge.hpp): QA reports and a gate on
// their verdicts. FILES are spline files, SVG files, fonts, folders or globs; the batch
// (finding files, running them in parallel, writing every output) is report/corpus.hpp:
// this file only parses.
// A font file is imported (io/font.hpp): each glyph contour is one closed spline;
// an SVG file (.svg) is read as cmr import reads it (io/svg.hpp, y-up): each
// subpath is one spline. A run of space curves (files, folders, globs or -) is judged by
// report/space_report.hpp and written in the same schema with the same CI files
// (tools/cmd_space.hpp: run_space_report); a flag only planar runs take is refused.
// A run with both planar and space inputs judges them as two parts in a
// private folder and merges them into --out (report/merge.hpp, MixedRun below).
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <optional>

#include <CLI/CLI.hpp>

#include "spline/errors.hpp"
#include "spline/limits.hpp"
#include "tools/cli_common.hpp"
#include "tools/cmd_space.hpp"
#include "io/ufo.hpp"
#include "io/masters.hpp"
#include "report/interpolation.hpp"
#include "report/corpus.hpp"
#include "report/font_report.hpp"
#include "io/font.hpp"
#include "io/output.hpp"
#include "io/svg.hpp"
#include "report/report.hpp"
#include "report/batch.hpp"
#include "report/merge.hpp"
#include "report/report_cache.hpp"
#include "report/severity.hpp"

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
  std::string location;
  std::string between;
  double min_severity = -1;
  bool strict = false;
  bool no_severity = false;
  report::FileFilter filter;  // folders: --include / --exclude
  std::string junit, sarif, markdown, baseline, source_root;
  bool quiet = false;
  bool no_fixes = false;
  bool no_cache = false;
  double constant_tolerance = report::kDefaultConstantTolerance;
  double torsion_tolerance = 0;
  std::string shard;                // --shard i/N (report/merge.hpp)
  std::vector<std::string> merge;   // --merge DIR...
  int jobs = 0;                     // --jobs N: threads; 0 = every core
  double fix_budget = report::kDefaultFixBudgetSeconds;
  double time_limit = report::kDefaultReportTimeLimit;
};

static_assert(report::kExitPass == kOk && report::kExitFail == kFail && report::kExitInvalid == kInvalid);

namespace fs = std::filesystem;

/// A run with planar and space inputs: a private folder (under the system's
/// temporary folder) with the two parts' report folders, `planar` and
/// `space` (their names under DIR/parts after the merge), removed when the
/// run ends, however it ends. A part's CI file has the asked file's name in
/// its folder, where report::merge_reports looks for it.
struct MixedRun {
  fs::path root, planar, space;
  explicit MixedRun(const std::string& out) {
    std::string pattern = (fs::temp_directory_path() / "cmr-mixed-XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr)
      throw EnvironmentError(out + ": cannot make a temporary folder for the planar and space parts (" +
                             std::strerror(errno) + ")");
    root = pattern;
    planar = root / "planar";
    space = root / "space";
  }
  MixedRun(const MixedRun&) = delete;
  MixedRun& operator=(const MixedRun&) = delete;
  ~MixedRun() {
    std::error_code ec;
    fs::remove_all(root, ec);
  }
  fs::path planar_file(const std::string& asked) const { return planar / fs::path(asked).filename(); }
  fs::path space_file(const std::string& asked) const { return space / fs::path(asked).filename(); }
};

/// One `cmr report` run from its parsed arguments: a merge of shards, or
/// the inputs collected, the space curves judged (report/space_report.hpp,
/// tools/cmd_space.hpp), the planar inputs batched (report/batch.hpp), and
/// a run with both merged into --out (report/merge.hpp). run() returns the
/// exit code.
class ReportRun {
 public:
  ReportRun(const ReportArgs& args, const CLI::App& cmd, const CLI::Option& shard_option)
      : a_(args), cmd_(cmd), shard_option_(shard_option) {}

  int run() {
    if (!a_.merge.empty()) return merge_shards();
    if (a_.files.empty()) throw InputError("FILES: name the spline files, fonts or folders to report");
    if (shard_option_.count() > 0) shard_ = report::parse_shard(a_.shard);
    collect();
    // A run with both: the space curves and the planar inputs are judged as
    // two parts of one run in a private folder, each with its CI files, then
    // merged into --out (report/merge.hpp: one report.json, JUnit, SARIF,
    // Markdown; index.html links each part's page).
    mixed_ = !space_.empty() && !planar_.empty();
    if (mixed_) parts_.emplace(a_.out);
    if (!space_.empty()) {
      const int code = space_part();
      if (!mixed_) return code;
    }
    if (!mixed_ && cmd_.count("--torsion-tol") > 0) throw InputError("--torsion-tol: for space curves, and this run has none");
    const report::BatchSummary s = planar_part();
    if (mixed_) return merge_parts(s);
    // The one line goes to stderr when a CI file is written to standard output.
    const bool piped = is_stdout_path(a_.junit) || is_stdout_path(a_.sarif) || is_stdout_path(a_.markdown);
    (piped ? std::cerr : std::cout) << report::summary_line(s) << "; wrote " << a_.out << '\n';
    return s.exit_code;
  }

 private:
  /// --merge: the parts' outputs combined, nothing judged again.
  int merge_shards() const {
    if (!a_.files.empty() || shard_option_.count() > 0)
      throw InputError("--merge: takes report folders only (no FILES, no --shard)");
    report::MergeOptions m;
    m.parts.assign(a_.merge.begin(), a_.merge.end());
    m.out = a_.out;
    m.pretty = a_.pretty;
    if (!a_.junit.empty()) m.junit = a_.junit;
    if (!a_.sarif.empty()) m.sarif = a_.sarif;
    if (!a_.markdown.empty()) m.markdown = a_.markdown;
    const report::MergeSummary s = report::merge_reports(m);
    std::cout << s.line << "; wrote " << a_.out << '\n';
    return s.exit_code;
  }

  /// The inputs (folders walked, globs expanded), each with its dimension:
  /// space curves ([x, y, z] points) go to report/space_report.hpp, with the
  /// same schema, findings and CI files (docs/space.md).
  void collect() {
    collected_ = report::collect_files(a_.files, a_.filter, &bases_, &skipped_, {a_.out});
    for (const std::string& f : collected_) {
      int dimension = 2;
      if (report::file_kind(f) == report::FileKind::spline) try {
          dimension = spline_file_dimension(f);
        } catch (const InputError&) {
          // mixed [x, y] and [x, y, z] points: one invalid entry of the report, not the end of the run
        }
      (dimension == 3 ? space_ : planar_) = f;
      dimensions_.push_back(dimension);
    }
  }

  /// The space curves' report (alone, or the space part of a mixed run):
  /// its exit code.
  int space_part() {
    for (const char* flag : {"--segments", "--glyphs", "--location", "--min-severity", "--no-severity", "--strict", "--backend",
                             "--device"})
      if (cmd_.count(flag) > 0)
        throw InputError(std::string(flag) + ": not for space curves (" + space_ +
                         "); their report takes --require, --junit, --sarif, --markdown, --baseline, --constant-tol, "
                         "--torsion-tol and the joint tolerances");
    if (shard_) throw InputError(space_ + ": a space curve; --shard is for planar reports (fonts, SVG, spline files)");
    if (!mixed_)
      for (const report::SkippedPath& k : skipped_)
        std::cerr << "cmr: note: skipped " << k.path << ": " << show_fields(k.reason) << '\n';
    SpaceReportRun run;
    if (mixed_) {  // the space files to their part, the planar ones stay in collected_
      std::vector<std::string> kept, kept_bases;
      const bool with_bases = bases_.size() == collected_.size();
      for (std::size_t i = 0; i < collected_.size(); ++i) {
        const bool is_space = dimensions_[i] == 3;
        (is_space ? run.files : kept).push_back(std::move(collected_[i]));
        if (with_bases) (is_space ? run.bases : kept_bases).push_back(std::move(bases_[i]));
      }
      collected_ = std::move(kept);
      bases_ = std::move(kept_bases);
    } else {
      run.files = std::move(collected_);
      run.bases = std::move(bases_);
    }
    run.out = mixed_ ? parts_->space.string() : a_.out;
    run.quiet = mixed_;
    run.pretty = a_.pretty;
    if (!a_.require.empty()) report::parse_require_list(a_.require, run.parsed);
    report::space_requirements(run.parsed, run.options, space_);
    run.options.max_depth = a_.depth;
    run.options.torsion = true;
    run.options.continuity = a_.continuity;
    run.options.constant_tolerance = a_.constant_tolerance;
    run.options.torsion_tolerance = a_.torsion_tolerance;
    run.options.fixes = !a_.no_fixes && !a_.no_thumbnails;
    run.options.regions = !a_.no_thumbnails;
    run.options.region_size = a_.region_size;
    run.options.budget = cmd_.count("--fix-budget") > 0 ? a_.fix_budget : report::kDefaultSpaceBudgetSeconds;
    run.options.show_fields = show_fields;  // the libraries' fields as this command's flags
    if (!a_.junit.empty()) run.junit = mixed_ ? parts_->space_file(a_.junit) : fs::path(a_.junit);
    if (!a_.sarif.empty()) run.sarif = mixed_ ? parts_->space_file(a_.sarif) : fs::path(a_.sarif);
    if (!a_.baseline.empty()) run.baseline = a_.baseline;
    if (!a_.source_root.empty()) run.source_root = a_.source_root;
    if (!a_.markdown.empty()) run.markdown = mixed_ ? parts_->space_file(a_.markdown) : fs::path(a_.markdown);
    return run_space_report(run);
  }

  /// The planar report's options (checks, gates, severity, regions).
  report::ReportOptions planar_options() const {
    validate(a_.continuity);  // before the batch: a bad tolerance is a usage error, not a bad file
    report::ReportOptions o;
    o.continuity = a_.continuity;
    o.constant_tolerance = a_.constant_tolerance;
    if (!a_.require.empty()) report::parse_require_list(a_.require, o);
    if (!a_.segments.empty()) o.segments = parse_segment_range(a_.segments);
    report::set_severity_options(o, a_.min_severity != -1 ? std::optional<double>(a_.min_severity) : std::nullopt,
                                 !a_.no_severity, a_.strict);
    o.max_depth = a_.depth;
    o.regions = !a_.no_thumbnails;
    o.region_size = a_.region_size;
    o.threads = a_.jobs;
    // Without thumbnails nothing renders: no Vulkan probe (40 ms on lavapipe)
    // and no note about it.
    if (o.regions) o.backend = make_region_backend(a_.backend, "fp64", a_.device, 0);
    o.show_fields = show_fields;  // the libraries' fields as this command's flags
    return o;
  }

  /// The planar inputs (alone, or the planar part of a mixed run), batched;
  /// its notes on stderr.
  report::BatchSummary planar_part() {
    report::ReportOptions o = planar_options();
    report::BatchOptions b;
    report::select_font_inputs(b, o, a_.glyphs, a_.location, a_.between, a_.files);
    const bool interpolation = std::any_of(o.gates.begin(), o.gates.end(), report::is_interpolation_gate);
    b.out = mixed_ ? parts_->planar.string() : a_.out;
    b.pretty = a_.pretty;
    b.fixes = !a_.no_fixes;
    b.fix_budget = a_.fix_budget;
    b.time_limit = a_.time_limit;
    b.cache = !a_.no_cache;
    if (!a_.junit.empty()) b.junit = mixed_ ? parts_->planar_file(a_.junit) : fs::path(a_.junit);
    if (!a_.sarif.empty()) b.sarif = mixed_ ? parts_->planar_file(a_.sarif) : fs::path(a_.sarif);
    if (!a_.markdown.empty()) b.markdown = mixed_ ? parts_->planar_file(a_.markdown) : fs::path(a_.markdown);
    if (!a_.baseline.empty()) b.baseline = a_.baseline;
    if (!a_.source_root.empty()) b.source_root = a_.source_root;
    // A rerun never reads its own outputs (cmr report . --out qa).
    std::vector<std::string> files;
    if (interpolation) {  // a designspace is one file (its masters together), not its sources
      files = report::collect_run_files(a_.files, a_.filter, true, &b.bases, &b.skipped, {a_.out});
    } else {
      files = std::move(collected_);
      b.bases = std::move(bases_);
      b.skipped = std::move(skipped_);
    }
    if (shard_) {
      b.shard = shard_;
      b.shard_positions = report::keep_shard(*shard_, files, b.bases);
    }
    for (const report::SkippedPath& k : b.skipped)
      std::cerr << "cmr: note: skipped " << k.path << ": " << show_fields(k.reason) << '\n';
    const bool bar = !a_.quiet && ::isatty(STDERR_FILENO) == 1 && std::getenv("CI") == nullptr;
    b.report = std::move(o);
    const report::BatchSummary s = report::run_batch(files, b, bar ? report::terminal_progress(std::cerr) : report::BatchProgress{});
    if (bar) report::clear_progress(std::cerr);
    for (const std::string& e : s.invalid_messages) std::cerr << "cmr: " << e << '\n';
    if (!s.note.empty()) std::cerr << "cmr: note: " << show_fields(s.note) << '\n';  // read_spline_file names the file
    if (!s.cache_note.empty()) std::cerr << "cmr: note: " << s.cache_note << '\n';
    if (s.cache_read && s.glyphs_reused + s.glyphs_judged > 0)  // what the resume cache saved (report/report_cache.hpp)
      std::cerr << "cmr: note: " << (fs::path(b.out) / report::kReportCacheName).string() << ": " << s.glyphs_reused
                << (s.glyphs_reused == 1 ? " glyph" : " glyphs") << " unchanged, taken from it; " << s.glyphs_judged
                << " judged\n";
    for (const report::Finding& f : s.new_list) std::cerr << "cmr: new: " << f.file << ": " << f.gate << ": " << f.message << '\n';
    return s;
  }

  /// A mixed run's two parts into --out, and the merged line: its exit code.
  int merge_parts(const report::BatchSummary& s) const {
    report::MergeOptions m;
    m.parts = {parts_->planar, parts_->space};
    m.out = a_.out;
    m.pretty = a_.pretty;
    m.mixed = true;
    if (!a_.junit.empty()) m.junit = a_.junit;
    if (!a_.sarif.empty()) m.sarif = a_.sarif;
    if (!a_.markdown.empty()) m.markdown = a_.markdown;
    const report::MergeSummary merged = report::merge_reports(m);
    const bool piped = is_stdout_path(a_.junit) || is_stdout_path(a_.sarif) || is_stdout_path(a_.markdown);
    std::string line = merged.line.substr(merged.line.find(": ") + 2);  // "merged 2 parts: " is this run's own business
    (piped ? std::cerr : std::cout) << line << "; " << s.items << " planar, " << (merged.splines - s.items)
                                    << (merged.splines - s.items == 1 ? " space curve" : " space curves") << "; wrote " << a_.out << '\n';
    return merged.exit_code;
  }

  const ReportArgs& a_;
  const CLI::App& cmd_;
  const CLI::Option& shard_option_;
  std::optional<report::Shard> shard_;
  std::vector<std::string> collected_, bases_;
  std::vector<report::SkippedPath> skipped_;
  std::vector<int> dimensions_;
  std::string space_, planar_;  // one space input and one planar input, when there are any
  bool mixed_ = false;
  std::optional<MixedRun> parts_;
};

}  // namespace

void add_report_command(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<ReportArgs>();
  auto* cmd = app.add_subcommand("report", "QA report of spline files: JSON and a self-contained HTML page");
  cmd->add_option("FILES", args->files,
                  "spline files (JSON), SVG files, fonts (.ttf, .otf, ...), font sources (NAME.ufo, .glif, "
                  ".designspace: its masters), folders (walked recursively) or globs");
  CLI::Option* shard_option = cmd->add_option("--shard", args->shard,
                  "i/N: report only the inputs whose position k (0-based, in the collected and expanded order) has "
                  "k mod N = i-1; merge the N parts with --merge (docs/report.md, Large collections)");
  cmd->add_option("--merge", args->merge,
                  "combine the report folders of a sharded run into --out (report.json, index.html; with --junit, "
                  "--sarif, --markdown NAME: each part's NAME), without judging again");
  in_range(cmd->add_option("--jobs,-j", args->jobs, "threads (default: every core)"), 1, 4096);
  cmd->add_option("--include", args->filter.include, "in folders, only files matching this glob (repeatable)");
  cmd->add_option("--exclude", args->filter.exclude, "in folders, leave out files matching this glob (repeatable)");
  cmd->add_option("--junit", args->junit, "also write a JUnit XML file (one test case per glyph or spline)");
  cmd->add_option("--sarif", args->sarif, "also write a SARIF 2.1.0 file (one result per violation)");
  cmd->add_option("--markdown", args->markdown,
                  "also write a GitHub-flavoured Markdown summary for a pull request comment (under 65,536 characters)");
  cmd->add_option("--source-root", args->source_root,
                  "findings name files relative to this folder (baseline keys), and SARIF URIs are relative to it; "
                  "default: relative to the folder given (files: the working folder), SARIF to the working folder")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--baseline", args->baseline,
                  "an earlier report.json: fail only on findings that are new since it (new, fixed, unchanged counted)");
  cmd->add_flag("--no-fixes", args->no_fixes, "fonts: draw the thumbnails but do not search certified fixes");
  cmd->add_flag("--no-cache", args->no_cache,
                "fonts: judge every glyph and write no resume cache (default: a glyph whose sources, options and cmr "
                "build did not change since the last run into --out is taken from OUT/report.cache)");
  cmd->add_flag("--quiet", args->quiet, "no progress bar (it is drawn only on a terminal, and never with CI set)");
  cmd->add_option("--out", args->out, "output folder for report.json and index.html")->required();
  cmd->add_option("--require", args->require,
                  "gates, comma separated: exit 1 when a spline fails cmrwi, cmr, split:S (a curvature extremum at "
                  "joint S: the parts before and after monotone in opposite directions), split:S:sharpest, split:S:flattest (by |curvature|), "
                  "curvature-extrema-at-nodes (alias: extrema-at-nodes), curvature-extrema-at-nodes:runs, "
                  "max-extrema-per-segment:N, g2-at-smooth-nodes[:tol], g3-at-smooth-nodes[:tol], no-inflection, each-piece or xy-extrema-at-nodes[:U] "
                  "(a node at every horizontal and vertical tangent; U: tolerated overshoot in font units, default 1); for a "
                  ".designspace or a variable font also g1-between-masters[:DEG] (DEG: a turn in degrees tolerated at smooth nodes), curvature-between-masters and "
                  "extrema-between-masters (judged at every location between the masters: docs/interpolation.md)");
  cmd->add_option("--segments", args->segments, "judge only spans A..B (inclusive); the others are reported as ignored");
  cmd->add_option("--glyphs", args->glyphs, "characters of the fonts among FILES (A-Z,a-z,U+00E9), or all: every glyph of a UFO, every "
                  "character of a font")->capture_default_str();
  cmd->add_option("--min-severity", args->min_severity,
                  "fonts: each finding's severity is the smallest certified move (font units) found that removes it; "
                  "one below UNITS is info and does not fail (default 0.5: half a font unit, invisible on the grid)");
  cmd->add_flag("--no-severity", args->no_severity, "fonts: no severity: every finding fails (faster)");
  cmd->add_flag("--strict", args->strict, "info findings fail too");
  cmd->add_option("--location", args->location,
                  "variable fonts: the instance to judge, axis tags and user values (wght=700,opsz=14); default: the "
                  "default instance");
  cmd->add_option("--between", args->between,
                  "interpolation gates (g1-between-masters): judge this segment of the design space, two locations "
                  "that differ in one axis (wght=400:wght=700; axis tags, user values); default: between adjacent "
                  "masters along every axis");
  in_range(cmd->add_option("--depth", args->depth, "maximum subdivision depth D (level 0 = whole span)"), 0,
           kMaxDepth)
      ->capture_default_str();
  cmd->add_flag("--no-thumbnails", args->no_thumbnails, "skip the regions (fix search and thumbnails)");
  add_backend_options(*cmd, args->backend, args->device);
  in_range(cmd->add_option("--region-size", args->region_size, "fix-search image size in pixels per side"), 8, 1024)
      ->capture_default_str();
  add_continuity_options(*cmd, args->continuity);
  in_range(cmd->add_option("--constant-tol", args->constant_tolerance,
                           "a segment whose curvature spread, halved, times its length (its turning against an arc "
                           "of constant curvature, radians) is at most this is an arc of constant curvature: the "
                           "extremum gates skip its stationary points (rounded circle arcs, CAD approximations of "
                           "circles); 0: exact constants only"),
           0.0, 1.0)
      ->capture_default_str();
  cmd->add_option("--torsion-tol", args->torsion_tolerance,
                  "space curves: a segment whose |torsion| is at most this is planar (torsion constant); default 0: "
                  "only exactly planar segments");
  in_range(cmd->add_option("--fix-budget", args->fix_budget,
                           "seconds for all fix searches of the run (regions, certified fixes); after them failing "
                           "splines are reported without fixes (a note says how many); 0: no limit. Space curves: "
                           "their fix searches and thumbnails, default 5 (the rest listed as not drawn)"),
           0.0, 1e9)
      ->capture_default_str();
  in_range(cmd->add_option("--time-limit", args->time_limit,
                           "seconds for the whole run: past it the run stops with exit 2 and writes nothing; 0: none"),
           0.0, 1e9)
      ->capture_default_str();
  add_pretty_flag(*cmd, args->pretty);
  cmd->callback([args, cmd, shard_option, &exit_code] { exit_code = ReportRun(*args, *cmd, *shard_option).run(); });
}

}  // namespace cmr::cli
