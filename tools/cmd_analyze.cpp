// cmr analyze FILE [--depth D] [--split S[,S2,...]] [--mode cmrwi|cmr]
// [--segments A..B] [--angle-tol DEG] [--curvature-tol REL]: exact per-span
// classification, joint continuity and spline-level verdicts (README, "Semantics").
#include <iostream>

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

nlohmann::ordered_json segment_json(const Segment& s, const SegmentClass& c, const SegmentShape& sh, bool judged) {
  if (!judged)  // --segments: reported, not judged
    return {{"index", s.index}, {"interval", {s.a, s.b}}, {"curvature", "ignored"}, {"inflection", "ignored"}};
  nlohmann::ordered_json seg = {{"index", s.index},
                                {"interval", {s.a, s.b}},
                                {"class", shape_class(sh)},
                                {"curvature", to_string(c.monotonicity.curvature)},
                                {"inflection", to_string(sh.inflection)},
                                {"zero_curvature_at", kappa_zero_at(sh)},
                                {"algorithm2", to_string(c.inflection.inflection)},
                                {"depth", c.monotonicity.depth},
                                {"inflection_depth", c.inflection.depth},
                                {"exact", c.exact_used}};
  if (sh.pole) seg["poles"] = sh.poles;  // W = 0 there: the curve passes through infinity
  return seg;
}

nlohmann::ordered_json verdict_json(const SplineAnalysis& a, const std::vector<int>& splits) {
  nlohmann::ordered_json verdict = {{"cmrwi", to_string(a.cmrwi)},
                                    {"cmr", to_string(a.cmr)},
                                    {"cmr_algorithm2", to_string(a.cmr_algorithm2)},
                                    {"cusp", a.cusp}};
  if (a.pole) verdict["pole"] = true;
  if (a.split) verdict["split"] = to_string(*a.split);
  if (a.alternation || a.each_piece) {
    // --split S1,S2,... (alternation) or --each-piece (each group on its own:
    // monotone in either direction): the groups between the cut joints.
    if (a.alternation) verdict["alternation"] = to_string(*a.alternation);
    else verdict["each_piece"] = to_string(*a.each_piece);
    nlohmann::ordered_json groups = nlohmann::ordered_json::array();
    const auto parts = segment_groups(a.range, a.alternation ? splits : a.cuts);
    for (std::size_t g = 0; g < a.groups.size(); ++g)
      groups.push_back({{"segments", {parts[g].first, parts[g].second - 1}}, {"direction", to_string(a.groups[g])}});
    verdict["groups"] = groups;
  }
  if (a.range != SegmentRange{0, static_cast<int>(a.segments.size()) - 1})
    verdict["segments"] = {a.range.first, a.range.last};
  if (!a.joint_conflicts.empty()) verdict["joint_conflicts"] = a.joint_conflicts;
  return verdict;
}

// The analysis as JSON on stdout, one segment and one joint at a time (a
// spline of 10^6 spans is never one JSON tree: docs/outputs.md, "Limits").
void print_analysis(const BSpline& spline, const SplineAnalysis& a, const std::vector<int>& splits, bool pretty) {
  JsonObjectStream out(std::cout, pretty);
  out.begin_array("segments");
  for (std::size_t i = 0; i < a.segments.size(); ++i) {
    const Segment& s = spline.segments()[i];
    out.element(segment_json(s, a.segments[i], a.shapes[i], a.judged(s.index)));
  }
  out.end_array();
  out.begin_array("joints");
  const auto joint = [&](const Joint& j) {
    const bool is_seam = a.seam && j.index == a.seam->index;
    nlohmann::ordered_json json = joint_json(j, {std::nullopt, true, is_seam});  // pole and seam marks
    const bool inside = j.index > a.range.first && j.index <= a.range.last;
    const bool seam_judged = is_seam && a.range.first == 0 &&
                             a.range.last == static_cast<int>(a.segments.size()) - 1 && splits.empty() && !a.split &&
                             !a.each_piece;
    if (!inside && !seam_judged) json["ignored"] = true;
    out.element(json);
  };
  for (const Joint& j : a.joints) joint(j);
  if (a.seam) joint(*a.seam);  // a closed spline's seam: joint N
  out.end_array();
  out.member("spline", verdict_json(a, splits));
  out.finish();
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
    print_analysis(spline, analyze(spline, o), o.splits, args->pretty);
    exit_code = kOk;
  });
}

}  // namespace cmr::cli
