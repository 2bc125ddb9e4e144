#include "report/glyph_unfixed.hpp"

#include <vector>

#include "report/batch.hpp"

namespace cmr::report::glyph_detail {

namespace {

/// "O/c0/p3" -> "p3" (the report's node names, report/corpus_inputs.cpp).
std::string node_of(const std::string& name) {
  const std::size_t slash = name.rfind('/');
  return slash == std::string::npos ? name : name.substr(slash + 1);
}

/// A violation's place on `c` as the report names it.
std::string place_of(const import::Contour& c, const GateViolation& v, int segments) {
  const auto& names = c.joint_names;
  const bool named = static_cast<int>(names.size()) == segments && segments > 0;
  if (v.segment >= 0) {
    const bool has_end = v.segment + 1 < segments || c.spline.closed();
    if (named && has_end) return node_of(names[v.segment]) + "-" + node_of(names[(v.segment + 1) % segments]);
    return "segment " + std::to_string(v.segment);
  }
  if (v.joint >= 0) return named ? node_of(names[v.joint % segments]) : "joint " + std::to_string(v.joint);
  return "the contour";
}

}  // namespace

std::string unfixed_reason(const std::string& why, const import::Contour& c, const BSpline& stopped,
                           const ReportOptions& o, int stopped_total, int source_total) {
  std::string out = why.empty() ? "no fix passes every check" : why;
  if (stopped_total <= 0 || stopped_total >= source_total) return out;
  const SplineReport r = gate_report(stopped, o);
  const int segments = stopped.segment_count();
  out += "; where the search stopped, " + std::to_string(stopped_total) + " of the source's " +
         std::to_string(source_total) + (stopped_total == 1 ? " violations is left:" : " violations are left:");
  int shown = 0, hidden = 0;
  std::string sep = " ";
  if (o.require && !r.requirement_pass) {
    out += sep + "the " + to_string(*o.require) + " check";
    sep = "; ";
    ++shown;
  }
  for (const GateResult& g : r.gates) {
    if (g.violations.empty()) continue;
    std::string places;
    for (const GateViolation& v : g.violations) {
      if (shown >= kShownPlaces) {
        ++hidden;
        continue;
      }
      places += (places.empty() ? "" : ", ") + place_of(c, v, segments);
      ++shown;
    }
    if (!places.empty()) out += sep + to_string(g.gate) + " at " + places;
    sep = "; ";
  }
  if (hidden > 0) out += " and " + std::to_string(hidden) + " more";
  return out;
}

}  // namespace cmr::report::glyph_detail
