// cmr fix: the JSON it prints, the fixed spline it writes (atomically, and
// judged again by cmr analyze), and bad input: exit 2 with one line naming
// the reason and no output file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "tests/cli_util.hpp"

namespace cmr::test {
namespace {

const std::string kFig8 = std::string(CMR_SOURCE_DIR) + "/examples/figures/fig8.json";

/// The CMR Bezier (0,0) (2,0) (3,0.5) (3.3,1.2) split at t = 1/2 (a G1 and G2
/// joint at a knot of multiplicity 3) with P5 moved: segment 1 fails CMR.
const char* kSplit = R"({"degree": 3, "knots": [0,0,0,1,1,1,2,2,2],
  "points": [[0,0],[1,0],[1.75,0.125],[2.2875,0.3375],[2.825,0.55],[3.35,0.65],[3.3,1.2]]})";
/// The same with the end point moved instead: the joint stays G2.
const char* kSplitEnd = R"({"degree": 3, "knots": [0,0,0,1,1,1,2,2,2],
  "points": [[0,0],[1,0],[1.75,0.125],[2.2875,0.3375],[2.825,0.55],[3.15,0.85],[3.6,0.9]]})";

int lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

TEST(FixCli, Fig8FixedByOnePointAndWrittenOut) {
  const fs::path out = scratch() / "fig8_fixed.json";
  fs::remove(out);
  const Outcome r = run("fix " + kFig8 + " --require cmrwi --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_EQ(doc["require"], "cmrwi");
  EXPECT_TRUE(doc["fixed"].get<bool>());
  EXPECT_FALSE(doc["already"].get<bool>());
  ASSERT_EQ(doc["moves"].size(), 1u);
  const auto& m = doc["moves"][0];
  const double dx = m["to"][0].get<double>() - m["from"][0].get<double>();
  const double dy = m["to"][1].get<double>() - m["from"][1].get<double>();
  EXPECT_NEAR(std::hypot(dx, dy), m["distance"].get<double>(), 1e-12);
  EXPECT_TRUE(doc["certificate"]["holds"].get<bool>());
  EXPECT_NE(doc["certificate"]["cmrwi"], "none");
  // The written spline is the fixed one: analyze agrees with the certificate.
  const Outcome a = run("analyze " + out.string());
  ASSERT_EQ(a.code, 0) << a.err;
  EXPECT_EQ(nlohmann::json::parse(a.out)["spline"]["cmrwi"], doc["certificate"]["cmrwi"]);
  const auto fixed = nlohmann::json::parse(slurp(out));
  const int k = m["point"].get<int>();
  EXPECT_EQ(fixed["points"][k], m["to"]);
}

TEST(FixCli, BeforeAfterPicture) {
  const fs::path png = scratch() / "fix.png", out = scratch() / "fix_out.json";
  fs::remove(png), fs::remove(out);
  const Outcome r = run("fix " + kFig8 + " --require cmrwi --png " + png.string() + " --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string bytes = slurp(png);
  ASSERT_GT(bytes.size(), 8u);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
  EXPECT_TRUE(fs::exists(out));
  EXPECT_EQ(nlohmann::json::parse(r.out)["png"], png.string());
}

TEST(FixCli, SeveralPointsKeepG1) {
  const Outcome r = run("fix " + write("split.json", kSplit) + " --points 3,4,5 --keep g1");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_EQ(doc["keep"], "g1");
  EXPECT_EQ(doc["tie_joints"], nlohmann::json::parse("[1]"));
  EXPECT_TRUE(doc["certificate"]["joints"][0]["g1"].get<bool>());
  EXPECT_TRUE(doc["certificate"]["ties"].get<bool>());
}

TEST(FixCli, KeepG2KeepsTheJointG2) {
  const Outcome r = run("fix " + write("split_end.json", kSplitEnd) + " --keep g2 --require cmr");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_TRUE(doc["certificate"]["joints"][0]["g2"].get<bool>());
}

TEST(FixCli, AlreadyPassingExits0WithNoMove) {
  const Outcome r = run("fix " + write("ok.json", R"({"degree":3,"knots":[0,0,0,1,1,1],"points":[[0,0],[2,0],[3,0.5],[3.3,1.2]]})"));
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_TRUE(doc["already"].get<bool>());
  EXPECT_TRUE(doc["moves"].empty());
}

/// Each bad input: exit 2, one stderr line with the reason, no --out file.
/// --segments: only the judged range must meet the requirement. The split
/// Bezier fails CMR on segment 1 only: judged on segment 0 nothing moves; on
/// segment 1 the fix is certified there (the JSON's segments).
TEST(FixCli, SegmentsJudgeOnlyTheirRange) {
  const std::string split = write("split_seg.json", kSplit);
  const Outcome zero = run("fix " + split + " --segments 0..0");
  ASSERT_EQ(zero.code, 0) << zero.err;
  const auto z = nlohmann::json::parse(zero.out);
  EXPECT_TRUE(z["already"].get<bool>());
  EXPECT_EQ(z["segments"], nlohmann::json::array({0, 0}));
  const Outcome one = run("fix " + split + " --segments 1..1");
  ASSERT_EQ(one.code, 0) << one.err;
  const auto o = nlohmann::json::parse(one.out);
  EXPECT_TRUE(o["fixed"].get<bool>());
  EXPECT_FALSE(o["moves"].empty());
  EXPECT_EQ(o["segments"], nlohmann::json::array({1, 1}));
}

/// The gates' requirements from the command line: g2 at the smooth joint.
TEST(FixCli, G2AtSmoothNodes) {
  const std::string split = write("split_g2.json", kSplit);
  const Outcome r = run("fix " + split + " --require g2-at-smooth-nodes:0.01");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  EXPECT_EQ(doc["require"], "g2-at-smooth-nodes:0.01");
  EXPECT_TRUE(doc["fixed"].get<bool>());
  EXPECT_TRUE(doc["certificate"]["holds"].get<bool>());
}

TEST(FixCli, BadInputExits2WithOneLineAndNoFile) {
  const fs::path out = scratch() / "never.json";
  fs::remove(out);
  const std::string split = write("split2.json", kSplit);
  const struct {
    std::string args, reason;
  } cases[] = {
      {"fix " + split + " --max-move 1e-6", "no certified fix within --max-move"},
      {"fix " + split + " --points 1", "P1 does not act on a failing segment (failing: 1)"},
      {"fix " + split + " --points 9", "--points: P9 is outside 0..6"},
      {"fix " + split + " --points 4,x", "--points: 'x' is neither a point index (K or PK) nor a name of the file's points"},
      {"fix " + split + " --require cmq", "--require: 'cmq' is not cmrwi, cmr"},
      {"fix " + split + " --require split:7", "split 7 is outside 1..1"},
      {"fix " + split + " --keep g3", "--keep"},
      {"fix " + split + " --segments 0..5", "segments 0..5"},
      {"fix " + split + " --segments x", "--segments"},
      {"fix " + split + " --require g2-at-smooth-nodes:x", "needs a relative tolerance"},
      {"fix " + split + " --max-move -1", "--max-move: -1"},
      {"fix " + write("bad.json", R"({"degree":3,"knots":[0,0,0,1,1],"points":[[0,0],[1,0],[2,1],[3,3]]})"), "knots"},
      {"fix " + write("notjson.json", "{"), "notjson.json"},
  };
  for (const auto& c : cases) {
    const Outcome r = run(c.args + " --out " + out.string());
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.err;
    EXPECT_EQ(lines(r.err), 1) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.reason), std::string::npos) << c.args << "\nstderr: " << r.err;
    EXPECT_TRUE(r.out.empty()) << c.args;
    EXPECT_FALSE(fs::exists(out)) << c.args;
  }
  // An --out folder that does not exist: refused before any work.
  const Outcome r = run("fix " + split + " --out " + (scratch() / "no_such_dir" / "f.json").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(lines(r.err), 1) << r.err;
}

}  // namespace
}  // namespace cmr::test
