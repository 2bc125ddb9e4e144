// Rational splines with a pole (W = 0 somewhere, spline/bspline.hpp), end to
// end through the cmr binary: analyze reports the `pole` class, report gives a
// page whose gates name the pole and whose pictures hold no inf/NaN, region
// and edit do not crash, and the weight rules' bad input exits 2 with one line.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>

#include "tests/cli_util.hpp"

namespace {

using cmr::test::Outcome;
using cmr::test::run;
using cmr::test::scratch;
using cmr::test::slurp;
using cmr::test::write;
namespace fs = std::filesystem;

// Uniform cubic: W(3) = (1 + 4 (-0.5) + 1) / 6 = 0, the joint of segments 0
// and 1; segment 2 has no pole (tests/region/pole_test.cpp).
const std::string kKnotPole =
    R"({"degree": 3, "knots": [0, 1, 2, 3, 4, 5, 6, 7], "points": [[0, 0], [1, 1.2], [2.2, 1.4], [3.1, 0.3], )"
    R"([4.4, -0.6], [5.5, 0.2]], "weights": [1, 1, -0.5, 1, 1, 1]})";
// A cubic Bezier whose W changes sign twice inside (weights 1, 1, -2, 1).
const std::string kCrossing = R"({"points": [[0, 0], [1, 2], [2, 0], [3, 1]], "weights": [1, 1, -2, 1]})";

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

// Numbers in SVG attributes and JSON never read inf or nan.
void expect_no_non_finite(const std::string& text, const std::string& what) {
  static const std::regex bad(R"([^A-Za-z](nan|inf|NaN|Infinity)[^A-Za-z])");
  std::smatch m;
  EXPECT_FALSE(std::regex_search(text, m, bad)) << what << ": " << m.str();
}

TEST(PoleCli, AnalyzeReportsThePoleClass) {
  const std::string file = write("knot_pole.json", kKnotPole);
  const Outcome r = run("analyze " + file);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  ASSERT_EQ(doc["segments"].size(), 3u);
  EXPECT_EQ(doc["segments"][0]["class"], "pole");
  EXPECT_EQ(doc["segments"][0]["poles"], nlohmann::json::parse("[3.0]"));
  EXPECT_EQ(doc["segments"][0]["curvature"], "non-monotone");
  EXPECT_EQ(doc["segments"][1]["class"], "pole");
  EXPECT_EQ(doc["segments"][2]["class"], "regular");
  EXPECT_FALSE(doc["segments"][2].contains("poles"));
  EXPECT_EQ(doc["joints"][0]["pole"], true);
  EXPECT_TRUE(doc["joints"][0]["kappa_left"].is_null());
  EXPECT_FALSE(doc["joints"][1].contains("pole"));  // W(4) = 3/4
  EXPECT_TRUE(doc["joints"][1]["kappa_left"].is_number());
  EXPECT_EQ(doc["spline"]["pole"], true);
  EXPECT_EQ(doc["spline"]["cmrwi"], "none");
  EXPECT_EQ(doc["spline"]["cmr"], "none");
  // Two crossings inside one segment: both listed, inside (0, 1).
  const Outcome c = run("analyze " + write("crossing.json", kCrossing));
  ASSERT_EQ(c.code, 0) << c.err;
  const auto cd = nlohmann::json::parse(c.out);
  ASSERT_EQ(cd["segments"][0]["poles"].size(), 2u);
  EXPECT_GT(cd["segments"][0]["poles"][0].get<double>(), 0.0);
  EXPECT_LT(cd["segments"][0]["poles"][1].get<double>(), 1.0);
  // A polynomial spline's output has no pole keys at all.
  const Outcome p = run("analyze " + std::string(CMR_SOURCE_DIR) + "/examples/uniform.json");
  ASSERT_EQ(p.code, 0) << p.err;
  EXPECT_EQ(p.out.find("pole"), std::string::npos);
}

TEST(PoleCli, ReportGatesNameThePoleAndPicturesStayFinite) {
  const fs::path out = scratch() / "pole_report";
  fs::remove_all(out);
  const std::string a = write("knot_pole.json", kKnotPole), b = write("crossing.json", kCrossing);
  const Outcome r = run("report " + a + " " + b + " --out " + out.string() +
                        " --require cmrwi,curvature-extrema-at-nodes,no-inflection --backend cpu --region-size 24");
  ASSERT_EQ(r.code, 1) << r.err;  // the gates fail, nothing is invalid
  const auto doc = read_json(out / "report.json");
  const std::string json_text = slurp(out / "report.json");
  const std::string html = slurp(out / "index.html");
  expect_no_non_finite(html, "index.html");
  expect_no_non_finite(json_text, "report.json");
  EXPECT_NE(html.find("segment 0 has a pole at t≈3"), std::string::npos);
  EXPECT_NE(html.find("segment 0 has a pole at t≈0.449"), std::string::npos);
  const auto& s0 = doc["splines"][0];
  EXPECT_EQ(s0["status"], "fail");
  EXPECT_EQ(s0["curvature"]["pole"], true);
  EXPECT_TRUE(s0["curvature"]["min"]["kappa"].is_null());
  bool named = false;
  for (const auto& gate : s0["gates"])
    for (const auto& v : gate["violations"]) named = named || v["message"] == "segment 1 has a pole at t≈3";
  EXPECT_TRUE(named) << s0["gates"].dump();
  // The curve picture of the crossing (the second section) is broken at its
  // poles: one segment, several subpaths.
  const std::string curve = "stroke=\"#111\" stroke-width=\"2\" d=\"";
  const auto at = html.find(curve, html.find(curve) + 1);
  ASSERT_NE(at, std::string::npos);
  const std::string path = html.substr(at + curve.size(), html.find('"', at + curve.size()) - at - curve.size());
  EXPECT_GE(std::count(path.begin(), path.end(), 'M'), 2) << path;
}

TEST(PoleCli, RegionAndKnotOperationsDoNotCrash) {
  const std::string file = write("knot_pole.json", kKnotPole);
  const fs::path png = scratch() / "pole_region.png";
  const Outcome all = run("region " + file + " --point 3 --size 48x48 --backend cpu --png " + png.string());
  ASSERT_EQ(all.code, 0) << all.err;
  const auto doc = nlohmann::json::parse(all.out);
  EXPECT_EQ(doc["points"][0]["counts"]["none"], 48 * 48);  // a judged pole: every pixel fails
  EXPECT_GT(fs::file_size(png), 0u);
  EXPECT_NE(all.err.find("has a pole (W = 0 at t = "), std::string::npos) << all.err;  // said why
  const Outcome part = run("region " + file + " --point 4 --segments 2..2 --size 48x48 --backend cpu");
  ASSERT_EQ(part.code, 0) << part.err;
  EXPECT_EQ(part.err.find("has a pole"), std::string::npos) << part.err;  // the pole is outside the judged span
  EXPECT_LT(nlohmann::json::parse(part.out)["points"][0]["counts"]["none"], 48 * 48);
  // Inserting t = 0.5 into (1, -1, 1) makes a new weight 0 with a point at
  // infinity, which (x, y, w) files cannot hold: one line, exit 2.
  const Outcome k = run("knots " + write("touch.json", R"({"points": [[0, 0], [1, 2], [2, 0]], "weights": [1, -1, 1]})") +
                        " insert 0.5");
  EXPECT_EQ(k.code, 2);
  EXPECT_TRUE(k.out.empty());
  EXPECT_EQ(k.err.find('\n'), k.err.size() - 1) << k.err;
  EXPECT_NE(k.err.find("weight 0 and lie at infinity"), std::string::npos) << k.err;
  // Elevating keeps the curve and its pole.
  const Outcome e = run("knots " + file + " elevate");
  ASSERT_EQ(e.code, 0) << e.err;
  const Outcome ea = run("analyze " + write("elevated.json", e.out));
  ASSERT_EQ(ea.code, 0) << ea.err;
  EXPECT_EQ(nlohmann::json::parse(ea.out)["spline"]["pole"], true);
}

TEST(PoleCli, AllNegativeWeightsAreTheSameCurve) {
  const std::string neg = write("negative.json", R"({"points": [[3, 0], [3, 2], [0, 2]], "weights": [-2, -1, -1]})");
  const std::string pos = write("positive.json", R"({"points": [[3, 0], [3, 2], [0, 2]], "weights": [2, 1, 1]})");
  const Outcome a = run("analyze " + neg), b = run("analyze " + pos);
  ASSERT_EQ(a.code, 0) << a.err;
  EXPECT_EQ(a.out, b.out);
}

TEST(PoleCli, EditLoadsAPoleSplineWithoutCrashing) {
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) GTEST_SKIP() << "xvfb-run is not installed";
  const fs::path dir = scratch() / "pole_edit";
  fs::create_directories(dir);
  const std::string file = write("knot_pole_edit.json", kKnotPole);
  const std::string script = write("pole_edit_script.txt", "drag 3 3.5 -0.2 6\nsave " + (dir / "saved.json").string() + "\n");
  // -f: an X authority file of the run's own (edit_test.cpp's kXvfbAuth says why).
  const std::string line = "xvfb-run -a -f \"$(mktemp)\" -s '-screen 0 800x600x24' " + std::string(CMR_BINARY) + " edit " + file +
                           " --size 320x240 --script " + script + " --screenshot " + (dir / "shot.png").string() +
                           " >" + (dir / "out").string() + " 2>" + (dir / "err").string();
  const int status = std::system(line.c_str());
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  ASSERT_EQ(code, 0) << slurp(dir / "err");
  EXPECT_EQ(read_json(dir / "saved.json")["weights"], nlohmann::json::parse("[1, 1, -0.5, 1, 1, 1]"));
  EXPECT_GT(fs::file_size(dir / "shot.png"), 0u);
}

}  // namespace
