#pragma once
// Internal to cmr::report: what the report model (report.cpp), its JSON
// (report_json.cpp) and its HTML (report_html.cpp) share.
#include <vector>

#include <glm/vec3.hpp>

#include "report/report.hpp"

namespace cmr::report::report_detail {

// Point, tangent and curvature of a Bezier segment at u (de Casteljau down to
// three points, whose differences give the first two derivatives).
struct Frame {
  Vec2 point{0.0}, tangent{0.0};
  double kappa = 0;
  double weight = 1;  ///< W(u) of a rational segment (its sign tells the sides of a pole apart)
  bool drawn = true;  ///< drawable (CurveSampler::inside): false near a pole, where the curve runs off
};

Frame frame_at(const std::vector<Vec2>& B, double u);

// Defined in report.cpp:
Frame frame_at(const std::vector<Vec2>& B, const std::vector<glm::dvec3>& H, double u);

}  // namespace cmr::report::report_detail
