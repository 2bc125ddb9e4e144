// xy-extrema-at-nodes (report/xy_extrema.hpp): exact references from
// gen_xy_extrema_reference.py (rational arithmetic, independent of the C++),
// the tolerance, the gate's text, real glyphs of DejaVu Sans and Nimbus Sans
// (their O has its extrema on nodes; rotated, it has four extrema inside
// segments per contour, where dense sampling puts them), and the command's
// JSON and SARIF.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>

#include <nlohmann/json.hpp>

#include "io/font.hpp"
#include "report/batch.hpp"
#include "report/report.hpp"
#include "report/xy_extrema.hpp"
#include "spline/errors.hpp"
#include "tests/cli_util.hpp"
#include "tests/report/xy_extrema_reference.hpp"

namespace cmr::report {
namespace {

const char* kDejaVu = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
const char* kNimbus = "/usr/share/fonts/opentype/urw-base35/NimbusSans-Regular.otf";

ReportOptions gates(const std::string& require) {
  ReportOptions o;
  o.regions = false;
  parse_require_list(require, o);
  return o;
}

BSpline bezier_of(const std::vector<std::pair<double, double>>& pts, const std::string& name) {
  std::vector<Vec2> p;
  for (const auto& [x, y] : pts) p.push_back({x, y});
  return BSpline::bezier(p, name);
}

// Every reference piece: the same extrema (axis, kind), t to the roots'
// enclosure width and the point to rounding.
TEST(XyExtrema, MatchExactReferencesOfCubicAndQuadraticPieces) {
  for (const reference::XyPieceReference& ref : reference::xy_extrema_references()) {
    const BSpline s = bezier_of(ref.points, ref.name);
    const SplineReport r = judged_report(s, gates("xy-extrema-at-nodes:0"));
    const std::vector<XyExtremum> got = xy_extrema(r);
    ASSERT_EQ(got.size(), ref.extrema.size()) << ref.name;
    for (std::size_t k = 0; k < got.size(); ++k) {
      const reference::XyExtremumReference& want = ref.extrema[k];
      EXPECT_EQ(got[k].axis, want.axis) << ref.name << " extremum " << k;
      EXPECT_EQ(got[k].kind, want.kind) << ref.name << " extremum " << k;
      EXPECT_NEAR(got[k].local_t, want.t, 2e-12) << ref.name << " extremum " << k;
      EXPECT_LE(got[k].local_lo, want.t) << ref.name << " extremum " << k;
      EXPECT_GE(got[k].local_hi, want.t) << ref.name << " extremum " << k;
      EXPECT_NEAR(got[k].point.x, want.x, 1e-8) << ref.name << " extremum " << k;
      EXPECT_NEAR(got[k].point.y, want.y, 1e-8) << ref.name << " extremum " << k;
      EXPECT_EQ(got[k].segment, 0) << ref.name;
    }
    // The gate at :0 reports each, and its message says where to add the node.
    ASSERT_EQ(r.gates.size(), 1u);
    EXPECT_EQ(r.gates[0].violations.size(), ref.extrema.size()) << ref.name;
    for (const GateViolation& v : r.gates[0].violations) {
      EXPECT_EQ(v.segment, 0) << v.message;
      EXPECT_NE(v.message.find("add a node at ("), std::string::npos) << v.message;
    }
  }
}

// The derivative's Bernstein form: n (P_{k+1} - P_k) for a polynomial piece,
// and for a rational one the numerator X'W - XW' of degree 2n-1 whose sign
// is that of x' (checked against finite differences of the curve).
TEST(XyExtrema, DerivativeFormsAgreeWithTheCurve) {
  const BSpline cubic = BSpline::bezier({{0, 0}, {100, 300}, {400, 300}, {500, 0}}, "arc");
  const Bernstein<Rational> dy = xy_derivative(cubic, 0, 1);
  ASSERT_EQ(dy.size(), 3u);
  EXPECT_EQ(dy[0], 900);
  EXPECT_EQ(dy[1], 0);
  EXPECT_EQ(dy[2], -900);
  const BSpline rational = BSpline::bezier({{0, 0}, {100, 300}, {400, 300}, {500, 0}}, "rational arc", {1, 2, 0.5, 1});
  for (int axis = 0; axis < 2; ++axis) {
    const Bernstein<Rational> p = xy_derivative(rational, 0, axis);
    ASSERT_EQ(p.size(), 6u);  // degree 2n-1
    for (int q = 1; q < 20; ++q) {
      const double u = q / 20.0, h = 1e-6;
      const Vec2 a = evaluate(rational, u - h), b = evaluate(rational, u + h);
      const double fd = axis == 0 ? b.x - a.x : b.y - a.y;
      const double exact = bernstein_eval(p, Rational(u)).get_d();
      if (std::abs(fd) > 1e-6) {
        EXPECT_EQ(fd > 0, exact > 0) << "axis " << axis << " u " << u;
      }
    }
  }
  // Its extremum (the rational arc's top) is where y' changes sign.
  const SplineReport r = judged_report(rational, gates("xy-extrema-at-nodes:0"));
  const std::vector<XyExtremum> e = xy_extrema(r);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].axis, 1);
  EXPECT_EQ(e[0].kind, 1);
  const Vec2 left = evaluate(rational, e[0].local_t - 1e-4), right = evaluate(rational, e[0].local_t + 1e-4);
  EXPECT_GE(e[0].point.y, left.y);
  EXPECT_GE(e[0].point.y, right.y);
}

// A handle one unit off the axis puts a y minimum a hair after its node,
// 0.0037 units below it: tolerated by default (one font unit), reported at
// :0, and the threshold is the overshoot itself.
TEST(XyExtrema, ToleratesExtremaThatTheIntegerGridCannotAvoid) {
  const BSpline s = BSpline::bezier({{0, 0}, {100, -1}, {400, 200}, {500, 500}}, "one unit off");
  const SplineReport r = judged_report(s, gates("xy-extrema-at-nodes,xy-extrema-at-nodes:0"));
  ASSERT_EQ(r.gates.size(), 2u);
  EXPECT_TRUE(r.gates[0].pass()) << r.gates[0].violations.front().message;
  ASSERT_EQ(r.gates[1].violations.size(), 1u);
  EXPECT_NE(r.gates[1].violations[0].message.find("y minimum (horizontal tangent)"), std::string::npos)
      << r.gates[1].violations[0].message;
  const std::vector<XyExtremum> e = xy_extrema(r);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_NEAR(e[0].overshoot, 0.003714434811144862, 1e-9);  // its depth below the start node (the reference's y)
  EXPECT_EQ(xy_extremum_violations(r, e[0].overshoot * 1.01).size(), 0u);
  EXPECT_EQ(xy_extremum_violations(r, e[0].overshoot * 0.99).size(), 1u);
  // Ten units off: it pokes out by more than a unit and fails by default.
  const BSpline far = BSpline::bezier({{0, 0}, {100, -40}, {400, 200}, {500, 500}}, "forty units off");
  const SplineReport rf = judged_report(far, gates("xy-extrema-at-nodes"));
  ASSERT_EQ(rf.gates[0].violations.size(), 1u);
  EXPECT_GT(xy_extrema(rf)[0].overshoot, 1.0);
}

// A straight segment has none (even one that doubles back), nor has an
// axis-parallel one; a tangency that touches is none.
TEST(XyExtrema, StraightPiecesAndTouchingTangentsHaveNone) {
  for (const BSpline& s : {BSpline::bezier({{0, 0}, {600, 300}, {-100, -50}, {300, 150}}, "line doubling back"),
                           BSpline::bezier({{0, 0}, {100, 0}, {200, 0}, {300, 0}}, "horizontal"),
                           BSpline::bezier({{0, 0}, {100, 100}, {200, 0}, {300, 100}}, "touch")}) {
    const SplineReport r = judged_report(s, gates("xy-extrema-at-nodes:0"));
    EXPECT_TRUE(r.gates[0].pass()) << s.name() << ": " << r.gates[0].violations.front().message;
  }
}

// TrueType's implied on-curve midpoints are simple knots, no nodes: the
// closed uniform quadratic on a square's corners has its four extrema on
// such joints (the sides' midpoints), and each is a violation there.
TEST(XyExtrema, ExtremaOnImpliedMidpointsAreViolations) {
  const BSpline s = BSpline::make_closed(2, {0, 1, 2, 3, 4}, {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}}, "square");
  const SplineReport r = judged_report(s, gates("xy-extrema-at-nodes"));
  const std::vector<GateViolation>& v = r.gates[0].violations;
  ASSERT_EQ(v.size(), 4u);
  for (const GateViolation& x : v) {
    EXPECT_EQ(x.segment, -1) << x.message;
    EXPECT_GE(x.joint, 1) << x.message;
    EXPECT_NE(x.message.find("which is no node"), std::string::npos) << x.message;
  }
  const std::vector<XyExtremum> e = xy_extrema(r);
  ASSERT_EQ(e.size(), 4u);
  for (const XyExtremum& x : e) {
    EXPECT_EQ(std::abs(x.point.x) + std::abs(x.point.y), 1.0) << x.point.x << ", " << x.point.y;  // a side's midpoint
    EXPECT_EQ(x.overshoot, 2.0);  // from the opposite side's extremum (no node anywhere)
  }
}

// The gate's text round-trips; a bad tolerance is refused with the gate named.
TEST(XyExtrema, GateTextRoundTrips) {
  const std::optional<Gate> g = parse_gate("xy-extrema-at-nodes");
  ASSERT_TRUE(g);
  EXPECT_EQ(g->kind, Gate::Kind::xy_extrema_at_nodes);
  EXPECT_EQ(g->overshoot, kDefaultXyExtremumTolerance);
  EXPECT_EQ(to_string(*g), "xy-extrema-at-nodes");
  EXPECT_EQ(to_string(*parse_gate("xy-extrema-at-nodes:1")), "xy-extrema-at-nodes");
  for (const char* text : {"xy-extrema-at-nodes:0.5", "xy-extrema-at-nodes:0", "xy-extrema-at-nodes:2"}) {
    const std::optional<Gate> p = parse_gate(text);
    ASSERT_TRUE(p) << text;
    EXPECT_EQ(to_string(*p), text);
    EXPECT_EQ(parse_gate(to_string(*p))->overshoot, p->overshoot) << text;
  }
  for (const char* bad : {"xy-extrema-at-nodes:x", "xy-extrema-at-nodes:-1", "xy-extrema-at-nodes:", "xy-extrema-at-nodes:nan"}) {
    try {
      (void)parse_gate(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("xy-extrema-at-nodes"), std::string::npos) << e.what();
    }
  }
  ReportOptions o;
  parse_require_list("cmr,xy-extrema-at-nodes:0.25,curvature-extrema-at-nodes", o);
  ASSERT_EQ(o.gates.size(), 2u);
  EXPECT_EQ(o.gates[0].kind, Gate::Kind::xy_extrema_at_nodes);
  EXPECT_EQ(o.gates[0].overshoot, 0.25);
}

BSpline rotated(const BSpline& s, double degrees) {
  const double c = std::cos(degrees * M_PI / 180), sn = std::sin(degrees * M_PI / 180);
  BSpline out = s;
  for (int k = 0; k < s.unique_point_count(); ++k) {
    const Vec2 p = s.points()[k];
    out = out.with_point(k, {c * p.x - sn * p.y, sn * p.x + c * p.y});
  }
  return out;
}

// O has its extrema on nodes in both fonts; rotated by 30 degrees each
// (convex) contour has exactly one x maximum, x minimum, y maximum and y
// minimum, all inside segments, at the points where dense sampling finds
// the contour's extreme x and y.
TEST(XyExtrema, OPassesAndARotatedOFailsWhereSamplingPutsItsExtrema) {
  const ReportOptions o = gates("xy-extrema-at-nodes");
  for (const char* path : {kDejaVu, kNimbus}) {
    const import::Font font = import::read_font(path, import::parse_glyph_spec("O"));
    ASSERT_EQ(font.glyphs.size(), 1u) << path;
    ASSERT_EQ(font.glyphs[0].contours.size(), 2u) << path;
    for (const import::Contour& c : font.glyphs[0].contours) {
      const SplineReport r = judged_report(c.spline, o);
      EXPECT_TRUE(r.gates[0].pass()) << path << " " << c.spline.name() << ": " << r.gates[0].violations.front().message;
      const BSpline turned = rotated(c.spline, 30);
      const SplineReport rt = judged_report(turned, o);
      const std::vector<GateViolation>& v = rt.gates[0].violations;
      ASSERT_EQ(v.size(), 4u) << path << " " << c.spline.name();
      // Dense sampling of the rotated contour: its extreme x and y.
      constexpr int kSamples = 200000;
      const double t0 = turned.domain_begin(), t1 = turned.domain_end();
      Vec2 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
      Vec2 hi = -lo;
      Vec2 at_lo[2], at_hi[2];
      for (int q = 0; q < kSamples; ++q) {
        const Vec2 p = evaluate(turned, t0 + (t1 - t0) * q / kSamples);
        if (p.x < lo.x) lo.x = p.x, at_lo[0] = p;
        if (p.y < lo.y) lo.y = p.y, at_lo[1] = p;
        if (p.x > hi.x) hi.x = p.x, at_hi[0] = p;
        if (p.y > hi.y) hi.y = p.y, at_hi[1] = p;
      }
      const std::vector<XyExtremum> e = xy_extrema(rt);
      ASSERT_EQ(e.size(), 4u);
      for (const XyExtremum& x : e) {
        EXPECT_GE(x.segment, 0) << "an extremum on a joint that is no node";
        const Vec2 want = x.kind > 0 ? at_hi[x.axis] : at_lo[x.axis];
        const double value = x.axis == 0 ? x.point.x : x.point.y;
        const double want_value = x.axis == 0 ? want.x : want.y;
        EXPECT_NEAR(value, want_value, 1e-3) << path << " axis " << x.axis << " kind " << x.kind;
        EXPECT_NEAR(x.point.x, want.x, 0.5) << path << " axis " << x.axis << " kind " << x.kind;
        EXPECT_NEAR(x.point.y, want.y, 0.5) << path << " axis " << x.axis << " kind " << x.kind;
        // The point is on the curve at t.
        const Vec2 on = evaluate(turned, x.t);
        EXPECT_NEAR(on.x, x.point.x, 1e-6);
        EXPECT_NEAR(on.y, x.point.y, 1e-6);
      }
    }
  }
}

// The command: --require xy-extrema-at-nodes fails the top arc (exit 1),
// report.json carries the violation and the SARIF file its own rule.
TEST(XyExtrema, CommandReportsTheGateInJsonAndSarif) {
  namespace fs = std::filesystem;
  const std::string file = test::write(
      "xy_arc.json", R"({"name": "arc", "degree": 3, "knots": [0, 0, 0, 1, 1, 1], "points": [[0, 0], [100, 300], [400, 300], [500, 0]]})");
  const fs::path out = test::scratch() / "xy_out";
  const fs::path sarif = test::scratch() / "xy.sarif";
  const test::Outcome run = test::run("report " + file + " --require xy-extrema-at-nodes --no-thumbnails --quiet --out " +
                                      out.string() + " --sarif " + sarif.string() + " --junit " +
                                      (test::scratch() / "xy.xml").string());
  EXPECT_EQ(run.code, 1) << run.err;
  const nlohmann::json report = nlohmann::json::parse(test::slurp(out / "report.json"));
  const std::string text = report.dump();
  EXPECT_NE(text.find("xy-extrema-at-nodes"), std::string::npos);
  EXPECT_NE(text.find("add a node at (250, 225)"), std::string::npos) << text.substr(0, 2000);
  const nlohmann::json s = nlohmann::json::parse(test::slurp(sarif));
  bool rule = false;
  for (const auto& r : s["runs"][0]["tool"]["driver"]["rules"])
    if (r["id"] == "xy-extrema-at-nodes") rule = r["name"] == "XyExtremaAtNodes";
  EXPECT_TRUE(rule) << s["runs"][0]["tool"]["driver"]["rules"].dump();
  ASSERT_FALSE(s["runs"][0]["results"].empty());
  EXPECT_EQ(s["runs"][0]["results"][0]["ruleId"], "xy-extrema-at-nodes");
  EXPECT_NE(test::slurp(test::scratch() / "xy.xml").find("add a node at (250, 225)"), std::string::npos);
}

// A UFO source: each finding's SARIF location is the .glif and the line of
// a <point> of the segment that needs the node.
TEST(XyExtrema, UfoFindingsPointAtTheGlifLine) {
  namespace fs = std::filesystem;
  const fs::path dir = test::scratch() / "xy_ufo";
  fs::remove_all(dir);
  const fs::path ufo = dir / "Test.ufo";
  fs::create_directories(ufo / "glyphs");
  const char* plist_head =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<!DOCTYPE plist PUBLIC \"-//Apple//DTD PLIST 1.0//EN\" "
      "\"http://www.apple.com/DTDs/PropertyList-1.0.dtd\">\n<plist version=\"1.0\">\n";
  std::ofstream(ufo / "metainfo.plist") << plist_head
                                        << "<dict><key>creator</key><string>cmr tests</string><key>formatVersion</key>"
                                           "<integer>3</integer></dict>\n</plist>\n";
  std::ofstream(ufo / "fontinfo.plist") << plist_head << "<dict><key>unitsPerEm</key><integer>1000</integer></dict>\n</plist>\n";
  std::ofstream(ufo / "layercontents.plist")
      << plist_head << "<array><array><string>public.default</string><string>glyphs</string></array></array>\n</plist>\n";
  std::ofstream(ufo / "glyphs" / "contents.plist")
      << plist_head << "<dict><key>D</key><string>D_.glif</string></dict>\n</plist>\n";
  // A cubic from (400, 0) to (0, 500) whose handles leave the axes: an x
  // maximum and a y maximum inside it.
  std::ofstream(ufo / "glyphs" / "D_.glif") << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                                               "<glyph name=\"D\" format=\"2\">\n"
                                               "  <advance width=\"600\"/>\n"
                                               "  <unicode hex=\"0044\"/>\n"
                                               "  <outline>\n"
                                               "    <contour>\n"
                                               "      <point x=\"0\" y=\"0\" type=\"line\"/>\n"
                                               "      <point x=\"400\" y=\"0\" type=\"line\"/>\n"
                                               "      <point x=\"600\" y=\"400\"/>\n"
                                               "      <point x=\"200\" y=\"600\"/>\n"
                                               "      <point x=\"0\" y=\"500\" type=\"curve\"/>\n"
                                               "    </contour>\n"
                                               "  </outline>\n"
                                               "</glyph>\n";
  const test::Outcome run = test::run_captured("cd " + dir.string() + " && " + CMR_BINARY +
                                               " report Test.ufo --glyphs all --require xy-extrema-at-nodes "
                                               "--no-thumbnails --quiet --out out --sarif s.sarif");
  ASSERT_EQ(run.code, 1) << run.out << run.err;
  const nlohmann::json s = nlohmann::json::parse(test::slurp(dir / "s.sarif"));
  const auto& results = s["runs"][0]["results"];
  ASSERT_EQ(results.size(), 2u) << results.dump();
  std::vector<std::string> lines;
  {
    std::ifstream in(ufo / "glyphs" / "D_.glif");
    for (std::string line; std::getline(in, line);) lines.push_back(line);
  }
  for (const auto& r : results) {
    const auto& loc = r["locations"][0]["physicalLocation"];
    const std::string uri = loc["artifactLocation"]["uri"];
    EXPECT_NE(uri.find("D_.glif"), std::string::npos) << uri;
    const int line = loc["region"]["startLine"];
    ASSERT_GE(line, 1);
    ASSERT_LE(line, static_cast<int>(lines.size()));
    EXPECT_NE(lines[line - 1].find("<point"), std::string::npos) << lines[line - 1];
    EXPECT_NE(r["message"]["text"].get<std::string>().find("add a node at ("), std::string::npos) << r.dump();
  }
}

}  // namespace
}  // namespace cmr::report
