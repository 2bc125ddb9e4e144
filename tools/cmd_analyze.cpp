// cmr analyze FILE [--depth D] [--split S[,S2,...]] [--mode cmrwi|cmr]
// [--segments A..B] [--angle-tol DEG] [--curvature-tol REL]: exact per-span
// classification, joint continuity and spline-level verdicts (README, "Semantics").
#include <iostream>

#include <CLI/CLI.hpp>

#include "bezierize/analyze.hpp"
#include "report/analyze_json.hpp"
#include "spline/errors.hpp"
#include "spline/limits.hpp"
#include "spline/space.hpp"
#include "spline/spline_json.hpp"
#include "tools/cli_common.hpp"
#include "tools/cmd_space.hpp"

namespace cmr::cli {

namespace {

struct AnalyzeArgs {
  std::string file;
  int depth = kDefaultDepth;
  std::vector<int> split;
  std::string mode = "cmrwi";
  ContinuityTolerances continuity;
  bool pretty = false;
  std::string segments;
  bool torsion = false;  // space curves (tools/cmd_space.hpp)
  std::string each_piece;  // --each-piece [S1,S2,...]
  const CLI::Option* each_piece_option = nullptr;
  double torsion_tolerance = 0;
};

}  // namespace

void add_analyze_command(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<AnalyzeArgs>();
  auto* cmd = app.add_subcommand("analyze", "Classify every span (Algorithms 1 and 2, exact) and the whole spline");
  cmd->add_option("FILE", args->file, "spline file (JSON)")->required();
  in_range(cmd->add_option("--depth", args->depth, "maximum subdivision depth D (level 0 = whole span)"), 0,
           kMaxDepth)
      ->capture_default_str();
  cmd->add_option("--split", args->split,
                  "joint S: spans 0..S-1 against S..N-1; joints S1,S2,...: the groups between them must "
                  "alternate direction (an extremum at each joint and nowhere else)")
      ->delimiter(',');
  cmd->add_option("--segments", args->segments, "judge only spans A..B (inclusive); the others are reported as ignored");
  cmd->add_option("--mode", args->mode, "verdict used for --split")
      ->check(CLI::IsMember({"cmrwi", "cmr"}))
      ->capture_default_str();
  args->each_piece_option =
      cmd->add_option("--each-piece", args->each_piece,
                      "each piece monotone on its own, in either direction (no alternation); with joints "
                      "S1,S2,... the groups between them (docs/semantics.md)")
          ->expected(0, 1);
  add_continuity_options(*cmd, args->continuity);
  cmd->add_flag("--torsion", args->torsion, "space curves: also judge torsion monotonicity (docs/space.md)");
  cmd->add_option("--torsion-tol", args->torsion_tolerance,
                  "with --torsion: a segment whose |torsion| is at most this is planar (torsion constant); default 0: "
                  "only exactly planar segments");
  add_pretty_flag(*cmd, args->pretty);
  cmd->callback([args, &exit_code] {
    // The file is parsed once (a 10^6-span spline's JSON is large).
    std::optional<nlohmann::json> doc = read_spline_document(args->file);
    std::optional<JsonReleaser> release(std::in_place, *doc);  // out of memory below: torn down without allocating
    if (spline_file_dimension(args->file, *doc) == 3) {  // [x, y, z] points: a space curve (docs/space.md)
      if (!args->split.empty() || !args->segments.empty() || args->mode != "cmrwi" ||
          args->each_piece_option->count() > 0)
        throw InputError(args->file +
                         ": a space curve; --split, --segments, --each-piece and --mode are for planar splines");
      if (args->torsion_tolerance != 0 && !args->torsion) throw InputError("--torsion-tol: only with --torsion");
      run_space_analyze(args->file, args->depth, args->torsion, args->continuity, args->pretty, args->torsion_tolerance);
      exit_code = kOk;
      return;
    }
    const BSpline spline = spline_from_document(*doc, args->file);
    release.reset();
    doc.reset();  // its memory before the analysis
    if (args->torsion || args->torsion_tolerance != 0)
      throw InputError(input_name(args->file) + ": a planar spline; --torsion and --torsion-tol are for space curves");
    AnalyzeOptions o;
    o.classify.max_depth = args->depth;
    if (args->split.size() == 1) o.split = args->split[0];
    else o.splits = args->split;
    if (args->each_piece_option->count() > 0) {
      if (!args->split.empty()) throw InputError("--each-piece takes the joints itself (--each-piece S1,S2,...): drop --split");
      o.each_piece = true;
      o.splits = parse_joint_list(args->each_piece);
    }
    if (!args->segments.empty()) o.segments = parse_segment_range(args->segments);
    o.split_mode = args->mode == "cmr" ? Mode::cmr : Mode::cmrwi;
    o.continuity = args->continuity;
    // Streamed, on every available core (report/analyze_json.hpp).
    report::write_analysis_json(std::cout, spline, o, {.pretty = args->pretty});
    exit_code = kOk;
  });
}

}  // namespace cmr::cli
