#include "report/report.hpp"
#include "report/report_detail.hpp"

#include <algorithm>
#include <charconv>
#include <functional>
#include <cmath>
#include <limits>
#include <mutex>
#include <sstream>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "numeric/bernstein.hpp"
#include "bezierize/extract.hpp"
#include "design/fix.hpp"
#include "numeric/fast_roots.hpp"
#include "numeric/tracked.hpp"
#include "bezierize/joint_json.hpp"
#include "bezierize/lambda.hpp"
#include "bezierize/rational_lambda.hpp"
#include "region/region.hpp"
#include "spline/curvature.hpp"
#include "spline/errors.hpp"
#include "spline/parallel.hpp"
#include "spline/spline_json.hpp"
#include "draw/draw.hpp"
#include "draw/svg_text.hpp"
#include "io/output.hpp"
#include "report/extremum.hpp"

// report.json as a tree (report.hpp: report_json, spline_json and the words
// they use). The model is in report.cpp.

namespace cmr::report {

using namespace report_detail;  // what the parts share (report_detail.hpp)

// ---------------------------------------------------------------- JSON

nlohmann::ordered_json gates_json(const SplineReport& r) {
  nlohmann::ordered_json gates = nlohmann::ordered_json::array();
  for (const GateResult& g : r.gates) {
    nlohmann::ordered_json where = nlohmann::ordered_json::array();
    for (const GateViolation& v : g.violations) {
      nlohmann::ordered_json w{{"t", v.t}, {"message", v.message}};
      if (v.segment >= 0) w["segment"] = v.segment, w["local_t"] = v.local_t;
      if (v.joint >= 0) w["joint"] = v.joint;
      where.push_back(w);
    }
    gates.push_back({{"gate", to_string(g.gate)}, {"pass", g.pass()}, {"violations", where}});
  }
  return gates;
}

const char* status_word(const SplineReport& r) { return !r.error.empty() ? "invalid" : (r.pass ? "pass" : "fail"); }

const char* root_kind_word(int sign_before, int sign_after) {
  if (sign_before == sign_after) return "touch";
  return sign_before > 0 ? "maximum" : "minimum";  // lambda + to -: kappa rises, then falls
}

const char* root_at_word(SpanRoot::At at) {
  switch (at) {
    case SpanRoot::At::interior: return "interior";
    case SpanRoot::At::start: return "start";
    case SpanRoot::At::end: return "end";
  }
  return "?";
}

namespace {

using Json = nlohmann::ordered_json;

Json root_json(const SpanRoot& r, bool extremum) {
  Json j{{"t", r.t}, {"enclosure", {r.t_lo, r.t_hi}}, {"exact", r.exact}, {"multiplicity", r.multiplicity}};
  if (extremum) {
    j["kind"] = root_kind_word(r.sign_before, r.sign_after);
    j["kappa"] = r.kappa;
  } else {
    j["kind"] = r.sign_before == r.sign_after ? "touch" : "sign change";
  }
  j["at"] = root_at_word(r.at);
  return j;
}

Json place_json(Json j, const CurveEvent& e) {
  j["on_joint"] = e.joint >= 0;
  j["segment"] = e.segment >= 0 ? Json(e.segment) : Json(nullptr);
  j["joint"] = e.joint >= 0 ? Json(e.joint) : Json(nullptr);
  return j;
}

Json segments_json(const SplineReport& r) {
  Json segments = Json::array();
  for (const SpanReport& sp : r.spans) {
    Json e = Json::array(), i = Json::array();
    for (const SpanRoot& x : sp.extrema) e.push_back(root_json(x, true));
    for (const SpanRoot& x : sp.inflections) i.push_back(root_json(x, false));
    if (!r.analysis.judged(sp.segment.index)) {  // --segments: not judged, its roots still listed
      segments.push_back({{"index", sp.segment.index},
                          {"interval", {sp.segment.a, sp.segment.b}},
                          {"ignored", true},
                          {"curvature", "ignored"},
                          {"inflection", "ignored"},
                          {"lambda_zero", sp.lambda_zero},
                          {"eta_zero", sp.eta_zero},
                          {"extrema", e},
                          {"inflections", i}});
      continue;
    }
    segments.push_back({{"index", sp.segment.index},
                        {"interval", {sp.segment.a, sp.segment.b}},
                        {"class", shape_class(sp.shape)},
                        {"curvature", to_string(sp.classification.monotonicity.curvature)},
                        {"inflection", to_string(sp.shape.inflection)},
                        {"zero_curvature_at", kappa_zero_at(sp.shape)},
                        {"algorithm2", to_string(sp.classification.inflection.inflection)},
                        {"depth", sp.classification.monotonicity.depth},
                        {"inflection_depth", sp.classification.inflection.depth},
                        {"exact", sp.classification.exact_used},
                        {"lambda_zero", sp.lambda_zero},
                        {"eta_zero", sp.eta_zero},
                        {"kappa_spread", std::isfinite(sp.kappa_spread) ? Json(sp.kappa_spread) : Json(nullptr)},
                        {"turning_deviation", std::isfinite(sp.turning_deviation) ? Json(sp.turning_deviation) : Json(nullptr)},
                        {"near_constant", sp.near_constant},
                        {"extrema", e},
                        {"inflections", i}});
    if (sp.shape.pole) segments.back()["poles"] = sp.shape.poles;
  }
  return segments;
}

Json joints_json(const SplineReport& r) {
  Json joints = Json::array();
  for (const JointReport& jr : r.joints) {
    joints.push_back(joint_json(jr.joint, {jr.corner, false, false}));
  }
  return joints;
}

/// The fixes, or null when none were searched (a passing spline, or regions off).
Json fixes_json(const SplineReport& r) {
  if (!r.fixes) return nullptr;
  Json fixes = Json::array();
  for (const Fix& f : *r.fixes) {
    Json fj{{"point", f.point}, {"region_pixels", f.pixels}};
    fj["example"] = f.example ? Json{f.example->x, f.example->y} : Json(nullptr);
    fj["verified"] = f.verified;
    fixes.push_back(fj);
  }
  return fixes;
}

}  // namespace

bool straight_only(const SplineReport& r) {
  if (!r.error.empty() || r.spans.empty()) return false;
  const int last = std::min(r.analysis.range.last, static_cast<int>(r.spans.size()) - 1);
  for (int i = std::max(0, r.analysis.range.first); i <= last; ++i)
    if (!r.spans[static_cast<std::size_t>(i)].eta_zero) return false;
  return true;
}

std::string verdict_label(const SplineReport& r, Direction d) { return straight_only(r) ? "straight" : to_string(d); }

namespace {

Json spline_json(const SplineReport& r, int index) {
  std::string id = "s";  // built with +=: GCC 12 warns falsely (-Wrestrict) on "literal" + string&& here
  id += std::to_string(index);
  Json j{{"id", id}, {"file", r.file}, {"name", r.name}, {"status", status_word(r)}};
  if (!r.error.empty()) {
    j["error"] = r.error;
    return j;
  }
  const BSpline& s = *r.spline;
  j["degree"] = s.degree();
  j["control_points"] = s.unique_point_count();  // a closed spline's distinct points
  j["domain"] = {s.domain_begin(), s.domain_end()};
  Json verdict{{"cmrwi", verdict_label(r, r.analysis.cmrwi)},
               {"cmr", verdict_label(r, r.analysis.cmr)},
               {"cmr_algorithm2", to_string(r.analysis.cmr_algorithm2)}};
  if (r.analysis.split) verdict["split"] = to_string(*r.analysis.split);
  if (r.analysis.range != SegmentRange{0, s.segment_count() - 1})
    verdict["segments"] = {r.analysis.range.first, r.analysis.range.last};
  verdict["joint_conflicts"] = r.analysis.joint_conflicts;
  j["verdict"] = verdict;

  Json extrema = Json::array(), inflections = Json::array();
  for (const CurveEvent& e : r.extrema)
    extrema.push_back(place_json({{"t", e.t},
                                  {"kind", to_string(event_kind(r, e))},              // by |kappa|
                                  {"direction", e.kind > 0 ? "maximum" : "minimum"},  // of signed kappa
                                  {"kappa", e.kappa}},
                                 e));
  for (const CurveEvent& e : r.inflections)
    inflections.push_back(place_json({{"t", e.t}, {"kappa_sign_after", e.kind}}, e));
  // With a cusp there is no finite range: NaN prints as null.
  j["curvature"] = {{"cusp", r.cusp},
                    {"min", {{"kappa", r.kappa_min}, {"t", r.t_min}}},
                    {"max", {{"kappa", r.kappa_max}, {"t", r.t_max}}},
                    {"monotone_pieces", r.monotone_pieces},
                    {"extrema", extrema},
                    {"inflections", inflections}};
  if (r.analysis.pole) j["curvature"]["pole"] = true;  // no finite range either (null)

  j["segments"] = segments_json(r);
  j["joints"] = joints_json(r);
  j["fixes"] = fixes_json(r);
  if (!r.certified_fixes.empty()) {
    j["certified_fixes"] = Json::array();
    for (const CertifiedFix& f : r.certified_fixes) j["certified_fixes"].push_back(certified_fix_json(f));
  }
  if (s.closed()) j["closed"] = true;
  if (!r.gates.empty()) j["gates"] = gates_json(r);
  return j;
}

}  // namespace

nlohmann::ordered_json report_json(const std::vector<SplineReport>& reports, const ReportOptions& options) {
  int pass = 0, fail = 0, invalid = 0;
  Json splines = Json::array();
  for (std::size_t i = 0; i < reports.size(); ++i) {
    const SplineReport& r = reports[i];
    (!r.error.empty() ? invalid : (r.pass ? pass : fail))++;
    splines.push_back(spline_json(r, static_cast<int>(i)));
  }
  Json regions = nullptr;
  if (options.regions)
    regions = {{"size", options.region_size},
               {"backend", options.backend ? options.backend->name() : "none"}};
  return {{"schema", kSchema},
          {"settings",
           {{"check", to_string(check_of(options))},
            {"gate", options.require.has_value() || !options.gates.empty()},
            {"segments", options.segments ? Json{options.segments->first, options.segments->last} : Json(nullptr)},
            {"type_gates", [&] {
               Json g = Json::array();
               for (const Gate& x : options.gates) g.push_back(to_string(x));
               return g;
             }()},
            {"depth", options.max_depth},
            {"root_tolerance", options.roots.tolerance},
            {"constant_tolerance", options.constant_tolerance},
            {"regions", regions}}},
          {"summary",
           {{"splines", reports.size()},
            {"pass", pass},
            {"fail", fail},
            {"invalid", invalid},
            {"exit_code", exit_code(reports, options)}}},
          {"splines", splines}};
}

}  // namespace cmr::report
