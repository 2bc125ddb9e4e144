// `cmr report` on space curves in CI (issue 40, items 1 and 2): the planar
// report's schema with findings, JUnit, SARIF, --baseline and folders; the
// 3D gates; flags that do not apply refused in one line; --constant-tol and
// --torsion-tol (report/space_report.hpp, bezierize/space_analyze.hpp).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/cli_util.hpp"

namespace cmr {
namespace {

namespace fs = std::filesystem;
using test::Outcome;
using test::run;
using test::slurp;

const std::string kSource = CMR_SOURCE_DIR;
const std::string kPassing = kSource + "/examples/space/fig8b_lifted.json";  // |kappa| decreasing
const std::string kFailing = kSource + "/examples/space/fig8_lifted.json";   // not monotone

fs::path fresh(const std::string& name) {
  const fs::path dir = test::scratch() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void expect_one_line_exit_2(const Outcome& r, const std::string& part, const std::string& label) {
  EXPECT_EQ(r.code, 2) << label << ": " << r.err;
  EXPECT_NE(r.err.find(part), std::string::npos) << label << ": " << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << label << ": " << r.err;
}

TEST(SpaceReportCi, AFolderWithRequireJunitSarifAndBaselineWritesBothFilesAndHonoursTheBaseline) {
  const fs::path dir = fresh("space_ci");
  const fs::path curves = dir / "curves";
  fs::create_directories(curves);
  fs::copy_file(kPassing, curves / "a.json");
  fs::copy_file(kFailing, curves / "b.json");
  const std::string ci = " --require cmrwi --no-thumbnails --junit " + (dir / "j.xml").string() + " --sarif " +
                         (dir / "s.sarif").string() + " --markdown " + (dir / "m.md").string();
  // 1. The first run: b fails; both CI files written, report.json with the schema and findings.
  const Outcome first = run("report " + curves.string() + ci + " --out " + (dir / "r1").string());
  EXPECT_EQ(first.code, 1) << first.err;
  ASSERT_TRUE(fs::exists(dir / "j.xml"));
  ASSERT_TRUE(fs::exists(dir / "s.sarif"));
  const std::string junit = slurp(dir / "j.xml");
  EXPECT_NE(junit.find("<testsuites"), std::string::npos);
  std::size_t cases = 0;
  for (std::size_t at = junit.find("<testcase"); at != std::string::npos; at = junit.find("<testcase", at + 1)) ++cases;
  EXPECT_EQ(cases, 2u) << junit;
  EXPECT_NE(junit.find("<failure"), std::string::npos) << junit;
  const std::string markdown = slurp(dir / "m.md");  // the planar run's summary: the failing curve named
  EXPECT_NE(markdown.find("b.json"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("fig8-lifted"), std::string::npos) << markdown;
  const nlohmann::json sarif = nlohmann::json::parse(slurp(dir / "s.sarif"));
  ASSERT_EQ(sarif["runs"][0]["results"].size(), 1u) << sarif.dump();
  EXPECT_EQ(sarif["runs"][0]["results"][0]["ruleId"], "cmrwi");
  const nlohmann::json doc = nlohmann::json::parse(slurp(dir / "r1" / "report.json"));
  EXPECT_EQ(doc["schema"], "cmr-report/2");
  ASSERT_EQ(doc["splines"].size(), 2u);
  EXPECT_EQ(doc["splines"][0]["status"], "pass");
  EXPECT_EQ(doc["splines"][1]["status"], "fail");
  ASSERT_EQ(doc["splines"][1]["findings"].size(), 1u);
  EXPECT_EQ(doc["splines"][1]["findings"][0]["key"], "b.json|fig8-lifted|c0||cmrwi") << doc["splines"][1].dump();
  // 2. Against its own baseline: nothing new, exit 0, the SARIF result "unchanged".
  const std::string baseline = " --baseline " + (dir / "r1" / "report.json").string();
  const Outcome same = run("report " + curves.string() + ci + baseline + " --out " + (dir / "r2").string());
  EXPECT_EQ(same.code, 0) << same.err;
  EXPECT_NE(same.out.find("0 new, 0 fixed, 1 unchanged"), std::string::npos) << same.out;
  EXPECT_EQ(nlohmann::json::parse(slurp(dir / "s.sarif"))["runs"][0]["results"][0]["baselineState"], "unchanged");
  // 3. A new failing curve: exit 1, named on stderr; the old one stays unchanged.
  fs::copy_file(kFailing, curves / "c.json");
  const Outcome more = run("report " + curves.string() + ci + baseline + " --out " + (dir / "r3").string());
  EXPECT_EQ(more.code, 1) << more.err;
  EXPECT_NE(more.err.find("cmr: new: c.json: cmrwi:"), std::string::npos) << more.err;
  EXPECT_NE(more.out.find("1 new, 0 fixed, 1 unchanged"), std::string::npos) << more.out;
  EXPECT_NE(slurp(dir / "m.md").find("1 new"), std::string::npos) << slurp(dir / "m.md");
  // 4. The fixed curve: the baseline counts it fixed.
  fs::remove(curves / "b.json");
  fs::remove(curves / "c.json");
  const Outcome fixed = run("report " + curves.string() + ci + baseline + " --out " + (dir / "r4").string());
  EXPECT_EQ(fixed.code, 0) << fixed.err;
  EXPECT_NE(fixed.out.find("0 new, 1 fixed, 0 unchanged"), std::string::npos) << fixed.out;
  fs::remove_all(dir);
}

// Planar and space inputs in one run (a folder with both): one report.json
// with every curve (the planar part's first, then the space curves'), one
// JUnit, SARIF and Markdown file, the exit code of the whole run, a baseline
// honoured for both kinds, each part's page under parts/; a file with both
// [x, y] and [x, y, z] points is one invalid entry (exit 2). The private
// folder of the parts is gone afterwards (the scratch cleanup fixture fails
// on leftovers).
TEST(SpaceReportCi, MixedPlanarAndSpaceInputsAreOneReport) {
  const fs::path dir = fresh("space_mixed");
  const fs::path curves = dir / "curves";
  fs::create_directories(curves);
  fs::copy_file(kPassing, curves / "a3.json");
  fs::copy_file(kFailing, curves / "b3.json");
  fs::copy_file(kSource + "/examples/clamped.json", curves / "c2.json");
  fs::copy_file(kSource + "/examples/uniform.json", curves / "d2.json");
  const std::string ci = " --require cmrwi --no-thumbnails --junit " + (dir / "j.xml").string() + " --sarif " +
                         (dir / "s.sarif").string() + " --markdown " + (dir / "m.md").string();
  // What each kind gives alone: the mixed run must add up to these.
  const Outcome planar_alone = run("report " + (curves / "c2.json").string() + " " + (curves / "d2.json").string() +
                                   " --require cmrwi --no-thumbnails --out " + (dir / "p").string());
  const Outcome space_alone = run("report " + (curves / "a3.json").string() + " " + (curves / "b3.json").string() +
                                  " --require cmrwi --no-thumbnails --out " + (dir / "s").string());
  const nlohmann::json p = nlohmann::json::parse(slurp(dir / "p" / "report.json"));
  const nlohmann::json sp = nlohmann::json::parse(slurp(dir / "s" / "report.json"));
  const int findings = p["summary"]["findings"].get<int>() + sp["summary"]["findings"].get<int>();
  const Outcome first = run("report " + curves.string() + ci + " --out " + (dir / "r1").string());
  EXPECT_EQ(first.code, std::max(planar_alone.code, space_alone.code)) << first.err;
  EXPECT_EQ(first.code, 1) << first.err;  // fig8-lifted fails cmrwi
  EXPECT_NE(first.out.find("2 planar, 2 space curves; wrote "), std::string::npos) << first.out;
  const nlohmann::json doc = nlohmann::json::parse(slurp(dir / "r1" / "report.json"));
  EXPECT_EQ(doc["schema"], "cmr-report/2");
  ASSERT_EQ(doc["splines"].size(), 4u);
  std::vector<std::string> files;
  int statuses_equal = 0;
  for (const auto& s : doc["splines"]) {
    files.push_back(fs::path(s["file"].get<std::string>()).filename().string());
    for (const nlohmann::json* alone : {&p, &sp})
      for (const auto& a : (*alone)["splines"])
        if (fs::path(a["file"].get<std::string>()).filename() == files.back()) {
          EXPECT_EQ(s["status"], a["status"]) << files.back();
          EXPECT_EQ(s["findings"].size(), a["findings"].size()) << files.back();
          ++statuses_equal;
        }
  }
  EXPECT_EQ(files, (std::vector<std::string>{"c2.json", "d2.json", "a3.json", "b3.json"}));
  EXPECT_EQ(statuses_equal, 4);
  EXPECT_EQ(doc["summary"]["findings"], findings);
  EXPECT_EQ(doc["summary"]["exit_code"], 1);
  std::size_t cases = 0;
  const std::string junit = slurp(dir / "j.xml");
  for (std::size_t at = junit.find("<testcase"); at != std::string::npos; at = junit.find("<testcase", at + 1)) ++cases;
  EXPECT_EQ(cases, 4u) << junit;
  const nlohmann::json sarif = nlohmann::json::parse(slurp(dir / "s.sarif"));
  EXPECT_EQ(sarif["runs"].size(), 1u);
  EXPECT_EQ(static_cast<int>(sarif["runs"][0]["results"].size()), findings);
  const std::string markdown = slurp(dir / "m.md");
  EXPECT_NE(markdown.find("Part 1: planar"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("Part 2: space"), std::string::npos) << markdown;
  EXPECT_TRUE(fs::exists(dir / "r1" / "parts" / "planar" / "index.html"));
  EXPECT_TRUE(fs::exists(dir / "r1" / "parts" / "space" / "index.html"));
  // Against its own baseline: nothing new for either kind, exit 0.
  const Outcome same = run("report " + curves.string() + ci + " --baseline " + (dir / "r1" / "report.json").string() +
                           " --out " + (dir / "r2").string());
  EXPECT_EQ(same.code, 0) << same.err;
  EXPECT_NE(same.out.find("0 new, 0 fixed, " + std::to_string(findings) + " unchanged"), std::string::npos) << same.out;
  // A file with both kinds of points: an invalid entry, exit 2, the report still written.
  std::ofstream(curves / "e.json") << R"({"degree": 1, "knots": [0, 0, 1, 1], "points": [[0, 0, 0], [1, 1]]})";
  const Outcome bad = run("report " + curves.string() + " --no-thumbnails --out " + (dir / "r3").string());
  EXPECT_EQ(bad.code, 2) << bad.err;
  const nlohmann::json d3 = nlohmann::json::parse(slurp(dir / "r3" / "report.json"));
  int invalid = 0;
  for (const auto& s : d3["splines"]) invalid += s["status"] == "invalid";
  EXPECT_EQ(invalid, 1) << d3.dump();
  EXPECT_EQ(d3["summary"]["invalid"], 1);
  fs::remove_all(dir);
}

TEST(SpaceReportCi, GatesThatMeanSomethingIn3DGiveFindingsBySegmentAndJoint) {
  const fs::path dir = fresh("space_gates");
  const Outcome r = run("report " + kFailing + " --require curvature-extrema-at-nodes,g2-at-smooth-nodes:0,no-inflection " +
                        "--no-thumbnails --out " + dir.string());
  EXPECT_EQ(r.code, 1) << r.err;
  const nlohmann::json doc = nlohmann::json::parse(slurp(dir / "report.json"));
  const nlohmann::json& s = doc["splines"][0];
  ASSERT_EQ(s["gates"].size(), 3u);
  // Every curvature extremum strictly inside a segment is one finding, "segment i".
  std::size_t extrema = 0;
  for (const auto& e : s["curvature_extrema"]) (void)e, ++extrema;
  std::size_t inside = 0;
  for (const auto& f : s["findings"])
    if (f["gate"] == "curvature-extrema-at-nodes") {
      ++inside;
      EXPECT_EQ(f["node"].get<std::string>().rfind("segment ", 0), 0u) << f.dump();
    }
  EXPECT_EQ(inside, extrema);
  EXPECT_GT(extrema, 0u);
  // A C2 cubic spline: equal curvature at every joint, so no G2 finding even at tolerance 0.
  for (const auto& f : s["findings"]) EXPECT_NE(f["gate"], "g2-at-smooth-nodes:0") << f.dump();
  fs::remove_all(dir);
}

TEST(SpaceReportCi, FlagsAndGatesThatDoNotApplyAreRefusedInOneLine) {
  const fs::path dir = fresh("space_refused");
  const std::string out = " --out " + (dir / "r").string();
  expect_one_line_exit_2(run("report " + kPassing + " --glyphs A" + out), "--glyphs: not for space curves", "glyphs");
  expect_one_line_exit_2(run("report " + kPassing + " --segments 0..1" + out), "--segments: not for space curves", "segments");
  expect_one_line_exit_2(run("report " + kPassing + " --require split:1" + out), "has no meaning in 3D", "split");
  expect_one_line_exit_2(run("report " + kPassing + " --require xy-extrema-at-nodes" + out), "a rule for font outlines", "xy");
  expect_one_line_exit_2(run("report " + kSource + "/examples/clamped.json --torsion-tol 1e-6" + out),
                         "--torsion-tol: for space curves", "torsion-tol on a planar run");
  // Planar and space inputs together: a gate or flag that does not apply to the space curves is refused.
  const std::string mixed = "report " + kPassing + " " + kSource + "/examples/clamped.json";
  expect_one_line_exit_2(run(mixed + " --require split:1" + out), "has no meaning in 3D", "mixed split");
  expect_one_line_exit_2(run(mixed + " --require cmrwi,xy-extrema-at-nodes" + out), "a rule for font outlines", "mixed xy");
  expect_one_line_exit_2(run(mixed + " --glyphs A" + out), "--glyphs: not for space curves", "mixed glyphs");
  expect_one_line_exit_2(run(mixed + " --shard 1/2" + out), "--shard is for planar reports", "mixed shard");
  expect_one_line_exit_2(run("analyze " + kSource + "/examples/clamped.json --torsion-tol 1e-6"),
                         "--torsion and --torsion-tol are for space curves", "analyze planar");
  EXPECT_FALSE(fs::exists(dir / "r"));
  fs::remove_all(dir);
}

/// A quarter circle of radius 1 in the plane spanned by u = (1, 0, 0) and
/// v = (0, cos 30°, sin 30°) (a rational quadratic: u, u + v, v with weights
/// 1, cos 45°, 1), its middle weight times (1 + eps): a circle up to
/// rounding for eps = 0, else an ellipse arc whose curvature varies by about
/// 3 eps relative.
std::string tilted_arc(double eps) {
  const double w = std::sqrt(0.5) * (1 + eps), c = std::sqrt(0.75);
  char buf[320];
  std::snprintf(buf, sizeof buf,
                R"({"name": "arc", "points": [[1, 0, 0], [1, %.17g, 0.5], [0, %.17g, 0.5]], "weights": [1, %.17g, 1]})", c,
                c, w);
  return buf;
}

TEST(SpaceReportCi, ConstantTolerancePassesANearCircleAndIsNotIgnored) {
  const fs::path dir = fresh("space_constant");
  const std::string arc = (dir / "arc.json").string();
  std::ofstream(arc) << tilted_arc(1e-7);
  const auto verdict = [&](const std::string& tol) {
    const Outcome r = run("report " + arc + " --require cmrwi --no-thumbnails --constant-tol " + tol + " --out " +
                          (dir / ("r" + tol)).string());
    const nlohmann::json doc = nlohmann::json::parse(slurp(dir / ("r" + tol) / "report.json"));
    return std::make_pair(r.code, doc["splines"][0]["kappa_spread"].get<double>());
  };
  const auto [tight, spread] = verdict("1e-9");
  const auto [loose, spread2] = verdict("1e-5");
  EXPECT_EQ(tight, 1) << "a spread of " << spread << " is no constant at 1e-9";
  EXPECT_EQ(loose, 0) << "a spread of " << spread2 << " is constant at 1e-5";
  EXPECT_GT(spread, 1e-9);
  EXPECT_LT(spread, 1e-5);
  EXPECT_EQ(spread, spread2);
  fs::remove_all(dir);
}

// One --constant-tol rule for planar and space curves (report.hpp,
// turning_deviation): a planar curve and the same curve turned into space
// (rotated about the x axis) get the same turning deviation per segment and
// the same near_constant at a tolerance above it and one below it: a near
// circle (a rational arc with a weight off by 3e-7) and a designed cubic.
TEST(SpaceReportCi, ConstantToleranceIsOneRuleForPlanarAndSpaceCurves) {
  const fs::path dir = fresh("space_one_rule");
  struct Curve {
    const char* name;
    std::vector<std::array<double, 2>> points;
    std::string extra;
  };
  const std::vector<Curve> curves = {
      {"arc", {{1, 0}, {1, 1}, {0, 1}}, R"(, "weights": [1, 0.70710685, 1])"},
      {"cubic", {{0, 0}, {1, 2}, {3, 3}, {6, 3}, {8, 1}}, R"(, "degree": 3, "knots": [0, 0, 0, 1, 2, 2, 2])"}};
  const double c = std::cos(0.7), s = std::sin(0.7);
  for (const Curve& cv : curves) {
    std::string planar = std::string(R"({"name": ")") + cv.name + R"(", "points": [)", space = planar;
    for (std::size_t i = 0; i < cv.points.size(); ++i) {
      const auto [x, y] = cv.points[i];
      char buf[160];
      std::snprintf(buf, sizeof buf, "%s[%.17g, %.17g]", i ? ", " : "", x, y);
      planar += buf;
      std::snprintf(buf, sizeof buf, "%s[%.17g, %.17g, %.17g]", i ? ", " : "", x, y * c, y * s);
      space += buf;
    }
    const fs::path p2 = dir / (std::string(cv.name) + "_2d.json"), p3 = dir / (std::string(cv.name) + "_3d.json");
    std::ofstream(p2) << planar << "]" << cv.extra << "}";
    std::ofstream(p3) << space << "]" << cv.extra << "}";
    const auto segments = [&](const fs::path& file, const std::string& tol, bool is_space) {
      const fs::path out = dir / (file.stem().string() + "_" + tol);
      const Outcome r = run("report " + file.string() + " --no-thumbnails --constant-tol " + tol + " --out " + out.string());
      EXPECT_EQ(r.code, 0) << r.err;
      const nlohmann::json doc = nlohmann::json::parse(slurp(out / "report.json"));
      return is_space ? doc["splines"][0]["analysis"]["segments"] : doc["splines"][0]["segments"];
    };
    const nlohmann::json flat = segments(p2, "1e-9", false);
    const nlohmann::json turned = segments(p3, "1e-9", true);
    ASSERT_EQ(flat.size(), turned.size()) << cv.name;
    for (std::size_t i = 0; i < flat.size(); ++i) {
      const double d2 = flat[i]["turning_deviation"], d3 = turned[i]["turning_deviation"];
      EXPECT_NEAR(d3, d2, 1e-6 * d2) << cv.name << " segment " << i;
      EXPECT_GT(d2, 1e-9) << cv.name;  // neither is constant at the default
      for (const double tol : {d2 * 2, d2 / 2}) {
        char t[32];
        std::snprintf(t, sizeof t, "%.6g", tol);
        const bool a = segments(p2, t, false)[i]["near_constant"], b = segments(p3, t, true)[i]["near_constant"];
        EXPECT_EQ(a, tol > d2) << cv.name << " at " << t;
        EXPECT_EQ(b, a) << cv.name << " at " << t;
      }
    }
  }
  fs::remove_all(dir);
}

TEST(SpaceReportCi, TorsionToleranceMakesANearlyPlanarCurvePlanar) {
  const fs::path dir = fresh("space_torsion");
  // fig8b lifted only by 1e-7 z wiggles: torsion of about that size, not exactly 0.
  const std::string file = (dir / "flat.json").string();
  std::ofstream(file) << R"({"name": "flat", "degree": 3, "knots": [0, 1, 2, 3, 4, 5, 6, 7],
    "points": [[1.3, -1.43, 0], [1.05, -0.06, 1e-7], [2.15, -1.31, -1e-7], [1.2, -4.03, 2e-7], [-2.23, -6.95, 0],
               [-6.78, -9.78, 1e-7]]})";
  const Outcome exact = run("analyze " + file + " --torsion");
  ASSERT_EQ(exact.code, 0) << exact.err;
  const nlohmann::json a = nlohmann::json::parse(exact.out);
  EXPECT_EQ(a["spline"]["planar"], false);
  const Outcome tol = run("analyze " + file + " --torsion --torsion-tol 1e-3");
  ASSERT_EQ(tol.code, 0) << tol.err;
  const nlohmann::json b = nlohmann::json::parse(tol.out);
  EXPECT_EQ(b["spline"]["planar"], true);
  EXPECT_EQ(b["spline"]["torsion"], "increasing");  // constant pieces go with either direction (the planar rules)
  for (const auto& s : b["segments"]) EXPECT_EQ(s["torsion"], "constant") << s.dump();
  // An exactly planar curve is planar without a tolerance.
  const std::string flat = (dir / "zero.json").string();
  std::ofstream(flat) << R"({"degree": 3, "knots": [0, 1, 2, 3, 4, 5, 6, 7],
    "points": [[1.3, -1.43, 1], [1.05, -0.06, 1], [2.15, -1.31, 1], [1.2, -4.03, 1], [-2.23, -6.95, 1],
               [-6.78, -9.78, 1]]})";
  const Outcome zero = run("analyze " + flat + " --torsion");
  ASSERT_EQ(zero.code, 0) << zero.err;
  EXPECT_EQ(nlohmann::json::parse(zero.out)["spline"]["planar"], true);
  expect_one_line_exit_2(run("analyze " + file + " --torsion-tol 1e-3"), "--torsion-tol: only with --torsion", "no --torsion");
  expect_one_line_exit_2(run("analyze " + file + " --torsion --torsion-tol -1"), "--torsion-tol", "negative");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace cmr
