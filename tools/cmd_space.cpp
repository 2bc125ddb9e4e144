// Space curves on the command line (tools/cmd_space.hpp, docs/space.md).
#include "tools/cmd_space.hpp"

#include <cmath>
#include <iostream>

#include "bezierize/space_region.hpp"
#include "draw/draw.hpp"
#include "io/output.hpp"
#include "spline/errors.hpp"
#include "tools/cli_common.hpp"

namespace cmr::cli {

namespace {

nlohmann::ordered_json vec3(const Vec3& p) { return {p.x, p.y, p.z}; }

const char* sign_word(int s) { return s > 0 ? "positive" : (s < 0 ? "negative" : "changes-or-zero"); }

}  // namespace

nlohmann::ordered_json space_analysis_json(const SpaceSpline& spline, const SpaceAnalysis& a) {
  nlohmann::ordered_json segs = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < a.segments.size(); ++i) {
    const Segment& s = spline.segments()[i];
    const SpaceSegmentResult& r = a.segments[i];
    nlohmann::ordered_json j = {{"index", s.index},
                                {"interval", {s.a, s.b}},
                                {"class", r.cusp ? "cusp" : (r.straight ? "straight" : "regular")},
                                {"curvature", to_string(r.curvature.curvature)},
                                {"zero_curvature", r.zero_curvature},
                                {"depth", r.curvature.depth},
                                {"exact", r.exact_used}};
    if (r.torsion) {
      j["torsion"] = to_string(r.torsion->curvature);
      j["torsion_depth"] = r.torsion->depth;
      j["torsion_sign"] = sign_word(r.torsion_sign);
    }
    segs.push_back(j);
  }
  nlohmann::ordered_json joints = nlohmann::ordered_json::array();
  std::vector<SpaceJoint> all = a.joints;
  if (a.seam) all.push_back(*a.seam);
  for (const SpaceJoint& j : all) {
    std::string continuity = std::to_string(j.continuity);
    continuity.insert(continuity.begin(), 'C');
    joints.push_back({{"index", j.index},
                      {"knot", j.knot},
                      {"multiplicity", j.multiplicity},
                      {"continuity", continuity},
                      {"g1", j.g1},
                      {"g2", j.g2},
                      {"angle", j.angle_deg},
                      {"normal_angle", j.normal_angle_deg},
                      {"zero_tangent", j.zero_tangent},
                      {"kappa_left", j.kappa_left},
                      {"kappa_right", j.kappa_right},
                      {"jump", j.jump > 0 ? "up" : (j.jump < 0 ? "down" : "none")},
                      {"tau_left", j.tau_left},
                      {"tau_right", j.tau_right},
                      {"torsion_jump", j.torsion_jump > 0 ? "up" : (j.torsion_jump < 0 ? "down" : "none")}});
    if (a.seam && j.index == a.seam->index) joints.back()["seam"] = true;
  }
  nlohmann::ordered_json verdict = {{"dimension", 3},
                                    {"curvature", to_string(a.curvature)},
                                    {"zero_curvature", a.zero_curvature},
                                    {"cusp", a.cusp}};
  if (a.torsion) verdict["torsion"] = to_string(*a.torsion);
  if (!a.joint_conflicts.empty()) verdict["joint_conflicts"] = a.joint_conflicts;
  return {{"segments", segs}, {"joints", joints}, {"spline", verdict}};
}

void run_space_analyze(const std::string& file, int depth, bool torsion, const ContinuityTolerances& continuity,
                       bool pretty) {
  const SpaceSpline spline = read_space_spline_file(file);
  SpaceAnalyzeOptions o;
  o.max_depth = depth;
  o.torsion = torsion;
  o.continuity = continuity;
  print_json(space_analysis_json(spline, analyze_space(spline, o)), pretty);
}

namespace {

std::string pgm(const RegionResult& img, const std::vector<std::uint8_t>& values, int maxval) {
  std::string out = "P5\n" + std::to_string(img.width) + " " + std::to_string(img.height) + "\n" +
                    std::to_string(maxval) + "\n";
  out.append(reinterpret_cast<const char*>(values.data()), values.size());
  return out;
}

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

}  // namespace

void run_space_region(const SpaceRegionArgs& a) {
  if (a.backend == "vulkan")
    throw InputError("--backend vulkan: regions of space curves run on the CPU backend only (use --backend cpu or auto)");
  if (a.point.empty()) throw InputError("--point is required (see cmr region --help)");
  const SpaceSpline spline = read_space_spline_file(a.file);
  SpaceRegionRequest r;
  try {
    std::size_t used = 0;
    r.point = std::stoi(a.point, &used);
    if (used != a.point.size()) throw std::invalid_argument(a.point);
  } catch (const std::exception&) {
    throw InputError("--point: expected an index (got '" + a.point + "'; 'all' is for planar splines)");
  }
  if (r.point < 0 || r.point >= spline.unique_point_count())
    throw InputError("--point " + a.point + " is outside 0.." + std::to_string(spline.unique_point_count() - 1));
  if (!a.plane.empty()) r.plane = parse_space_plane(a.plane, spline.points()[static_cast<std::size_t>(r.point)]);
  const auto [w, h] = parse_size(a.size);
  r.width = w;
  r.height = h;
  r.max_depth = a.depth;
  if (!a.view.empty()) r.view = parse_view(a.view);
  if (!a.png.empty()) check_output_path(a.png, "--png");
  if (!a.labels.empty()) check_output_path(a.labels, "--labels");
  if (!a.depth_map.empty()) check_output_path(a.depth_map, "--depth-map");
  const SpaceRegionProblem problem = SpaceRegionProblem::make(spline, r);
  const RegionResult img = problem.render();
  const SpacePlane& plane = *problem.request().plane;
  OutputSet out;
  if (!a.labels.empty()) out.stage(a.labels, pgm(img, img.codes(), 255));
  const BSpline seen = project_to_plane(spline, plane);
  if (!a.png.empty() || ends_with(a.depth_map, ".png")) {
    draw::RegionPicture pic;
    pic.spline = &seen;
    pic.layers = {&img};
    pic.points = {r.point};
    pic.max_depth = r.max_depth;
    if (!a.png.empty()) out.stage(a.png, draw::region_png(pic));
    if (ends_with(a.depth_map, ".png")) {
      pic.depth_shading = true;
      out.stage(a.depth_map, draw::region_png(pic));
    }
  }
  if (!a.depth_map.empty() && !ends_with(a.depth_map, ".png")) out.stage(a.depth_map, pgm(img, img.depth, r.max_depth));
  out.commit();
  std::uint64_t counts[kRegionLabelCodes] = {};
  for (std::size_t i = 0; i < img.size(); ++i) ++counts[img.code_at(i)];
  nlohmann::ordered_json c;
  for (std::uint8_t l = 0; l < kRegionLabelCodes; ++l) c[img.label_name(l)] = counts[l];
  nlohmann::ordered_json doc = {{"width", img.width},
                                {"height", img.height},
                                {"view", {img.view.x0, img.view.y0, img.view.x1, img.view.y1}},
                                {"plane", {{"origin", vec3(plane.origin)}, {"u", vec3(plane.u)}, {"v", vec3(plane.v)}}},
                                {"dimension", 3},
                                {"backend", "cpu"},
                                {"point", r.point},
                                {"counts", c}};
  if (a.stats) {
    doc["seconds"] = img.seconds;
    doc["exact_pixels"] = img.exact_pixels;
  }
  print_json(doc, a.pretty);
}

}  // namespace cmr::cli
