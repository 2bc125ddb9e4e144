// `cmr fix` on space curves (tools/cmd_space_fix.cpp, docs/fix.md "Space
// curves"): the fixed file re-judged by `cmr analyze` (not by the fix's own
// flag), rational curves, nothing to fix, one-line errors with exit code 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "tests/cli_util.hpp"

namespace cmr {
namespace {

using test::run;
using test::write;

const std::string kFailing = std::string(CMR_SOURCE_DIR) + "/examples/space/fig8_lifted.json";
const std::string kMonotone = std::string(CMR_SOURCE_DIR) + "/examples/space/fig8b_lifted.json";

int lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return nlohmann::json::parse(ss.str());
}

void expect_one_line_error(const test::Outcome& r, const std::string& want) {
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(want), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

/// cmr fix IN --out OUT, then cmr analyze OUT: |kappa| monotone, and OUT is
/// IN with exactly the reported point moved to the reported position.
void expect_fixed(const std::string& in, const std::string& options, const std::string& what) {
  const std::string out = write(what + "_fixed.json", "");
  const test::Outcome r = run("fix " + in + " --out " + out + " " + options);
  ASSERT_EQ(r.code, 0) << what << ": " << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_EQ(doc["dimension"], 3);
  EXPECT_EQ(doc["fixed"], true);
  EXPECT_EQ(doc["already"], false);
  ASSERT_EQ(doc["moves"].size(), 1u) << what;
  const auto& m = doc["moves"][0];
  ASSERT_EQ(m["to"].size(), 3u);
  const auto before = read_json(in), after = read_json(out);
  ASSERT_EQ(before["points"].size(), after["points"].size());
  for (std::size_t i = 0; i < before["points"].size(); ++i) {
    if (static_cast<int>(i) == m["point"].get<int>()) {
      EXPECT_EQ(after["points"][i], m["to"]) << what;
    } else {
      EXPECT_EQ(after["points"][i], before["points"][i]) << what << ": point " << i << " moved";
    }
  }
  if (before.contains("weights")) {
    EXPECT_EQ(after["weights"], before["weights"]) << what;
  }
  const test::Outcome a0 = run("analyze " + in);
  ASSERT_EQ(a0.code, 0) << a0.err;
  EXPECT_EQ(nlohmann::json::parse(a0.out)["spline"]["curvature"], "none") << what << ": the input must fail";
  const test::Outcome a = run("analyze " + out);
  ASSERT_EQ(a.code, 0) << a.err;
  const std::string verdict = nlohmann::json::parse(a.out)["spline"]["curvature"];
  EXPECT_TRUE(verdict == "increasing" || verdict == "decreasing") << what << ": analyze says " << verdict;
}

TEST(SpaceFixCli, FailingPolynomialCubicIsFixedAndAnalyzeAgrees) {
  expect_fixed(kFailing, "", "polynomial");
  expect_fixed(kFailing, "--plane xy --points P2", "polynomial_xy");
}

TEST(SpaceFixCli, PngShowsTheRegionAndTheMove) {
  const std::string png = write("space_fix.png", "");
  const test::Outcome r = run("fix " + kFailing + " --png " + png);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["png"], png);
  std::ifstream in(png, std::ios::binary);
  std::string head(8, '\0');
  in.read(head.data(), 8);
  EXPECT_EQ(head, std::string("\x89PNG\r\n\x1a\n", 8));
  in.seekg(0, std::ios::end);
  EXPECT_GT(in.tellg(), 5000);
}

TEST(SpaceFixCli, FailingRationalCubicIsFixedAndAnalyzeAgrees) {
  const std::string in = write("rational.json", R"({"degree": 3, "knots": [0, 1, 2, 3, 4, 5, 6, 7],
    "points": [[1.3, -1.43, 0], [1.05, -0.06, 0.3], [2.15, -1.31, 0.8], [1.97, -3.83, 1.5], [-2.23, -6.95, 2.4],
               [-6.78, -9.78, 3.5]], "weights": [1, 1.2, 0.9, 1.1, 1, 1]})");
  expect_fixed(in, "--points 2 --require cmrwi", "rational");
}

TEST(SpaceFixCli, AMonotoneCurveReportsNothingToFix) {
  const test::Outcome r = run("fix " + kMonotone);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_EQ(doc["already"], true);
  EXPECT_TRUE(doc["moves"].empty());
  EXPECT_EQ(doc["certificate"]["spline"]["curvature"], "decreasing");
}

std::string scratch_dir(const std::string& name) {
  const std::string probe = write(name + ".probe", "");
  return probe.substr(0, probe.rfind('/') + 1) + name;
}

TEST(SpaceFixCli, ReportSuggestsACertifiedFixForAFailingSpaceCurve) {
  const std::string dir = scratch_dir("space_fix_report");
  const test::Outcome r = run("report " + kFailing + " " + kMonotone + " --out " + dir + " --fix-budget 0");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = read_json(dir + "/report.json");
  ASSERT_EQ(doc["splines"].size(), 2u);
  const auto& failing = doc["splines"][0];
  EXPECT_EQ(failing["pass"], false);
  ASSERT_TRUE(failing.contains("certified_fixes"));
  const auto& fix = failing["certified_fixes"][0];
  EXPECT_EQ(fix["check"], "cmrwi");
  ASSERT_EQ(fix["found"], true) << fix.dump();
  ASSERT_EQ(fix["moves"].size(), 1u);
  EXPECT_EQ(fix["failing_segments"], nlohmann::json::array({0, 1}));
  // Apply the reported move to the input from the JSON's numbers alone and
  // re-judge it with cmr analyze.
  auto spline = read_json(kFailing);
  const auto& m = fix["moves"][0];
  EXPECT_EQ(spline["points"][m["point"].get<int>()], m["from"]);
  spline["points"][m["point"].get<int>()] = m["to"];
  const test::Outcome a = run("analyze " + write("report_fixed.json", spline.dump()));
  ASSERT_EQ(a.code, 0) << a.err;
  const std::string verdict = nlohmann::json::parse(a.out)["spline"]["curvature"];
  EXPECT_TRUE(verdict == "increasing" || verdict == "decreasing") << verdict;
  EXPECT_EQ(fix["certificate"]["curvature"], verdict);
  // A passing curve gets no entry; the page says what moves.
  EXPECT_FALSE(doc["splines"][1].contains("certified_fixes"));
  std::ifstream html(dir + "/index.html");
  const std::string page((std::istreambuf_iterator<char>(html)), std::istreambuf_iterator<char>());
  EXPECT_NE(page.find("Smallest certified fix (cmrwi): move P" + std::to_string(m["point"].get<int>())),
            std::string::npos);
  // --no-fixes skips the search.
  const std::string dir2 = scratch_dir("space_fix_report_nofix");
  ASSERT_EQ(run("report " + kFailing + " --out " + dir2 + " --no-fixes").code, 0);
  EXPECT_FALSE(read_json(dir2 + "/report.json")["splines"][0].contains("certified_fixes"));
}

TEST(SpaceFixCli, BadInputExitsTwoWithOneLine) {
  expect_one_line_error(run("fix " + kFailing + " --max-move 0.001"),
                        "fig8_lifted.json: no certified fix within --max-move 0.001 (failing segments: 0, 1;");
  expect_one_line_error(run("fix " + kFailing + " --require each-piece"),
                        "a space curve; its fix takes --require cmr (|kappa| monotone, no zero curvature) or cmrwi");
  expect_one_line_error(run("fix " + kFailing + " --segments 0..1"), "a space curve; --segments is for planar splines");
  expect_one_line_error(run("fix " + kFailing + " --points 9"), "--points: P9 is outside P0..P5");
  expect_one_line_error(run("fix " + kFailing + " --points 5"),
                        "--points: P5 does not act on a failing segment (failing segments: 0, 1)");
  expect_one_line_error(run("fix " + kFailing + " --points x"), "--points: 'x' is neither a point index (K or PK) nor a name of the file's points");
  expect_one_line_error(run("fix " + kFailing + " --plane 0,0,0,1,0,0,2,0,0"),
                        "--plane: U and V are parallel (the plane is degenerate)");
  expect_one_line_error(run("fix " + kFailing + " --plane ab"), "--plane: 'ab' is not a number");
  expect_one_line_error(run("fix " + std::string(CMR_SOURCE_DIR) + "/examples/figures/fig8.json --plane xy"),
                        "a planar spline; --plane is for space curves");
  expect_one_line_error(run("fix " + write("mixed.json", R"({"points":[[0,0,0],[1,1],[2,0,1],[3,1,1]]})")),
                        "points[1] has 2 coordinates but points[0] has 3");
  // Nothing is written when no fix is found.
  const std::string out = write("kept.json", "kept");
  expect_one_line_error(run("fix " + kFailing + " --max-move 0.001 --out " + out), "no certified fix");
  std::ifstream in(out);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "kept");
}

}  // namespace
}  // namespace cmr
