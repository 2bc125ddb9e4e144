#include "report/fix_json.hpp"

#include <string>
#include <utility>
#include <vector>

namespace cmr::report {

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

}  // namespace cmr::report
