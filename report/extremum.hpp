#pragma once
/// The |kappa| reading of the report's curvature extrema (sharpest /
/// flattest / inflection: bezierize/extremum_terms.hpp, docs/semantics.md).
#include "bezierize/extremum_terms.hpp"
#include "report/report.hpp"

namespace cmr::report {

/// The kind of extremum `e` of report `r`: inside a segment from the sign of
/// kappa there (exact), on a joint from the signs of kappa on its two sides.
inline ExtremumKind event_kind(const SplineReport& r, const CurveEvent& e) {
  if (e.joint >= 1 && e.joint <= static_cast<int>(r.joints.size())) {
    const Joint& j = r.joints[e.joint - 1].joint;
    if (j.kappa_left == j.kappa_left && j.kappa_right == j.kappa_right)
      return extremum_kind(e.kind, sign_of(j.kappa_left), sign_of(j.kappa_right));
  }
  return extremum_kind(e.kind, sign_of(e.kappa), sign_of(e.kappa));
}

/// "sharpest point", "flattest point", "inflection": what a message calls it.
inline std::string event_noun(ExtremumKind k) {
  return k == ExtremumKind::inflection ? "extremum at an inflection" : std::string(to_string(k)) + " point";
}

}  // namespace cmr::report
