// cmr fix FILE --require cmr|cmrwi|split:S[:sharpest|flattest]|each-piece|extrema-at-nodes|no-inflection|g2-at-smooth-nodes[:tol]|each-run [--segments A..B]
// [--points K,...] [--keep g1|g2|none] [--max-move D] [--out FIXED.json]:
// the nearest certified repair (bezierize/fix.hpp, docs/fix.md).
#include <CLI/CLI.hpp>

#include "bezierize/fix.hpp"
#include "bezierize/segments.hpp"
#include "bezierize/region.hpp"
#include "draw/draw.hpp"
#include "spline/errors.hpp"
#include "spline/spline_json.hpp"
#include "tools/cli_common.hpp"
#include "tools/cmd_space.hpp"

namespace cmr::cli {

namespace {

using Json = nlohmann::ordered_json;

Json point_json(Vec2 p) { return Json::array({p.x, p.y}); }

/// The verdicts of the certificate, as `cmr analyze` prints them.
Json certificate_json(const FixResult& f, const FixRequirement& req) {
  const SplineAnalysis& a = f.certificate;
  Json j = {{"requirement", to_string(req)},
            {"holds", f.certificate_holds},
            {"ties", f.ties_hold},
            {"cmrwi", to_string(a.cmrwi)},
            {"cmr", to_string(a.cmr)},
            {"cmr_algorithm2", to_string(a.cmr_algorithm2)}};
  if (a.split) j["split"] = to_string(*a.split);
  Json joints = Json::array();
  std::vector<Joint> all = a.joints;
  if (a.seam) all.push_back(*a.seam);
  for (const Joint& jt : all)
    joints.push_back({{"index", jt.index}, {"continuity", "C" + std::to_string(jt.continuity)}, {"g1", jt.g1}, {"g2", jt.g2}});
  j["joints"] = joints;
  return j;
}

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

}  // namespace

void add_fix_command(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand(
      "fix", "Move the fewest control points the least distance so that the curve meets a requirement (certified)");
  struct Args {
    std::string file, require = "cmr", points, keep = "g1", out, png, segments, plane;
    double max_move = 0, tolerance = 1e-6;
    int depth = kDefaultDepth;
    bool pretty = false;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("FILE", args->file, "spline file (JSON)")->required();
  cmd->add_option("--require", args->require,
                  "cmr (default), cmrwi, split:S, split:S:sharpest|flattest, each-piece, extrema-at-nodes, no-inflection, "
                  "g2-at-smooth-nodes[:tol], each-run");
  cmd->add_option("--points", args->points,
                  "points that may move (K,K2,...); several move together. Default: every point but an open "
                  "spline's ends, the best single one reported");
  cmd->add_option("--keep", args->keep, "ties kept at joints: g1 (default), g2, none")
      ->check(CLI::IsMember({"g1", "g2", "none"}));
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
  cmd->callback([args, max_move, &exit_code] {
    // 0 would mean "no point may move": no fix at all. Refused rather than
    // read as the default (it was: issue 42), so that it never means "unlimited".
    if (max_move->count() > 0 && !(args->max_move > 0 && std::isfinite(args->max_move)))
      throw InputError("--max-move: " + max_move->as<std::string>() + " is not a distance > 0 (leave it out for the default, the curve size)");
    if (spline_file_dimension(args->file) == 3) {  // [x, y, z] points: a space curve (docs/fix.md, "Space curves")
      if (!args->segments.empty())
        throw InputError(args->file + ": a space curve; --segments is for planar splines");
      run_space_fix({args->file, args->require, args->points, args->keep, args->plane, args->out, args->png,
                     args->max_move, args->tolerance, args->depth, args->pretty});
      exit_code = kOk;
      return;
    }
    if (!args->plane.empty()) throw InputError(args->file + ": a planar spline; --plane is for space curves");
    if (!args->out.empty()) check_output_path(args->out, "--out");
    if (!args->png.empty()) check_output_path(args->png, "--png");
    if (!(args->max_move >= 0) || !std::isfinite(args->max_move))
      throw InputError("--max-move: " + std::to_string(args->max_move) + " is not a distance >= 0");
    FixRequest request;
    request.requirement = parse_fix_requirement(args->require);
    if (!args->segments.empty()) request.requirement.segments = parse_segment_range(args->segments);
    if (!args->points.empty()) request.points = parse_point_list(args->points);
    request.together = request.points.size() > 1;
    request.keep = args->keep == "g2" ? Keep::g2 : args->keep == "none" ? Keep::none : Keep::g1;
    request.max_move = args->max_move;
    request.tolerance = args->tolerance;
    request.max_depth = args->depth;
    const BSpline spline = read_spline_file(args->file);
    const FixResult f = fix(spline, request);
    if (!f.fixed) throw InputError(args->file + ": " + f.reason);
    Json moves = Json::array();
    for (const PointMove& m : f.moves)
      moves.push_back({{"point", m.point},
                       {"from", point_json(m.from)},
                       {"to", point_json(m.to)},
                       {"displacement", point_json(m.to - m.from)},
                       {"distance", m.distance},
                       {"relative", m.distance / f.size}});
    Json units = Json::array();
    for (const UnitFix& u : f.units) {
      Json ju = {{"points", u.points}, {"slide", u.slide}, {"found", u.found}};
      if (u.found) ju["displacement"] = point_json(u.displacement), ju["distance"] = u.distance;
      units.push_back(ju);
    }
    Json doc = {{"file", args->file},
                {"require", to_string(request.requirement)},
                {"segments", {f.certificate.range.first, f.certificate.range.last}},
                {"keep", to_string(request.keep)},
                {"already", f.already},
                {"fixed", f.fixed},
                {"moves", moves},
                {"total_squared", f.total_squared},
                {"max_distance", f.max_distance},
                {"size", f.size},
                {"tolerance", request.tolerance * f.size},
                {"failing_segments", f.failing_segments},
                {"tie_joints", f.tie_joints},
                {"units", units},
                {"certificate", certificate_json(f, request.requirement)},
                {"evaluations", f.evaluations},
                {"seconds", f.seconds}};
    // All outputs or none (io/output.hpp).
    OutputSet outputs;
    if (!args->out.empty()) {
      outputs.stage(args->out, spline_to_json(*f.spline).dump(2) + "\n");
      doc["out"] = args->out;
    }
    if (!args->png.empty()) {
      outputs.stage(args->png, before_after_png(spline, f, request));
      doc["png"] = args->png;
    }
    outputs.commit();
    print_json(doc, args->pretty);
    exit_code = kOk;
  });
}

}  // namespace cmr::cli
