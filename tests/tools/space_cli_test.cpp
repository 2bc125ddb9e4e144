// `cmr analyze`, `cmr region` and `cmr report` on space curves (issue 25,
// tools/cmd_space.cpp): outputs and one-line errors with exit code 2.
#include <gtest/gtest.h>

#include <algorithm>

#include <nlohmann/json.hpp>

#include "tests/cli_util.hpp"

namespace cmr {
namespace {

using test::run;
using test::write;

const std::string kExample = std::string(CMR_SOURCE_DIR) + "/examples/space/fig8b_lifted.json";

int lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

void expect_one_line_error(const test::Outcome& r, const std::string& want) {
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(want), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST(SpaceCli, AnalyzeReportsCurvatureTorsionAndJoints) {
  const test::Outcome r = run("analyze " + kExample + " --torsion");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_EQ(doc["spline"]["dimension"], 3);
  EXPECT_EQ(doc["spline"]["curvature"], "decreasing");
  EXPECT_EQ(doc["spline"]["torsion"], "none");
  ASSERT_EQ(doc["segments"].size(), 3u);
  EXPECT_EQ(doc["segments"][1]["torsion"], "increasing");
  ASSERT_EQ(doc["joints"].size(), 2u);
  EXPECT_EQ(doc["joints"][0]["continuity"], "C2");
  EXPECT_EQ(doc["joints"][0]["g2"], true);
}

TEST(SpaceCli, PlanarFilesAreUnchanged) {
  const test::Outcome r = run("analyze " + std::string(CMR_SOURCE_DIR) + "/examples/figures/fig8b.json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_FALSE(doc["spline"].contains("dimension"));
  EXPECT_EQ(doc["spline"]["cmrwi"], "increasing");
}

TEST(SpaceCli, BadSpaceInputExitsTwoWithOneLine) {
  expect_one_line_error(run("analyze " + write("mixed.json", R"({"points":[[0,0,0],[1,1],[2,0,1]]})")),
                        "points[1] has 2 coordinates but points[0] has 3 (all points must be [x, y], or all [x, y, z])");
  expect_one_line_error(run("analyze " + write("w2.json", R"({"points":[[0,0,0],[1,1,1],[2,0,1]],"weights":[1,2]})")),
                        "weights: one weight per control point is needed: 3 points, 2 weights");
  expect_one_line_error(run("analyze " + write("w0.json", R"({"points":[[0,0,0],[1,1,1],[2,0,1]],"weights":[1,0,1]})")),
                        "weights[1] is 0: rational space curves need positive weights");
  expect_one_line_error(run("region " + write("wn.json", R"({"points":[[0,0,0],[1,1,1],[2,0,1]],"weights":[1,-2,1]})") +
                            " --point 1 --plane xy"),
                        "weights[1] is -2: rational space curves need positive weights");
  // A report lists a mixed file as invalid (exit 2, its line) instead of
  // ending the run, so that one such file does not stop a corpus (issue 42).
  const test::Outcome wm = run("report " + write("wm.json", R"({"points":[[0,0,0],[1,1],[2,0,1]],"weights":[1,2,1]})") +
                               " --out " + (test::scratch() / "wm_report").string());
  EXPECT_EQ(wm.code, 2) << wm.err;
  EXPECT_NE(wm.err.find("wm.json: points[1] has 2 coordinates but points[0] has 3"), std::string::npos) << wm.err;
  EXPECT_NE(test::slurp(test::scratch() / "wm_report" / "report.json").find("\"invalid\":1"), std::string::npos);
  expect_one_line_error(run("analyze " + kExample + " --split 1"),
                        "--split, --segments, --each-piece and --mode are for planar splines");
  expect_one_line_error(run("analyze " + std::string(CMR_SOURCE_DIR) + "/examples/figures/fig8b.json --torsion"),
                        "--torsion and --torsion-tol are for space curves");
  expect_one_line_error(run("region " + kExample + " --point 3 --plane 0,0,0,1,0,0,2,0,0"),
                        "--plane: U and V are parallel (the plane is degenerate)");
  expect_one_line_error(run("region " + kExample + " --point 3 --plane 0,0,0"), "--plane: 3 numbers given, expected 9");
  expect_one_line_error(
      run("region " +
          write("rational8.json", R"({"degree": 8, "knots": [0,0,0,0,0,0,0,0,1,1,1,1,1,1,1,1],
            "points": [[0,0,0],[1,0.1,0.2],[2,0.4,0.1],[3,0.9,0],[4,1.6,0.3],[5,2.5,0.1],[6,3.6,0],[7,4.9,0.2],[8,6.4,0]],
            "weights": [1,2,1,1,1,1,1,1,1]})") +
          " --point 4 --plane xy --backend vulkan"),
      "--backend vulkan: rational space curves of degree 2..6 only (this one has degree 8; use --backend cpu)");
  expect_one_line_error(run("region " + kExample + " --point 3 --split 1"), "--split is for planar splines");
  expect_one_line_error(run("region " + kExample + " --point 9"), "--point 9 is outside 0..5");
  expect_one_line_error(run("region " + kExample + " --point all"), "'all' is for planar splines");
  expect_one_line_error(run("region " + std::string(CMR_SOURCE_DIR) + "/examples/figures/fig8b.json --point 3 --plane xy"),
                        "--plane is for space curves");
  expect_one_line_error(run("analyze missing.json --torsion"), "missing.json: cannot open the file");
  expect_one_line_error(run("region missing.json --point 1 --plane xy"), "missing.json: cannot open the file");
}

TEST(SpaceCli, RegionWritesLabelsAndCountsThem) {
  const std::string labels = (test::scratch() / "space_labels.pgm").string();
  const test::Outcome r =
      run("region " + kExample + " --point 3 --plane xy --view -1.2,-1.2,0.8,0.8 --size 40x40 --labels " + labels);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_EQ(doc["dimension"], 3);
  EXPECT_EQ(doc["backend"], "cpu");
  EXPECT_EQ(doc["plane"]["origin"], nlohmann::json::parse("[1.2,-4.03,1.5]"));
  const int dec = doc["counts"]["decreasing"], none = doc["counts"]["none"];
  EXPECT_GT(dec, 100);
  EXPECT_GT(none, 100);
  const std::string pgm = test::slurp(labels);
  ASSERT_EQ(pgm.substr(0, 13), "P5\n40 40\n255\n");
  EXPECT_EQ(std::count(pgm.begin() + 13, pgm.end(), '\x02'), dec);
}

// examples/space/fig8b_lifted_rational.json: the lifted Fig. 8b curve with
// weights; analyze, region (CPU) and report all take it.
TEST(SpaceCli, RationalSpaceCurveAnalyzesReportsAndHasRegions) {
  const std::string file = std::string(CMR_SOURCE_DIR) + "/examples/space/fig8b_lifted_rational.json";
  const test::Outcome a = run("analyze " + file + " --torsion");
  ASSERT_EQ(a.code, 0) << a.err;
  const auto doc = nlohmann::json::parse(a.out);
  EXPECT_EQ(doc["spline"]["dimension"], 3);
  EXPECT_EQ(doc["spline"]["curvature"], "decreasing");
  ASSERT_EQ(doc["segments"].size(), 3u);
  EXPECT_EQ(doc["segments"][0]["torsion_sign"], "negative");
  const std::string labels = (test::scratch() / "space_rational_labels.pgm").string();
  const test::Outcome r =
      run("region " + file + " --point 3 --plane xy --view -1.2,-1.2,0.8,0.8 --size 24x24 --labels " + labels);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto reg = nlohmann::json::parse(r.out);
  EXPECT_GT(reg["counts"]["decreasing"].get<int>(), 20);
  EXPECT_GT(reg["counts"]["none"].get<int>(), 20);
  const std::string dir = (test::scratch() / "space_rational_report").string();
  const test::Outcome p = run("report " + file + " --out " + dir + " --require cmrwi");
  ASSERT_EQ(p.code, 0) << p.err;
  const auto rep = nlohmann::json::parse(test::slurp(dir + "/report.json"));
  EXPECT_EQ(rep["splines"][0]["pass"], true);
  EXPECT_EQ(rep["splines"][0]["analysis"]["spline"]["curvature"], "decreasing");
}

// --backend vulkan (lavapipe): the same labels file as --backend cpu.
TEST(SpaceCli, RegionOnVulkanWritesTheCpuLabels) {
  const std::string cpu = (test::scratch() / "space_cpu.pgm").string(), gpu = (test::scratch() / "space_vk.pgm").string();
  const std::string args = "region " + kExample + " --point 3 --plane xy --view -1.2,-1.2,0.8,0.8 --size 32x32 --labels ";
  const test::Outcome c = run(args + cpu + " --backend cpu");
  ASSERT_EQ(c.code, 0) << c.err;
  const test::Outcome g = run(args + gpu + " --backend vulkan --stats");
  ASSERT_EQ(g.code, 0) << g.err;
  const auto doc = nlohmann::json::parse(g.out);
  EXPECT_EQ(doc["backend"], "vulkan");
  EXPECT_LT(doc["host_pixels"].get<int>(), 32 * 32 / 2);
  EXPECT_EQ(test::slurp(gpu), test::slurp(cpu));
}

// A rational space curve on --backend vulkan: the same labels and picture.
TEST(SpaceCli, RegionOfARationalCurveOnVulkanWritesTheCpuLabelsAndPicture) {
  const std::string file = std::string(CMR_SOURCE_DIR) + "/examples/space/fig8b_lifted_rational.json";
  const std::string dir = test::scratch().string() + "/space_rational_";
  const std::string args = "region " + file + " --point 3 --plane xy --view -1.2,-1.2,0.8,0.8 --size 32x32";
  const test::Outcome c = run(args + " --labels " + dir + "cpu.pgm --png " + dir + "cpu.png --backend cpu");
  ASSERT_EQ(c.code, 0) << c.err;
  const test::Outcome g = run(args + " --labels " + dir + "vk.pgm --png " + dir + "vk.png --backend vulkan --stats");
  ASSERT_EQ(g.code, 0) << g.err;
  const auto doc = nlohmann::json::parse(g.out);
  EXPECT_EQ(doc["backend"], "vulkan");
  EXPECT_LT(doc["host_pixels"].get<int>(), 32 * 32 / 2);
  EXPECT_GT(doc["counts"]["decreasing"].get<int>(), 20);
  EXPECT_GT(doc["counts"]["none"].get<int>(), 20);
  EXPECT_EQ(test::slurp(dir + "vk.pgm"), test::slurp(dir + "cpu.pgm"));
  EXPECT_EQ(test::slurp(dir + "vk.png"), test::slurp(dir + "cpu.png"));
}

TEST(SpaceCli, ImportObjWritesSpaceSplinesThatAnalyzeReads) {
  const std::string dir = (test::scratch() / "obj_import").string();
  const test::Outcome r = run("import " + std::string(CMR_SOURCE_DIR) + "/examples/space/curves.obj --out " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("imported 2 space curves"), std::string::npos) << r.out;
  const test::Outcome a = run("analyze " + dir + "/curves_0_lifted.json");
  ASSERT_EQ(a.code, 0) << a.err;
  const auto doc = nlohmann::json::parse(a.out);
  // The same curve as examples/space/fig8b_lifted.json (its knots shifted by -1).
  EXPECT_EQ(doc["spline"]["curvature"], "decreasing");
  EXPECT_EQ(doc["segments"].size(), 3u);
  const test::Outcome b = run("analyze " + dir + "/curves_1_sweep.json");
  ASSERT_EQ(b.code, 0) << b.err;
  EXPECT_EQ(nlohmann::json::parse(b.out)["segments"].size(), 2u);
  expect_one_line_error(run("import " + write("none.obj", "v 0 0 0\nf 1 1 1\n") + " --out " + dir),
                        "none.obj: no curves (cstype/curv or l elements)");
}

TEST(SpaceCli, ReportWritesJsonAndHtmlAndGatesOnCurvature) {
  const std::string dir = (test::scratch() / "space_report").string();
  const test::Outcome r = run("report " + kExample + " --out " + dir + " --require cmrwi");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("1 space curve: 1 pass, 0 fail, 0 invalid"), std::string::npos) << r.out;
  const auto doc = nlohmann::json::parse(test::slurp(dir + "/report.json"));
  EXPECT_EQ(doc["dimension"], 3);
  EXPECT_EQ(doc["splines"][0]["analysis"]["spline"]["curvature"], "decreasing");
  EXPECT_EQ(doc["splines"][0]["analysis"]["spline"]["torsion"], "none");
  EXPECT_TRUE(doc["splines"][0]["curvature_extrema"].empty());  // monotone: no extremum inside a segment
  const std::string html = test::slurp(dir + "/index.html");
  int svgs = 0;
  for (std::size_t at = html.find("<svg"); at != std::string::npos; at = html.find("<svg", at + 1)) ++svgs;
  EXPECT_EQ(svgs, 3);  // projections, curvature plot, torsion plot
  // A curve that is not monotone fails the gate: exit 1, with its extrema located.
  const std::string bent = write("bent.json", R"({"points":[[0,0,0],[1,1,0.5],[2,-1,1],[3,0,0]]})");
  const test::Outcome f = run("report " + bent + " --out " + dir + " --require cmrwi");
  EXPECT_EQ(f.code, 1) << f.err;
  EXPECT_FALSE(nlohmann::json::parse(test::slurp(dir + "/report.json"))["splines"][0]["curvature_extrema"].empty());
  // Planar and space files together: one report of both (SpaceReportCi.MixedPlanarAndSpaceInputsAreOneReport).
  const test::Outcome mixed =
      run("report " + kExample + " " + std::string(CMR_SOURCE_DIR) + "/examples/figures/fig8b.json --out " + dir);
  EXPECT_EQ(mixed.code, 0) << mixed.err;
  EXPECT_EQ(nlohmann::json::parse(test::slurp(dir + "/report.json"))["splines"].size(), 2u);
  expect_one_line_error(run("report " + kExample + " --out " + dir + " --require split:1"),
                        "has no meaning in 3D");  // the other checks and gates: space_report_ci_test.cpp
}

}  // namespace
}  // namespace cmr
