// `cmr import` of Wavefront OBJ `rat` curves with unequal weights (issue 25,
// io/obj.hpp, docs/space.md): the imported file is the spline file, and
// analyze and report judge it as they judge that file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "tests/cli_util.hpp"

namespace cmr {
namespace {

using test::run;
using test::write;

const std::string kExamples = std::string(CMR_SOURCE_DIR) + "/examples/";

std::string imported(const std::string& name) {
  const std::string dir = (test::scratch() / "rational_obj").string();
  const test::Outcome r = run("import " + kExamples + "space/rational.obj --out " + dir);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("imported 2 space curves"), std::string::npos) << r.out;
  return dir + "/" + name;
}

nlohmann::json analyze(const std::string& file, const std::string& options = "") {
  const test::Outcome r = run("analyze " + file + options);
  EXPECT_EQ(r.code, 0) << file << ": " << r.err;
  return r.code == 0 ? nlohmann::json::parse(r.out) : nlohmann::json();
}

// The rat bspline of rational.obj is fig8b_lifted_rational.json: the same
// degree, knots, points and weights (exact doubles), and the same analysis.
TEST(SpaceObjRational, ImportedUnequalWeightsEqualTheSplineFileAndItsVerdict) {
  const std::string file = imported("rational_0_fig8b-lifted-rational.json");
  const auto got = nlohmann::json::parse(test::slurp(file));
  const auto want = nlohmann::json::parse(test::slurp(kExamples + "space/fig8b_lifted_rational.json"));
  for (const char* key : {"name", "degree", "knots", "points", "weights"})
    EXPECT_EQ(got[key], want[key]) << key;  // nlohmann compares the numbers as doubles: exact
  const auto a = analyze(file, " --torsion");
  const auto b = analyze(kExamples + "space/fig8b_lifted_rational.json", " --torsion");
  EXPECT_EQ(a, b);
  EXPECT_EQ(a["spline"]["curvature"], "decreasing");
}

// A quarter circle as a rational quadratic with weights 1, sqrt(2)/2, 1 as
// decimals: exactly an ellipse arc whose |kappa| has a stationary point
// mid-way (docs/analyze.md, "Arcs of constant curvature"): the segment is
// non-monotone, the spline verdict none, as for the planar file
// examples/rational/quarter_circle.json; its kappa is 1 to rounding.
TEST(SpaceObjRational, QuarterCircleIsAnalysedAsItsPlanarFile) {
  const std::string file = imported("rational_1_quarter-circle.json");
  const auto space = analyze(file);
  const auto plane = analyze(kExamples + "rational/quarter_circle.json");
  ASSERT_EQ(space["segments"].size(), 1u);
  EXPECT_EQ(space["segments"][0]["curvature"], "non-monotone");
  EXPECT_EQ(space["segments"][0]["curvature"], plane["segments"][0]["curvature"]);
  EXPECT_EQ(space["segments"][0]["zero_curvature"], nlohmann::json::array());
  EXPECT_EQ(space["spline"]["curvature"], "none");
  EXPECT_EQ(space["spline"]["curvature"], plane["spline"]["cmrwi"]);
  const std::string dir = (test::scratch() / "rational_obj_report").string();
  const test::Outcome r = run("report " + file + " --out " + dir + " --no-thumbnails");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(test::slurp(dir + "/report.json"));
  // The report reads it as the planar report reads a rounded circle: constant
  // within --constant-tol (default 1e-9), so it passes; with 0 (exact
  // constants only) its exact verdict fails it.
  EXPECT_EQ(doc["splines"][0]["pass"], true);
  EXPECT_EQ(doc["splines"][0]["near_constant"], true);
  EXPECT_LT(doc["splines"][0]["kappa_spread"].get<double>(), 1e-12);
  const test::Outcome exact = run("report " + file + " --out " + dir + " --no-thumbnails --constant-tol 0");
  ASSERT_EQ(exact.code, 0) << exact.err;
  EXPECT_EQ(nlohmann::json::parse(test::slurp(dir + "/report.json"))["splines"][0]["pass"], false);
  const auto range = doc["splines"][0]["kappa_range"];
  EXPECT_NEAR(range[0].get<double>(), 1.0, 1e-12);
  EXPECT_NEAR(range[1].get<double>(), 1.0, 1e-12);
}

void expect_one_line_error(const test::Outcome& r, const std::string& want) {
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find(want), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST(SpaceObjRational, BadWeightsExitTwoWithOneLineNamingTheLine) {
  const std::string dir = (test::scratch() / "rational_obj_bad").string();
  const std::string head = "v 0 0 0 1\nv 1 1 0 ";
  const std::string tail = "\nv 2 0 1 1\ncstype rat bspline\ndeg 2\ncurv 0 1 1 2 3\nparm u 0 0 0 1 1 1\nend\n";
  expect_one_line_error(run("import " + write("w0.obj", head + "0" + tail) + " --out " + dir),
                        "w0.obj:6: curv: vertex 2 (line 2) has weight 0: rational curves need positive weights");
  expect_one_line_error(run("import " + write("wneg.obj", head + "-1.5" + tail) + " --out " + dir),
                        "wneg.obj:6: curv: vertex 2 (line 2) has weight -1.5: rational curves need positive weights");
  EXPECT_FALSE(std::filesystem::exists(dir)) << "nothing is written on bad input";
}

}  // namespace
}  // namespace cmr
