// `cmr fix FILE` on a space curve (tools/cmd_space.hpp, design/space_fix.hpp,
// docs/fix.md "Space curves").
#include <cmath>
#include <iostream>

#include <glm/geometric.hpp>

#include "design/space_fix.hpp"
#include "draw/draw.hpp"
#include "io/output.hpp"
#include "report/fix_json.hpp"
#include "report/space_report.hpp"
#include "spline/errors.hpp"
#include "step/chain_fix.hpp"
#include "tools/cli_common.hpp"
#include "tools/cmd_space.hpp"

namespace cmr::cli {

namespace {

using Json = nlohmann::ordered_json;

Json vec3_json(const Vec3& p) { return Json::array({p.x, p.y, p.z}); }

std::string level_text(int level) {
  std::string s = level == 0 ? "not G1" : "G";
  if (level > 0) s += std::to_string(level);
  return s;
}

/// The moved point's region in its plane (the labels `cmr region` draws; a
/// point's region does not depend on where the point itself is) with the
/// curve projected onto the plane, before with the move and after; for a
/// curve that needs no fix, the region of its middle point in its default plane.
std::string space_fix_png(const SpaceSpline& before, const SpaceFixResult& f, int depth) {
  SpaceRegionRequest rr;
  rr.max_depth = depth;
  rr.width = rr.height = 200;
  Vec2 shift{0, 0};
  if (f.moves.empty()) {
    rr.point = before.unique_point_count() / 2;
  } else {
    const SpacePointMove& m = f.moves.front();
    rr.point = m.point;
    rr.plane = m.plane;
    shift = Vec2{glm::dot(m.to - m.from, m.plane.u), glm::dot(m.to - m.from, m.plane.v)};
    const double h = std::max(4 * m.distance, f.size / 20);
    rr.view = View{-h, -h, h, h};
  }
  const SpaceRegionProblem problem = SpaceRegionProblem::make(before, rr);
  const SpacePlane& plane = *problem.request().plane;
  const RegionResult image = problem.render();
  const BSpline seen_before = project_to_plane(before, plane), seen_after = project_to_plane(*f.spline, plane);
  draw::RegionPicture pb, pa;
  pb.spline = &seen_before, pb.layers = {&image}, pb.points = {rr.point};
  pa.spline = &seen_after, pa.layers = {&image}, pa.points = {rr.point};
  if (!f.moves.empty()) pb.moved = std::make_pair(Vec2{0, 0}, shift);
  draw::Figure fig;
  const std::string name = std::string("P").append(std::to_string(rr.point));
  fig.title = "cmr fix (space curve): " + name + "'s region in its plane";
  fig.rows = {{draw::Panel{pb, "before: the region and the move"},
               draw::Panel{pa, std::string("after: analyze_space says ") + to_string(f.certificate.curvature)}}};
  fig.legend = draw::legend_for(pb);
  std::string caption = "nothing to move: the curve meets the requirement";
  if (!f.moves.empty()) {
    caption = "moved " + name;
    caption.append(" by ").append(std::to_string(f.max_distance)).append(" (");
    caption.append(std::to_string(f.max_distance / f.size * 100)).append("% of the curve size)");
  }
  fig.caption = caption;
  return draw::figure_png(fig);
}

}  // namespace

void run_space_fix(const SpaceFixArgs& args) {
  if (!args.out.empty()) check_output_path(args.out, "--out");
  if (!args.png.empty()) check_output_path(args.png, "--png");
  if (args.require != "cmr" && args.require != "cmrwi")
    throw InputError(args.file + ": a space curve; its fix takes --require cmr (|kappa| monotone, no zero curvature) "
                                 "or cmrwi (|kappa| monotone), not '" +
                     args.require + "'");
  SpaceFixRequest request;
  request.no_zero_curvature = args.require == "cmr";
  if (!args.points.empty()) request.points = parse_point_list(args.points);
  request.plane_text = args.plane;
  request.keep = args.keep == "g2" ? Keep::g2 : args.keep == "none" ? Keep::none : Keep::g1;
  request.max_move = args.max_move;
  request.tolerance = args.tolerance;
  request.max_depth = args.depth;
  const SpaceSpline spline = read_space_spline_file(args.file);
  const SpaceFixResult f = space_fix(spline, request);
  if (!f.fixed) throw InputError(args.file + ": " + show_fields(f.reason));
  Json doc = report::space_fix_document(args.file, args.require, request, f);
  show_fields_in(doc, show_fields);  // the units' reasons name fields: as this command's flags
  OutputSet outputs;  // all or none (io/output.hpp)
  if (!args.out.empty()) {
    outputs.stage(args.out, space_spline_to_json(*f.spline).dump(2) + "\n");
    doc["out"] = args.out;
  }
  if (!args.png.empty()) {
    outputs.stage(args.png, space_fix_png(spline, f, args.depth));
    doc["png"] = args.png;
  }
  outputs.commit();
  // With --out - (or --png -) stdout is the file alone: the JSON goes to stderr (as cmr fix's).
  if (is_stdout_path(args.out) || is_stdout_path(args.png)) std::cerr << json_text(doc, args.pretty);
  else print_json(doc, args.pretty);
}

void run_chain_fix(const ChainFixArgs& args) {
  if (args.require != "cmr" && args.require != "cmrwi" && args.require != "each-piece")
    throw InputError(args.file + ": a STEP chain; its fix takes --require cmr (the whole chain's |kappa| one way, no zero "
                                 "curvature), cmrwi (the whole chain one way) or each-piece (each edge monotone), not '" +
                     args.require + "'");
  if (args.chain < 1) throw InputError("--chain: " + std::to_string(args.chain) + " is not a chain number (1, 2, ...: cmr import lists them)");
  import::ChainFixRequest request;  // --out is a folder (made, or written into, as cmr import's)
  request.whole_chain = args.require != "each-piece";
  request.no_zero_curvature = args.require == "cmr";
  request.keep = args.keep == "none" ? 0 : args.keep == "g1" ? 1 : args.keep == "g3" ? 3 : 2;
  request.max_move = args.max_move;
  request.tolerance = args.tolerance;
  request.max_depth = args.depth;
  const import::StepCurves curves = read_step_within_budget(args.file);
  if (static_cast<std::size_t>(args.chain) > curves.chains.size())
    throw InputError("--chain: " + args.file + " has " + std::to_string(curves.chains.size()) +
                     (curves.chains.size() == 1 ? " chain" : " chains") + ", not " + std::to_string(args.chain) +
                     " (cmr import lists them)");
  const std::size_t index = static_cast<std::size_t>(args.chain - 1);
  const import::ChainFixResult r = [&] {
    try {
      return import::fix_step_chain(curves, index, request);
    } catch (const InputError& e) {
      throw InputError(args.file + ": " + show_fields(marked_text(e)));
    }
  }();
  if (!r.fixed) throw InputError(args.file + ": chain " + std::to_string(args.chain) + ": " + show_fields(r.reason));
  const import::StepChain& chain = curves.chains[index];
  Json doc;
  doc["file"] = args.file;
  doc["chain"] = args.chain;
  doc["require"] = args.require;
  doc["keep"] = args.keep;
  doc["already"] = r.already;
  doc["fixed"] = r.fixed;
  doc["before"] = import::step_chain_report(curves, chain, args.chain).front();
  import::StepChain after = chain;
  after.junctions = r.junctions_after;
  doc["after"] = import::step_chain_report(r.curves, after, args.chain).front();
  Json edges = Json::array();
  for (std::size_t i = 0; i < r.edges.size(); ++i) {
    const import::ChainEdgeFix& e = r.edges[i];
    Json je;
    je["edge"] = import::chain_edge_label(curves, chain, i);
    je["name"] = curves.curves[e.curve].name;
    je["before"] = e.before;
    je["after"] = e.after;
    je["held"] = e.held;
    if (e.fix && !e.fix->moves.empty()) {
      const SpacePointMove& m = e.fix->moves.front();
      je["move"] = Json{{"point", m.point}, {"from", vec3_json(m.from)}, {"to", vec3_json(m.to)}, {"distance", m.distance},
                        {"relative", m.distance / e.fix->size}};
    }
    edges.push_back(je);
  }
  doc["edges"] = edges;
  Json junctions = Json::array();
  for (std::size_t j = 0; j < r.junctions_before.size(); ++j)
  {
    std::string at = import::chain_edge_label(curves, chain, j);
    at += " > ";
    at += import::chain_edge_label(curves, chain, (j + 1) % chain.curves.size());
    junctions.push_back(Json{{"at", at},
                             {"before", level_text(r.junctions_before[j].level)},
                             {"after", level_text(r.junctions_after[j].level)}});
  }
  doc["junctions"] = junctions;
  doc["certificate"] =
      "each moved edge judged again by analyze_space; the junctions computed again by OpenCASCADE from the fixed edges";
  doc["seconds"] = r.seconds;
  OutputSet outputs;  // all or none (io/output.hpp)
  if (!args.out.empty()) {
    const std::filesystem::path dir = args.out, stem = std::filesystem::path(args.file).stem();
    outputs.create_folder(dir);
    Json written = Json::array();
    for (std::size_t i : chain.curves) {
      const import::StepCurve& c = r.curves.curves[i];
      const std::filesystem::path path = dir / (stem.string() + "_" + import::step_curve_stem(c) + ".json");
      outputs.stage(path, import::step_curve_json(c).dump(2) + "\n");
      written.push_back(path.string());
    }
    doc["out"] = written;
  }
  outputs.commit();
  print_json(doc, args.pretty);
}

}  // namespace cmr::cli
