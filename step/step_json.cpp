// The parts of the STEP importer that need no OpenCASCADE (step/step.hpp).
#include "step/step.hpp"

namespace cmr::import {

nlohmann::ordered_json step_curve_json(const StepCurve& c) {
  nlohmann::ordered_json doc;
  doc["name"] = c.name;
  doc["degree"] = c.degree;
  if (c.closed) doc["closed"] = true;
  doc["knots"] = c.knots;
  nlohmann::ordered_json pts = nlohmann::ordered_json::array();
  for (const glm::dvec3& p : c.points) pts.push_back({p.x, p.y, p.z});
  doc["points"] = std::move(pts);
  if (!c.weights.empty()) doc["weights"] = c.weights;
  return doc;
}

std::string skipped_summary(const StepCurves& curves) {
  std::string out;
  for (const auto& [type, n] : curves.skipped) out += (out.empty() ? "" : ", ") + std::to_string(n) + " " + type;
  return out;
}

}  // namespace cmr::import
