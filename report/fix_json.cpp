#include "report/fix_json.hpp"

#include "report/space_report.hpp"

#include <string>
#include <utility>
#include <vector>

namespace cmr::report {

namespace {

using Json = nlohmann::ordered_json;

Json point_json(Vec2 p) { return Json::array({p.x, p.y}); }
Json vec3(const Vec3& p) { return Json::array({p.x, p.y, p.z}); }
Json plane_json(const SpacePlane& p) { return {{"origin", vec3(p.origin)}, {"u", vec3(p.u)}, {"v", vec3(p.v)}}; }

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
  for (const Joint& jt : all) {
    std::string continuity = "C";  // appended, not "C" + ...: GCC 12 warns (-Wrestrict) on that here
    continuity.append(std::to_string(jt.continuity));
    joints.push_back({{"index", jt.index}, {"continuity", continuity}, {"g1", jt.g1}, {"g2", jt.g2}});
  }
  j["joints"] = joints;
  return j;
}

}  // namespace

Json fix_json(const std::optional<std::string>& file, const FixRequest& request, const FixResult& f) {
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
  Json rest = {{"require", to_string(request.requirement)},
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
  if (!file) return rest;
  Json doc = {{"file", *file}};
  for (auto it = rest.begin(); it != rest.end(); ++it) doc[it.key()] = std::move(it.value());
  return doc;
}

Json space_fix_document(const std::optional<std::string>& file, const std::string& require,
                        const SpaceFixRequest& request, const SpaceFixResult& f) {
  Json moves = Json::array();
  for (const SpacePointMove& m : f.moves)
    moves.push_back({{"point", m.point},
                     {"from", vec3(m.from)},
                     {"to", vec3(m.to)},
                     {"displacement", vec3(m.to - m.from)},
                     {"distance", m.distance},
                     {"relative", m.distance / f.size},
                     {"plane", plane_json(m.plane)}});
  Json units = Json::array();
  for (const SpaceUnitFix& u : f.units) {
    Json ju = {{"point", u.point}, {"found", u.found}};
    if (u.plane) ju["plane"] = plane_json(*u.plane);
    if (u.found)
      ju["displacement"] = vec3(u.displacement), ju["distance"] = u.distance;
    else
      ju["reason"] = u.reason;
    units.push_back(ju);
  }
  Json certificate = {{"requirement", require},
                      {"holds", f.certificate_holds},
                      {"ties", f.ties_hold},
                      {"spline", report::space_verdict_json(f.certificate)}};
  Json joints = Json::array();
  std::vector<SpaceJoint> all = f.certificate.joints;
  if (f.certificate.seam) all.push_back(*f.certificate.seam);
  for (const SpaceJoint& jt : all) {
    const std::string continuity = std::string("C").append(std::to_string(jt.continuity));
    joints.push_back({{"index", jt.index}, {"continuity", continuity}, {"g1", jt.g1}, {"g2", jt.g2}});
  }
  certificate["joints"] = joints;
  Json rest = {{"dimension", 3},
               {"require", require},
               {"keep", to_string(request.keep)},
               {"already", f.already},
               {"fixed", f.fixed},
               {"moves", moves},
               {"total_squared", f.total_squared},
               {"max_distance", f.max_distance},
               {"size", f.size},
               {"tolerance", request.tolerance * f.size},
               {"failing_segments", f.failing_segments},
               {"joint_conflicts", f.joint_conflicts},
               {"tie_joints", f.tie_joints},
               {"units", units},
               {"certificate", certificate},
               {"evaluations", f.evaluations},
               {"seconds", f.seconds}};
  if (!file) return rest;
  Json doc = {{"file", *file}};
  for (auto it = rest.begin(); it != rest.end(); ++it) doc[it.key()] = std::move(it.value());
  return doc;
}

nlohmann::ordered_json glyph_fix_json(const import::Glyph& g, const std::vector<ContourFix>& fixes, double grid,
                                      std::vector<import::PointEdit>& edits, std::string& failed) {
  using Json = nlohmann::ordered_json;
  Json contours = Json::array();
  for (const ContourFix& f : fixes) {
    Json moves = Json::array();
    for (std::size_t i = 0; i < f.moves.size(); ++i) {
      const PointMove& m = f.moves[i];
      const int sp = f.source_points[i];
      const bool labelled = f.contour < static_cast<int>(g.point_labels.size()) && sp >= 0 &&
                            sp < static_cast<int>(g.point_labels[f.contour].size()) &&
                            !g.point_labels[f.contour][sp].empty();
      moves.push_back({{"point", f.names[i]},
                       {"from", Json::array({m.from.x, m.from.y})},
                       {"to", Json::array({m.to.x, m.to.y})},
                       {"distance", m.distance}});
      if (labelled) moves.back()["label"] = g.point_labels[f.contour][sp];  // the <point>'s name attribute
      if (sp >= 0) {
        moves.back()["source"] = Json::array({f.contour, sp});  // the .glif's contour and point
        edits.push_back({f.contour, sp, m.to.x, m.to.y});
      }
    }
    Json checks = Json::array();
    for (const GateCount& c : f.rejudged) checks.push_back({{"check", c.check}, {"before", c.before}, {"after", c.after}});
    Json jc = {{"contour", f.contour}, {"already", f.already}, {"fixed", f.fixed}, {"moves", moves}, {"rejudged", checks}};
    if (f.untouched) {
      jc["untouched"] = true;  // no point of it named: left as it is, whether it passes or not
      jc["reason"] = f.reason;
    } else if (!f.fixed) {
      jc["reason"] = f.reason;
      if (failed.empty() && !f.not_searched) failed = g.name + "/c" + std::to_string(f.contour) + ": " + f.reason;
    }
    if (f.off_grid_distance > 0) jc["off_grid_max_distance"] = f.off_grid_distance;
    if (f.fixed && !f.already && grid > 0) jc["settled"] = f.settled;
    if (!f.already) {
      jc["work"] = f.glyph_work;  // the glyph's search in work units, not time: the same on any machine
      if (f.guarded) jc["stopped_by_time"] = true;  // the time guard ended it first: only then may a rerun differ
    }
    contours.push_back(jc);
  }
  return contours;
}

}  // namespace cmr::report
