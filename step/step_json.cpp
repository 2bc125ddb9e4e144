// The parts of the STEP importer that need no OpenCASCADE (step/step.hpp).
#include "step/step.hpp"

#include <algorithm>

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

StepNesting step_nesting(std::string_view text) {
  StepNesting deepest;
  int depth = 0, line = 1;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
    } else if (c == '\'') {  // a string: '' inside it is a quote, so a scan to the next quote is enough
      const std::size_t end = text.find('\'', i + 1);
      if (end == std::string_view::npos) break;
      line += static_cast<int>(std::count(text.begin() + static_cast<std::ptrdiff_t>(i), text.begin() + static_cast<std::ptrdiff_t>(end), '\n'));
      i = end;
    } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '*') {
      const std::size_t end = text.find("*/", i + 2);
      if (end == std::string_view::npos) break;
      line += static_cast<int>(std::count(text.begin() + static_cast<std::ptrdiff_t>(i), text.begin() + static_cast<std::ptrdiff_t>(end), '\n'));
      i = end + 1;
    } else if (c == '(') {
      if (++depth > deepest.depth) deepest = {depth, line};
    } else if (c == ')') {
      depth = std::max(depth - 1, 0);
    }
  }
  return deepest;
}

std::string skipped_summary(const StepCurves& curves) {
  std::string out;
  for (const auto& [type, n] : curves.skipped) out += (out.empty() ? "" : ", ") + std::to_string(n) + " " + type;
  return out;
}

}  // namespace cmr::import
