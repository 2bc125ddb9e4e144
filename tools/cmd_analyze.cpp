// cmr analyze FILE [--depth D] [--split S[,S2,...]] [--mode cmrwi|cmr]
// [--segments A..B] [--angle-tol DEG] [--curvature-tol REL]: exact per-span
// classification, joint continuity and spline-level verdicts (README, "Semantics").
#include <CLI/CLI.hpp>

#include "bezierize/analyze.hpp"
#include "spline/limits.hpp"
#include "spline/spline_json.hpp"
#include "tools/cli_common.hpp"

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
    joints.push_back({{"index", j.index},
                      {"knot", j.knot},
                      {"multiplicity", j.multiplicity},
                      {"continuity", "C" + std::to_string(j.continuity)},
                      {"g1", j.g1},
                      {"g2", j.g2},
                      {"angle", j.angle_deg},  // NaN (a zero tangent) prints as null
                      {"zero_tangent", j.zero_tangent},
                      {"kappa_left", j.kappa_left},
                      {"kappa_right", j.kappa_right},
                      {"jump", jump_name(shown_jump(j))},
                      {"exact_jump", jump_name(j.jump)}});
    if (j.pole) joints.back()["pole"] = true;
    if (a.seam && j.index == a.seam->index) joints.back()["seam"] = true;
    const bool inside = j.index > a.range.first && j.index <= a.range.last;
    const bool seam_judged = a.seam && j.index == a.seam->index && a.range.first == 0 &&
                             a.range.last == static_cast<int>(a.segments.size()) - 1 && splits.empty() && !a.split;
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
  add_continuity_options(*cmd, args->continuity);
  add_pretty_flag(*cmd, args->pretty);
  cmd->callback([args, &exit_code] {
    const BSpline spline = read_spline_file(args->file);
    AnalyzeOptions o;
    o.classify.max_depth = args->depth;
    if (args->split.size() == 1) o.split = args->split[0];
    else o.splits = args->split;
    if (!args->segments.empty()) o.segments = parse_segment_range(args->segments);
    o.split_mode = args->mode == "cmr" ? Mode::cmr : Mode::cmrwi;
    o.continuity = args->continuity;
    print_json(analysis_json(spline, analyze(spline, o), o.splits), args->pretty);
    exit_code = kOk;
  });
}

}  // namespace cmr::cli
