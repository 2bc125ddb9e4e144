#include "report/sarif.hpp"

#include <cstdio>

#include <nlohmann/json.hpp>

#include "report/json_stream.hpp"

namespace cmr::report {
namespace {

using Json = nlohmann::ordered_json;

// cmr has no web address: the URN names the page that documents the rules (docs/report.md).
constexpr const char* kInformationUri = "urn:cmr:docs:report.md";
constexpr const char* kInvalidRule = "invalid-input";

struct RuleText {
  std::string name, short_text, full_text, help;
};

RuleText rule_text(const std::string& id) {
  if (id == "curvature-extrema-at-nodes")
    return {"CurvatureExtremaAtNodes", "A curvature extremum lies between nodes.",
            "Every curvature extremum (a certified root of lambda, or a jump of curvature at a joint) must lie on a "
            "node (an on-curve point); one inside a segment is a violation.",
            "Move the segment's points until the curvature along the segment is monotone, or add a node at the "
            "extremum. The page shows the smallest certified fix (cmr fix): the points to move, by how much, and the "
            "fixed outline."};
  if (id == "curvature-extrema-at-nodes:runs")
    return {"UnimodalRuns", "The curvature of a run between on-curve points is not unimodal.",
            "TrueType reading of curvature-extrema-at-nodes: each quadratic piece peaks once by construction, so the gate judges "
            "each run between explicit on-curve points (implied midpoints are not nodes): |curvature| must rise to at "
            "most one peak and fall (split at inflections). Each dip between two peaks is a violation.",
            "Move the named off-curve points (the handles of the segments meeting at the dip) so that the run's "
            "curvature has a single peak, or put an on-curve point at the dip."};
  if (id.rfind("max-extrema-per-segment", 0) == 0)
    return {"MaxExtremaPerSegment", "Too many curvature extrema inside one segment.",
            "At most N curvature extrema may lie strictly inside any one segment.",
            "Move the segment's handles so that its curvature has fewer turning points, or split the segment."};
  if (id.rfind("g2-at-smooth-nodes", 0) == 0)
    return {"G2AtSmoothNodes", "Curvature jumps at a smooth node.",
            "At every smooth node (C1, or G1 by exact tangents) the curvature on both sides must agree within the "
            "relative tolerance.",
            "Move the handles on both sides of the node along the tangent until the curvatures match."};
  if (id.rfind("g3-at-smooth-nodes", 0) == 0)
    return {"G3AtSmoothNodes", "Curvature or its slope jumps at a smooth node.",
            "At every smooth node the curvature, its arc-length derivative dkappa/ds and, on a space curve, the "
            "torsion on both sides must agree within the relative tolerance.",
            "Move the handles next to the node (the third points from it on both sides) until the slopes match."};
  if (id.rfind("xy-extrema-at-nodes", 0) == 0)
    return {"XyExtremaAtNodes", "An x or y extremum lies between nodes.",
            "Every horizontal and vertical tangent of the outline (a certified sign change of x' or y', where the "
            "outline turns back in x or y) must lie on a node (an on-curve point); one inside a segment, or on an "
            "implied on-curve point, is a violation. Extrema that poke out by less than the tolerance (default one "
            "font unit) past the nearer node are tolerated.",
            "Add a node at the point the message gives (split the segment there: the curve stays the same), or move "
            "the handles onto the axis so that the tangent at an existing node is horizontal or vertical. cmr names "
            "the point and does not insert it."};
  if (id.rfind("g1-between-masters", 0) == 0)
    return {"G1BetweenMasters", "A smooth node is a kink between the masters.",
            "A node smooth at both masters (smooth=\"yes\" and collinear, exactly) must stay G1 at every location "
            "between them: the cross product of its tangents, a polynomial of degree 2 in the axis, must vanish "
            "identically. It does not when the handles' lengths change in different ratios. With :DEG, a node whose "
            "tangents turn by at most DEG degrees at both masters must turn by at most DEG at every location.",
            "Make the two handles' lengths change in the same ratio from master to master (the message gives the "
            "worst location and angle)."};
  if (id == "curvature-between-masters" || id == "extrema-between-masters")
    return {id == "curvature-between-masters" ? "CurvatureBetweenMasters" : "ExtremaBetweenMasters",
            "The curvature of a segment is monotone at both masters but not between them.",
            "Every segment whose curvature is monotone at both masters must stay monotone at every location "
            "between them (a certificate in the segment's parameter and the axis); extrema-between-masters also "
            "asks a node that is a curvature extremum at both masters to stay one.",
            "Move the segment's handles in one master so that the instances between keep a monotone curvature; "
            "the message gives the first failing location and the instance's extremum."};
  if (id == "no-inflection")
    return {"NoInflection", "The curvature changes sign.", "The curve must not have an inflection.",
            "Move the handles so that the curve turns one way only, or split the contour at the inflection."};
  if (id == kInvalidRule)
    return {"InvalidInput", "The input could not be read.", "A file or spline that cannot be read is reported here.",
            "Fix the file named in the message; cmr reports every other file regardless."};
  return {"CurvatureMonotone", "The curvature is not monotone (" + id + ").",
          "The spline must pass the " + id +
              " check of CAD&A 2024 (Algorithms 1 and 2): its curvature monotone over the judged segments.",
          "The HTML report shows, per control point, the region where moving it alone makes the spline pass."};
}

Json location(const std::string& uri, bool relative, Json logical_locations) {
  Json artifact = {{"uri", uri}};
  if (relative) artifact["uriBaseId"] = kSarifRootId;
  return Json::array({Json{{"physicalLocation", {{"artifactLocation", artifact}}}, {"logicalLocations", logical_locations}}});
}

// The index of `id` in sarif_rule_ids(options), without building the list.
int rule_index(const std::string& id, const ReportOptions& options) {
  int i = 0;
  if (options.require) {
    if (to_string(*options.require) == id) return i;
    ++i;
  }
  for (const Gate& g : options.gates) {
    if (to_string(g) == id) return i;
    ++i;
  }
  return id == kInvalidRule ? i : -1;
}

}  // namespace

std::string path_uri(const std::string& path) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out = path.size() > 0 && path[0] == '/' ? "file://" : "";
  for (const unsigned char c : path) {
    if ((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '.' ||
        c == '_' || c == '~' || c == '/')
      out += static_cast<char>(c);
    else
      out += {'%', kHex[c >> 4], kHex[c & 15]};
  }
  return out;
}

std::vector<std::string> sarif_rule_ids(const ReportOptions& options) {
  std::vector<std::string> ids;
  if (options.require) ids.push_back(to_string(*options.require));
  for (const Gate& g : options.gates) ids.push_back(to_string(g));
  ids.push_back(kInvalidRule);
  return ids;
}

std::string sarif_header(const ReportOptions& options, const std::string& root_uri) {
  Json rules = Json::array();
  for (const std::string& id : sarif_rule_ids(options)) {
    const RuleText t = rule_text(id);
    rules.push_back({{"id", id},
                     {"name", t.name},
                     {"shortDescription", {{"text", t.short_text}}},
                     {"fullDescription", {{"text", t.full_text}}},
                     {"help", {{"text", t.help}}},
                     {"helpUri", kInformationUri},
                     {"defaultConfiguration", {{"level", "error"}}}});
  }
  const Json driver = {{"name", "cmr"},
                       {"informationUri", kInformationUri},
                       {"semanticVersion", "1.0.0"},
                       {"rules", rules}};
  // The document up to "results": [ — written as text, closed by sarif_footer.
  std::string head = "{\"$schema\":\"https://json.schemastore.org/sarif-2.1.0.json\",\"version\":\"2.1.0\",\"runs\":[{"
                     "\"tool\":{\"driver\":" +
                     driver.dump() + "},\"originalUriBaseIds\":" +
                     Json{{kSarifRootId, {{"uri", root_uri}}}}.dump() +
                     ",\"columnKind\":\"unicodeCodePoints\",\"results\":[";
  return head;
}

std::string sarif_result(const Finding& f, const std::string& uri, bool relative, const ReportOptions& options,
                         const char* baseline_state) {
  // Streamed (report/json_stream.hpp: the bytes nlohmann's dump gives): a
  // corpus has hundreds of thousands of results.
  std::string fq = f.glyph;
  if (!f.node.empty()) fq += "/c" + std::to_string(f.contour) + "/" + f.node;
  std::string out;
  JsonStream o(out, -1);
  o.begin_object();
  o.member("ruleId", f.gate);
  o.member("ruleIndex", rule_index(f.gate, options));
  o.member("level", f.info ? "note" : "error");  // info: below --min-severity, it does not fail
  o.key("message");
  o.begin_object();
  o.member("text", f.message);
  o.end_object();
  o.key("locations");
  o.begin_array();
  o.begin_object();
  o.key("physicalLocation");
  o.begin_object();
  o.key("artifactLocation");
  o.begin_object();
  o.member("uri", uri);
  if (relative) o.member("uriBaseId", kSarifRootId);
  o.end_object();
  if (f.line > 0) {  // a font source: the <point>'s line, where code scanning places the alert
    o.key("region");
    o.begin_object();
    o.member("startLine", f.line);
    o.end_object();
  }
  o.end_object();
  o.key("logicalLocations");
  o.begin_array();
  o.begin_object();
  o.member("name", f.node.empty() ? f.glyph : f.node);
  o.member("fullyQualifiedName", fq);
  o.member("kind", "element");
  o.end_object();
  o.end_array();
  o.end_object();
  o.end_array();
  o.key("partialFingerprints");
  o.begin_object();
  o.member("cmrFinding/v1", f.key());
  o.end_object();
  o.key("properties");
  o.begin_object();
  o.member("glyph", f.glyph);
  o.member("contour", f.contour);
  o.member("node", f.node);
  o.end_object();
  if (baseline_state) o.member("baselineState", baseline_state);
  o.end_object();
  return out;
}

std::string sarif_invalid(const std::string& uri, bool relative, const std::string& name, const std::string& error,
                          const ReportOptions& options) {
  Json r = {{"ruleId", kInvalidRule},
            {"ruleIndex", rule_index(kInvalidRule, options)},
            {"level", "error"},
            {"message", {{"text", error}}},
            {"locations", location(uri, relative, Json::array({Json{{"name", name}, {"kind", "element"}}}))}};
  return r.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string sarif_footer() { return "]}]}\n"; }

}  // namespace cmr::report
