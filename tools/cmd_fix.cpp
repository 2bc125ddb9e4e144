// cmr fix FILE --require cmr|cmrwi|split:S[:max|min]|extrema-at-nodes
// [--points K,...] [--keep g1|g2|none] [--max-move D] [--out FIXED.json]:
// the nearest certified repair (bezierize/fix.hpp, docs/fix.md).
#include <CLI/CLI.hpp>

#include "bezierize/fix.hpp"
#include "spline/errors.hpp"
#include "spline/spline_json.hpp"
#include "tools/cli_common.hpp"

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

std::vector<int> parse_points(const std::string& text) {
  std::vector<int> out;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t comma = text.find(',', pos);
    std::string item = text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    pos = comma == std::string::npos ? text.size() + 1 : comma + 1;
    if (!item.empty() && (item[0] == 'P' || item[0] == 'p')) item = item.substr(1);
    try {
      std::size_t used = 0;
      const int k = std::stoi(item, &used);
      if (used != item.size()) throw std::invalid_argument(item);
      out.push_back(k);
    } catch (const std::exception&) {
      throw InputError("--points: '" + text + "' is not a list of point indices (K,K2,... or P1,P2,...)");
    }
  }
  return out;
}

}  // namespace

void add_fix_command(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand(
      "fix", "Move the fewest control points the least distance so that the curve meets a requirement (certified)");
  struct Args {
    std::string file, require = "cmr", points, keep = "g1", out;
    double max_move = 0, tolerance = 1e-6;
    int depth = kDefaultDepth;
    bool pretty = false;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("FILE", args->file, "spline file (JSON)")->required();
  cmd->add_option("--require", args->require,
                  "cmr (default), cmrwi, split:S, split:S:max|min (sharpest|flattest), extrema-at-nodes");
  cmd->add_option("--points", args->points,
                  "points that may move (K,K2,...); several move together. Default: every point but an open "
                  "spline's ends, the best single one reported");
  cmd->add_option("--keep", args->keep, "ties kept at joints: g1 (default), g2, none")
      ->check(CLI::IsMember({"g1", "g2", "none"}));
  cmd->add_option("--max-move", args->max_move, "largest displacement of any point (default: the curve size)");
  cmd->add_option("--tolerance", args->tolerance, "distance tolerance relative to the curve size (default 1e-6)");
  in_range(cmd->add_option("--depth", args->depth, "maximum subdivision depth"), 0, kMaxDepth);
  cmd->add_option("--out", args->out, "write the fixed spline here (JSON, atomically)");
  add_pretty_flag(*cmd, args->pretty);
  cmd->callback([args, &exit_code] {
    if (!args->out.empty()) check_output_path(args->out, "--out");
    if (!(args->max_move >= 0) || !std::isfinite(args->max_move))
      throw InputError("--max-move: " + std::to_string(args->max_move) + " is not a distance >= 0");
    FixRequest request;
    request.requirement = parse_fix_requirement(args->require);
    if (!args->points.empty()) request.points = parse_points(args->points);
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
    if (!args->out.empty()) {
      write_spline_file(args->out, *f.spline);
      doc["out"] = args->out;
    }
    print_json(doc, args->pretty);
    exit_code = kOk;
  });
}

}  // namespace cmr::cli
