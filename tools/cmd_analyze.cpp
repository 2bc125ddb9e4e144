// cmr analyze FILE [--depth D] [--split S[,S2,...]] [--mode cmrwi|cmr]
// [--segments A..B] [--angle-tol DEG] [--curvature-tol REL]: exact per-span
// classification, joint continuity and spline-level verdicts (README, "Semantics").
#include <CLI/CLI.hpp>

#include "bezierize/analyze.hpp"
#include "spline/errors.hpp"
#include "bezierize/joint_json.hpp"
#include "spline/limits.hpp"
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
};

nlohmann::ordered_json analysis_json(const BSpline& spline, const SplineAnalysis& a, const std::vector<int>& splits) {
  nlohmann::ordered_json segs = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < a.segments.size(); ++i) {
    const Segment& s = spline.segments()[i];
    const SegmentClass& c = a.segments[i];
    const SegmentShape& sh = a.shapes[i];
    if (!a.judged(s.index)) {  // --segments: reported, not judged
      segs.push_back({{"index", s.index}, {"interval", {s.a, s.b}}, {"curvature", "ignored"}, {"inflection", "ignored"}});
      continue;
    }
    segs.push_back({{"index", s.index},
                    {"interval", {s.a, s.b}},
                    {"class", shape_class(sh)},
                    {"curvature", to_string(c.monotonicity.curvature)},
                    {"inflection", to_string(sh.inflection)},
                    {"zero_curvature_at", kappa_zero_at(sh)},
                    {"algorithm2", to_string(c.inflection.inflection)},
                    {"depth", c.monotonicity.depth},
                    {"inflection_depth", c.inflection.depth},
                    {"exact", c.exact_used}});
    if (sh.pole) segs.back()["poles"] = sh.poles;  // W = 0 there: the curve passes through infinity
  }
  nlohmann::ordered_json joints = nlohmann::ordered_json::array();
  std::vector<Joint> all = a.joints;
  if (a.seam) all.push_back(*a.seam);  // a closed spline's seam: joint N
  for (const Joint& j : all) {
    joints.push_back(joint_json(j, {std::nullopt, true, a.seam && j.index == a.seam->index}));  // pole and seam marks
    const bool inside = j.index > a.range.first && j.index <= a.range.last;
    const bool seam_judged = a.seam && j.index == a.seam->index && a.range.first == 0 &&
                             a.range.last == static_cast<int>(a.segments.size()) - 1 && splits.empty() && !a.split &&
                             !a.each_piece;
    if (!inside && !seam_judged) joints.back()["ignored"] = true;
  }
  nlohmann::ordered_json verdict = {{"cmrwi", to_string(a.cmrwi)},
                                    {"cmr", to_string(a.cmr)},
                                    {"cmr_algorithm2", to_string(a.cmr_algorithm2)},
                                    {"cusp", a.cusp}};
  if (a.pole) verdict["pole"] = true;
  if (a.split) verdict["split"] = to_string(*a.split);
  if (a.alternation) {
    verdict["alternation"] = to_string(*a.alternation);
    nlohmann::ordered_json groups = nlohmann::ordered_json::array();
    for (std::size_t g = 0; g < a.groups.size(); ++g) {
      const auto [first, end] = segment_groups(a.range, splits)[g];
      groups.push_back({{"segments", {first, end - 1}}, {"direction", to_string(a.groups[g])}});
    }
    verdict["groups"] = groups;
  }
  if (a.each_piece) {
    // Each group on its own (--each-piece): monotone in either direction.
    verdict["each_piece"] = to_string(*a.each_piece);
    nlohmann::ordered_json groups = nlohmann::ordered_json::array();
    for (std::size_t g = 0; g < a.groups.size(); ++g) {
      const auto [first, end] = segment_groups(a.range, a.cuts)[g];
      groups.push_back({{"segments", {first, end - 1}}, {"direction", to_string(a.groups[g])}});
    }
    verdict["groups"] = groups;
  }
  if (a.range != SegmentRange{0, static_cast<int>(a.segments.size()) - 1})
    verdict["segments"] = {a.range.first, a.range.last};
  if (!a.joint_conflicts.empty()) verdict["joint_conflicts"] = a.joint_conflicts;
  return {{"segments", segs}, {"joints", joints}, {"spline", verdict}};
}

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
  add_pretty_flag(*cmd, args->pretty);
  cmd->callback([args, &exit_code] {
    if (spline_file_dimension(args->file) == 3) {  // [x, y, z] points: a space curve (docs/space.md)
      if (!args->split.empty() || !args->segments.empty() || args->mode != "cmrwi" ||
          args->each_piece_option->count() > 0)
        throw InputError(args->file +
                         ": a space curve; --split, --segments, --each-piece and --mode are for planar splines");
      run_space_analyze(args->file, args->depth, args->torsion, args->continuity, args->pretty);
      exit_code = kOk;
      return;
    }
    const BSpline spline = read_spline_file(args->file);
    if (args->torsion) throw InputError(args->file + ": a planar spline; --torsion is for space curves");
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
    print_json(analysis_json(spline, analyze(spline, o), o.splits), args->pretty);
    exit_code = kOk;
  });
}

}  // namespace cmr::cli
