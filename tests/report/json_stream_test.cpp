// report.json streamed as text (report/json_stream.hpp) against the tree it
// replaced: the same bytes for seeded random splines and font contours, with
// and without the batch writer's additions, compact and indented; the
// streamed report.json of a font run read back with nlohmann and checked
// field by field against docs/report-schema.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>

#include <nlohmann/json.hpp>

#include "io/font.hpp"
#include "report/batch.hpp"
#include "report/json_stream.hpp"
#include "report/sarif.hpp"
#include "spline/errors.hpp"
#include "tests/cli_util.hpp"

namespace cmr::report {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

const char* kDejaVu = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

std::string dumped(const Json& j, int indent) {
  return j.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string streamed(const SplineReport& r, int index, const SplineJsonExtras& x, int indent) {
  std::string text;
  JsonStream s(text, indent);
  write_spline_json(s, r, index, x);
  return text;
}

// The first byte where two texts differ, with some context.
::testing::AssertionResult same_text(const std::string& tree, const std::string& stream) {
  if (tree == stream) return ::testing::AssertionSuccess();
  std::size_t i = 0;
  while (i < tree.size() && i < stream.size() && tree[i] == stream[i]) ++i;
  const std::size_t from = i < 60 ? 0 : i - 60;
  return ::testing::AssertionFailure() << "differ at byte " << i << "\n tree:   " << tree.substr(from, 120)
                                       << "\n stream: " << stream.substr(from, 120);
}

void expect_same(const SplineReport& r, int index, const std::string& ctx) {
  // Findings with text that nlohmann must escape: quotes, a backslash, a
  // control character, UTF-8 and an invalid byte (replaced by U+FFFD).
  const std::vector<Finding> findings = {
      {"a \"font\".ttf", "O", 1, "p3", "curvature-extrema-at-nodes", "move p3 \\ left\tby 2 \xc3\xa9 \xff", "", 0},
      {"f.ttf", "o", 0, "", "cmr", "plain", "", 0}};
  const std::string source = "fonts/Dé \"x\".ttf";
  SplineJsonExtras batch;
  batch.source = &source;
  batch.glyph = "O";
  batch.contour = 2;
  batch.findings = &findings;
  for (const int indent : {-1, 2, 4}) {
    EXPECT_TRUE(same_text(dumped(spline_json_tree(r, index), indent), streamed(r, index, {}, indent)))
        << ctx << ", indent " << indent;
    EXPECT_TRUE(same_text(dumped(spline_json_tree(r, index, batch), indent), streamed(r, index, batch, indent)))
        << ctx << " with the batch fields, indent " << indent;
  }
}

ReportOptions type_gates(bool loose = false) {
  ReportOptions o;
  o.regions = false;
  parse_require_list("curvature-extrema-at-nodes:runs,curvature-extrema-at-nodes,g2-at-smooth-nodes,no-inflection", o);
  if (loose) {  // wide G1/G2 tolerances: joints where "jump" (none at G2) and "exact_jump" differ
    o.continuity.angle_deg = 10;
    o.continuity.curvature_rel = 0.9;
  }
  return o;
}

// As tests/report/fast_path_test.cpp: integer, half-integer and random
// coordinates, straight runs, repeated points (cusps), repeated knots.
BSpline random_spline(std::mt19937_64& rng, int trial) {
  std::uniform_int_distribution<int> degree_of(2, 5), small(-40, 40), pick(0, 9);
  std::uniform_real_distribution<double> real(-10, 10);
  const int d = degree_of(rng);
  const int m = d + 1 + static_cast<int>(rng() % 8);
  const bool integer = trial % 2 == 0;
  std::vector<Vec2> P;
  for (int i = 0; i < m; ++i) {
    Vec2 p = integer ? Vec2(small(rng), small(rng)) * (trial % 4 == 0 ? 0.5 : 1.0) : Vec2(real(rng), real(rng));
    const int k = pick(rng);
    if (i >= 2 && k == 0) p = P[i - 1] + (P[i - 1] - P[i - 2]);
    if (i >= 1 && k == 1) p = P[i - 1];
    P.push_back(p);
  }
  std::vector<double> knots(d, 0.0);
  int interior = m - d - 1;
  double u = 0;
  while (interior > 0) {
    u += integer ? 1.0 : 0.5 + (rng() % 5) * 0.25;
    const int mult = std::min(interior, 1 + static_cast<int>(rng() % d));
    for (int k = 0; k < mult; ++k) knots.push_back(u);
    interior -= mult;
  }
  u += 1;
  for (int k = 0; k < d; ++k) knots.push_back(u);
  return BSpline::make(d, knots, P, "random " + std::to_string(trial));
}

TEST(JsonStream, WritesWhatNlohmannDumps) {
  Json tree = Json::object();
  tree["d"] = Json::array({0.1, 1.0, -0.0, 1e300, 5e-324, -2.5e-7, 123456789.125, std::nan(""),
                           std::numeric_limits<double>::infinity()});
  tree["i"] = Json::array({0, -1, std::numeric_limits<std::int64_t>::min(), std::numeric_limits<std::uint64_t>::max()});
  tree["s"] = Json::array({"", "plain", "q\"b\\n\n\x01", "\xc3\xa9", "bad \xff byte"});
  tree["empty"] = Json::object();
  tree["none"] = Json::array();
  tree["nested"] = {{"a", Json::array({Json::object(), Json::array({true, false, nullptr})})}};
  for (const int indent : {-1, 0, 2}) {
    std::string text;
    JsonStream s(text, indent);
    s.value(tree);
    EXPECT_TRUE(same_text(dumped(tree, indent), text)) << "indent " << indent;
  }
}

TEST(JsonStream, SeededRandomSplinesStreamTheTreesBytes) {
  std::mt19937_64 rng(2024);
  int reported = 0, differing_jumps = 0;
  for (int trial = 0; trial < 120; ++trial) {
    const ReportOptions options = type_gates(trial % 2 == 1);
    BSpline s = [&] {
      for (;;) {
        try {
          return random_spline(rng, trial);
        } catch (const std::exception&) {  // a draw that is not a valid spline: draw again
        }
      }
    }();
    SplineReport r;
    try {
      r = judged_report(s, options);
    } catch (const InputError& e) {
      r.file = "random";
      r.name = s.name();
      r.error = e.what();  // an invalid item: its short object
    }
    expect_same(r, trial, s.name());
    if (::testing::Test::HasFailure()) return;
    ++reported;
    for (const JointReport& j : r.joints) differing_jumps += shown_jump(j.joint) != j.joint.jump;
  }
  EXPECT_EQ(reported, 120);
  EXPECT_GT(differing_jumps, 0);  // the draws reach joints where the two jump fields differ
}

TEST(JsonStream, FontContoursStreamTheTreesBytes) {
  if (!fs::exists(kDejaVu)) GTEST_SKIP() << kDejaVu << " is not installed";
  const import::Font font = import::read_font(kDejaVu, import::parse_glyph_spec("O,o,H,S,e,a,g,&,@,i"));
  const ReportOptions options = type_gates();
  int contours = 0;
  for (const import::Glyph& g : font.glyphs)
    for (const import::Contour& c : g.contours) {
      expect_same(judged_report(c.spline, options), contours, c.spline.name());  // closed contours
      if (::testing::Test::HasFailure()) return;
      ++contours;
    }
  EXPECT_GT(contours, 10);
}

// docs/report-schema.md, field by field, on the streamed report.json.
void check_spline_schema(const Json& s, const std::string& ctx) {
  for (const char* k : {"id", "file", "name", "status", "source", "glyph"})
    ASSERT_TRUE(s.contains(k) && s[k].is_string()) << ctx << ": " << k;
  ASSERT_TRUE(s["contour"].is_number_integer()) << ctx;
  const std::string status = s["status"];
  if (status == "invalid") {
    EXPECT_TRUE(s["error"].is_string()) << ctx;
    return;
  }
  EXPECT_TRUE(status == "pass" || status == "fail") << ctx << ": " << status;
  EXPECT_TRUE(s["degree"].is_number_integer()) << ctx;
  EXPECT_TRUE(s["control_points"].is_number_integer()) << ctx;
  ASSERT_TRUE(s["domain"].is_array() && s["domain"].size() == 2) << ctx;
  const Json& v = s["verdict"];
  for (const char* k : {"cmrwi", "cmr", "cmr_algorithm2"}) EXPECT_TRUE(v[k].is_string()) << ctx << ": verdict." << k;
  EXPECT_TRUE(v["joint_conflicts"].is_array()) << ctx;
  const Json& c = s["curvature"];
  EXPECT_TRUE(c["cusp"].is_boolean()) << ctx;
  for (const char* k : {"min", "max"})
    for (const char* f : {"kappa", "t"})
      EXPECT_TRUE(c[k][f].is_number() || (c["cusp"] == true && c[k][f].is_null())) << ctx << ": " << k << "." << f;
  EXPECT_EQ(c["monotone_pieces"], c["extrema"].size() + 1) << ctx;
  for (const Json& e : c["extrema"]) {
    EXPECT_TRUE(e["t"].is_number() && e["kappa"].is_number()) << ctx;
    EXPECT_TRUE(e["kind"] == "sharpest" || e["kind"] == "flattest" || e["kind"] == "inflection") << ctx << ": " << e["kind"];
    EXPECT_TRUE(e["direction"] == "maximum" || e["direction"] == "minimum") << ctx;
    EXPECT_EQ(e["on_joint"].get<bool>(), e["joint"].is_number_integer()) << ctx;
    EXPECT_NE(e["segment"].is_null(), e["joint"].is_null()) << ctx;
  }
  for (const Json& e : c["inflections"]) {
    EXPECT_TRUE(e["kappa_sign_after"] == 1 || e["kappa_sign_after"] == -1) << ctx;
    EXPECT_TRUE(e["on_joint"].is_boolean()) << ctx;
  }
  ASSERT_TRUE(s["segments"].is_array() && !s["segments"].empty()) << ctx;
  for (const Json& g : s["segments"]) {
    EXPECT_TRUE(g["index"].is_number_integer()) << ctx;
    EXPECT_TRUE(g["interval"].is_array() && g["interval"].size() == 2) << ctx;
    EXPECT_TRUE(g["class"] == "regular" || g["class"] == "straight" || g["class"] == "cusp") << ctx;
    for (const char* k : {"curvature", "inflection", "zero_curvature_at", "algorithm2"})
      EXPECT_TRUE(g[k].is_string()) << ctx << ": segment." << k;
    for (const char* k : {"depth", "inflection_depth"}) EXPECT_TRUE(g[k].is_number_integer()) << ctx;
    for (const char* k : {"exact", "lambda_zero", "eta_zero", "near_constant"}) EXPECT_TRUE(g[k].is_boolean()) << ctx;
    EXPECT_TRUE(g["kappa_spread"].is_number() || g["kappa_spread"].is_null()) << ctx;
    for (const char* k : {"extrema", "inflections"})
      for (const Json& root : g[k]) {
        EXPECT_TRUE(root["t"].is_number()) << ctx;
        ASSERT_TRUE(root["enclosure"].is_array() && root["enclosure"].size() == 2) << ctx;
        EXPECT_LE(root["enclosure"][0].get<double>(), root["t"].get<double>()) << ctx;
        EXPECT_LE(root["t"].get<double>(), root["enclosure"][1].get<double>()) << ctx;
        EXPECT_TRUE(root["exact"].is_boolean() && root["multiplicity"].is_number_integer()) << ctx;
        EXPECT_TRUE(root["at"] == "interior" || root["at"] == "start" || root["at"] == "end") << ctx;
        EXPECT_EQ(root.contains("kappa"), std::string(k) == "extrema") << ctx;
      }
  }
  for (const Json& j : s["joints"]) {
    for (const char* k : {"index", "multiplicity"}) EXPECT_TRUE(j[k].is_number_integer()) << ctx;
    EXPECT_TRUE(j["knot"].is_number()) << ctx;
    EXPECT_EQ(j["continuity"].get<std::string>().rfind('C', 0), 0u) << ctx;
    for (const char* k : {"g1", "g2", "zero_tangent", "corner"}) EXPECT_TRUE(j[k].is_boolean()) << ctx;
    EXPECT_EQ(j["corner"], !j["g1"].get<bool>()) << ctx;
    for (const char* k : {"jump", "exact_jump"})
      EXPECT_TRUE(j[k] == "up" || j[k] == "down" || j[k] == "none") << ctx;
  }
  EXPECT_TRUE(s["fixes"].is_null()) << ctx;  // --no-thumbnails: regions off
  EXPECT_EQ(s["closed"], true) << ctx;       // font contours are closed
  ASSERT_TRUE(s["gates"].is_array() && s["gates"].size() == 2) << ctx;
  for (const Json& g : s["gates"]) {
    EXPECT_TRUE(g["gate"].is_string() && g["pass"].is_boolean()) << ctx;
    // A font's findings have their severity by default: a gate passes when
    // each of its violations is an `info` finding (a move under half a unit).
    int errors = 0, findings = 0;
    for (const Json& f : s["findings"])
      if (f["gate"] == g["gate"]) ++findings, errors += f["level"] == "error" ? 1 : 0;
    EXPECT_EQ(findings, static_cast<int>(g["violations"].size())) << ctx;
    EXPECT_EQ(g["pass"].get<bool>(), errors == 0) << ctx;
    for (const Json& w : g["violations"]) {
      EXPECT_TRUE(w["t"].is_number() && w["message"].is_string()) << ctx;
      EXPECT_TRUE(w.contains("segment") == w.contains("local_t")) << ctx;
      EXPECT_TRUE(w.contains("segment") || w.contains("joint")) << ctx;
    }
  }
  ASSERT_TRUE(s["findings"].is_array()) << ctx;
  for (const Json& f : s["findings"])
    for (const char* k : {"gate", "node", "message", "key"}) EXPECT_TRUE(f[k].is_string()) << ctx;
}

TEST(JsonStream, StreamedReportJsonOfAFontFollowsTheSchema) {
  if (!fs::exists(kDejaVu)) GTEST_SKIP() << kDejaVu << " is not installed";
  const fs::path out = test::scratch() / "json_stream";
  fs::remove_all(out);
  for (const char* pretty : {"", " --pretty"}) {
    const test::Outcome r = test::run(std::string("report ") + kDejaVu +
                                      " --glyphs U+0041-U+007A --require curvature-extrema-at-nodes,g2-at-smooth-nodes"
                                      " --no-thumbnails --quiet --out " + out.string() + pretty);
    ASSERT_EQ(r.code, 1) << r.err;  // DejaVu Sans fails curvature-extrema-at-nodes
    const Json doc = Json::parse(test::slurp(out / "report.json"));  // throws on malformed text
    EXPECT_EQ(doc["schema"], "cmr-report/2");
    EXPECT_EQ(doc["settings"]["type_gates"], Json::array({"curvature-extrema-at-nodes", "g2-at-smooth-nodes:0.05"}));
    const Json& splines = doc["splines"];
    ASSERT_GT(splines.size(), 60u);
    int fail = 0, findings = 0;
    for (std::size_t i = 0; i < splines.size(); ++i) {
      const Json& s = splines[i];
      EXPECT_EQ(s["id"], "s" + std::to_string(i));
      check_spline_schema(s, s.value("glyph", "?") + " contour " + std::to_string(s.value("contour", -1)) + pretty);
      if (::testing::Test::HasFatalFailure()) return;
      fail += s["status"] == "fail";
      findings += static_cast<int>(s["findings"].size());
    }
    EXPECT_EQ(doc["summary"]["splines"], splines.size());
    EXPECT_EQ(doc["summary"]["fail"], fail);
    EXPECT_EQ(doc["summary"]["findings"], findings);
  }
}


// sarif_result is streamed too: the same bytes as the tree SARIF's result
// object was built as (ruleId ... properties, then baselineState when given),
// for plain names and for quotes, backslashes, control characters, non-ASCII
// UTF-8 and an invalid byte in the file, glyph, node and message.
TEST(JsonStream, SarifResultsStreamTheTreesBytes) {
  ReportOptions options;
  options.require = parse_requirement("cmr");
  options.gates = {*parse_gate("curvature-extrema-at-nodes"), *parse_gate("g2-at-smooth-nodes:0.05")};
  const std::vector<std::string> ids = sarif_rule_ids(options);
  auto tree = [&](const Finding& f, const char* state) {
    std::string fq = f.glyph;
    if (!f.node.empty()) fq += "/c" + std::to_string(f.contour) + "/" + f.node;
    const int index = static_cast<int>(std::find(ids.begin(), ids.end(), f.gate) - ids.begin());
    Json logical = Json::array({Json{{"name", f.node.empty() ? f.glyph : f.node}, {"fullyQualifiedName", fq}, {"kind", "element"}}});
    Json artifact = {{"uri", path_uri(f.source.empty() ? f.file : f.source)}};
    if ((f.source.empty() ? f.file : f.source)[0] != '/') artifact["uriBaseId"] = "SRCROOT";
    Json physical = {{"artifactLocation", artifact}};
    if (f.line > 0) physical["region"] = {{"startLine", f.line}};
    Json r = {{"ruleId", f.gate},
              {"ruleIndex", index < static_cast<int>(ids.size()) ? index : -1},
              {"level", "error"},
              {"message", {{"text", f.message}}},
              {"locations", Json::array({Json{{"physicalLocation", physical}, {"logicalLocations", logical}}})},
              {"partialFingerprints", {{"cmrFinding/v1", f.key()}}},
              {"properties", {{"glyph", f.glyph}, {"contour", f.contour}, {"node", f.node}}}};
    if (state) r["baselineState"] = state;
    return dumped(r, -1);
  };
  const std::vector<Finding> findings = {
      {"/fonts/Sans.ttf", "O", 0, "p3-p4", "curvature-extrema-at-nodes", "O/c0 between nodes p3-p4: sharpest point inside", "", 0},
      {"fonts/Some Font (1).otf", "quote\"back\\slash", 2, "", "cmr", "fails the cmr check\n(verdict none)\t", "", 0},
      {"/f/\xc3\xa9t\xc3\xa9.ttf", "uni00E9", 1, "n\xe2\x80\x93" "2", "g2-at-smooth-nodes:0.05", "\xce\xba jumps \x01", "", 0},
      {"/f/bad\xff.ttf", "bad\xfe", 3, "p1", "unknown-gate", "invalid \xc3 byte", "", 0},
      // a font source: the .glif and the <point>'s line (region.startLine)
      {"Sans.ufo", "O", 1, "p4", "g2-at-smooth-nodes:0.05", "O/c1 at p4: jump", "Sans.ufo/glyphs/O_.glif", 17},
  };
  for (const Finding& f : findings)
    for (const char* state : {static_cast<const char*>(nullptr), "new", "unchanged"}) {
      const std::string& where = f.source.empty() ? f.file : f.source;  // a source finding: its .glif
      const std::string text = sarif_result(f, path_uri(where), where[0] != '/', options, state);
      EXPECT_EQ(text, tree(f, state)) << f.glyph << " " << (state ? state : "-");
      EXPECT_TRUE(Json::parse(text).is_object()) << f.glyph;
    }
}

}  // namespace
}  // namespace cmr::report
