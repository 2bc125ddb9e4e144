// End-to-end tests of the cmr command: exit codes, one-line errors, outputs.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "tests/cli_util.hpp"

#include <nlohmann/json.hpp>

namespace {

using cmr::test::Outcome;
using cmr::test::run;
using cmr::test::write;

const std::string kSixPoints = R"("points":[[0,0],[1,2],[3,3],[5,2.5],[6.5,1],[7,-1]])";

struct BadInput {
  const char* name;
  std::string args;        // may contain FILE, replaced by the written file
  std::string file_text;   // empty: no file written
  const char* message_part;
};

// Printed by its name, so the test's name (ctest lists GetParam()) is stable
// and readable, not the struct's bytes.
void PrintTo(const BadInput& c, std::ostream* os) { *os << c.name; }

class CliRejects : public ::testing::TestWithParam<BadInput> {};

TEST_P(CliRejects, WithExit2AndOneLineNamingTheProblem) {
  const BadInput& c = GetParam();
  std::string args = c.args;
  if (!c.file_text.empty()) {
    const std::string path = write(std::string(c.name) + ".json", c.file_text);
    args.replace(args.find("FILE"), 4, path);
  }
  const Outcome r = run(args);
  EXPECT_EQ(r.code, 2) << c.name << ": " << r.err;
  EXPECT_TRUE(r.out.empty()) << c.name << " printed to stdout: " << r.out;
  ASSERT_FALSE(r.err.empty()) << c.name;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << c.name << ": not one line: " << r.err;
  EXPECT_NE(r.err.find(c.message_part), std::string::npos) << c.name << ": " << r.err;
}

INSTANTIATE_TEST_SUITE_P(
    Table, CliRejects,
    ::testing::Values(
        BadInput{"malformed_json", "analyze FILE", "{\"points\": [[0,0],", "malformed JSON"},
        BadInput{"empty_file", "analyze FILE", " ", "malformed JSON"},
        BadInput{"missing_file", "analyze /nonexistent/spline.json", "", "cannot open"},
        BadInput{"wrong_knot_count", "analyze FILE", "{\"degree\":3,\"knots\":[0,1,2,3,4,5,6]," + kSixPoints + "}",
                 "8 knots (got 7)"},
        BadInput{"decreasing_knots", "segments FILE",
                 "{\"degree\":3,\"knots\":[0,1,2,3,2.5,5,6,7]," + kSixPoints + "}", "knots[4] (2.5) is smaller"},
        BadInput{"overflowing_number", "analyze FILE", "{\"points\":[[0,0],[1,1e999],[2,0]]}", "overflow"},
        BadInput{"nan_literal", "analyze FILE", "{\"points\":[[0,0],[1,NaN],[2,0]]}", "malformed JSON"},
        BadInput{"point_string", "analyze FILE", "{\"points\":[[0,0],[1,\"y\"],[2,0]]}", "points[1][1]"},
        BadInput{"degree_one", "analyze FILE", "{\"degree\":1,\"knots\":[0]," + kSixPoints + "}", "degree"},
        BadInput{"multiplicity", "analyze FILE", "{\"degree\":3,\"knots\":[0,1,1,1,1,5,6,7]," + kSixPoints + "}",
                 "multiplicity"},
        BadInput{"unknown_field", "analyze FILE", "{\"colour\":1," + kSixPoints + "}", "unknown field"},
        BadInput{"knots_without_degree", "analyze FILE", "{\"knots\":[0,1,2,3,4,5,6,7]," + kSixPoints + "}",
                 "degree: missing"},
        BadInput{"split_zero", "analyze FILE --split 0", "{\"degree\":3,\"knots\":[0,1,2,3,4,5,6,7]," + kSixPoints + "}",
                 "split 0 is outside 1..2"},
        BadInput{"split_too_big", "analyze FILE --split 3",
                 "{\"degree\":3,\"knots\":[0,1,2,3,4,5,6,7]," + kSixPoints + "}", "split 3 is outside"},
        BadInput{"splits_not_increasing", "analyze FILE --split 2,1",
                 "{\"degree\":3,\"knots\":[0,1,2,3,4,5,6,7]," + kSixPoints + "}", "split joints must increase"},
        BadInput{"segments_past_the_end", "analyze FILE --segments 0..3",
                 "{\"degree\":3,\"knots\":[0,1,2,3,4,5,6,7]," + kSixPoints + "}", "the curve has segments 0..2"},
        BadInput{"segments_reversed", "analyze FILE --segments 2..1",
                 "{\"degree\":3,\"knots\":[0,1,2,3,4,5,6,7]," + kSixPoints + "}", "after the last"},
        BadInput{"segments_malformed", "analyze FILE --segments 1-2",
                 "{\"degree\":3,\"knots\":[0,1,2,3,4,5,6,7]," + kSixPoints + "}", "--segments: expected A..B"},
        BadInput{"split_outside_segments", "analyze FILE --segments 1..2 --split 1",
                 "{\"degree\":3,\"knots\":[0,1,2,3,4,5,6,7]," + kSixPoints + "}", "split 1 is outside 2..2"},
        // analyze has no --conventional: the advice names the command that has it.
        BadInput{"conventional_knots", "analyze FILE",
                 "{\"degree\":3,\"knots\":[0,0,0,0,1,2,3,3,3,3]," + kSixPoints + "}",
                 "convert the file with `cmr knots FILE --conventional clamp`"},
        BadInput{"depth_out_of_range", "analyze FILE --depth 99", "{" + kSixPoints + "}", "--depth"},
        BadInput{"mode_unknown", "analyze FILE --mode bogus", "{" + kSixPoints + "}", "--mode"},
        BadInput{"weights_all_zero", "analyze FILE", "{\"weights\":[0,0,0,0,0,0]," + kSixPoints + "}",
                 "weights: every weight is 0; at least one must be non-zero"},
        BadInput{"weight_not_a_number", "analyze FILE", "{\"weights\":[1,\"NaN\",1,1,1,1]," + kSixPoints + "}",
                 "weights[1] is not a number"},
        BadInput{"weight_infinite", "analyze FILE", "{\"weights\":[1,1e999,1,1,1,1]," + kSixPoints + "}",
                 "number overflow parsing '1e999'"},
        BadInput{"weights_count", "region FILE --point 0 --backend cpu", "{\"weights\":[1,2]," + kSixPoints + "}",
                 "one weight per control point"},
        BadInput{"unknown_command", "frobnicate", "", "unknown command 'frobnicate'"},
        BadInput{"no_file_argument", "analyze", "", "FILE"}),
    [](const auto& p) { return std::string(p.param.name); });

TEST(Cli, SegmentsOnThePaperKnotVectors) {
  const Outcome u = run("segments " + std::string(CMR_SOURCE_DIR) + "/examples/uniform.json");
  ASSERT_EQ(u.code, 0) << u.err;
  const auto doc = nlohmann::json::parse(u.out);
  ASSERT_EQ(doc["segments"].size(), 3u);
  EXPECT_EQ(doc["segments"][0]["interval"], nlohmann::json::parse("[2.0, 3.0]"));
  EXPECT_EQ(doc["segments"][2]["interval"], nlohmann::json::parse("[4.0, 5.0]"));
  EXPECT_EQ(doc["segments"][1]["points"].size(), 4u);
  const Outcome c = run("segments " + std::string(CMR_SOURCE_DIR) + "/examples/clamped.json");
  ASSERT_EQ(c.code, 0) << c.err;
  const auto cd = nlohmann::json::parse(c.out);
  EXPECT_EQ(cd["segments"][0]["interval"], nlohmann::json::parse("[0.0, 1.0]"));
  std::ifstream in(std::string(CMR_SOURCE_DIR) + "/examples/clamped.json");
  const auto file = nlohmann::json::parse(in);
  EXPECT_EQ(cd["segments"][0]["points"][0], file["points"][0]);  // clamped: interpolates P0
}

TEST(Cli, RationalCircleIsConstantAndItsSegmentsCarryWeights) {
  const std::string circle = std::string(CMR_SOURCE_DIR) + "/examples/rational/circle.json";
  const Outcome a = run("analyze " + circle);
  ASSERT_EQ(a.code, 0) << a.err;
  const auto doc = nlohmann::json::parse(a.out);
  ASSERT_EQ(doc["segments"].size(), 4u);
  for (const auto& seg : doc["segments"]) EXPECT_EQ(seg["curvature"], "constant") << seg;
  for (const auto& j : doc["joints"]) EXPECT_EQ(j["jump"], "none") << j;
  const Outcome s = run("segments " + circle);
  ASSERT_EQ(s.code, 0) << s.err;
  const auto segs = nlohmann::json::parse(s.out)["segments"];
  ASSERT_EQ(segs.size(), 4u);
  EXPECT_EQ(segs[1]["weights"], nlohmann::json({1.0, 0.5, 0.5}));
  // Knot operations keep a rational curve rational: its file has weights.
  const Outcome e = run("knots " + circle + " elevate");
  ASSERT_EQ(e.code, 0) << e.err;
  EXPECT_EQ(nlohmann::json::parse(e.out)["weights"].size(), 13u);
}

TEST(Cli, AnalyzePrintsSegmentsAndVerdicts) {
  const Outcome r = run("analyze " + std::string(CMR_SOURCE_DIR) + "/examples/clamped.json --split 2 --depth 8");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  ASSERT_EQ(doc["segments"].size(), 3u);
  for (const auto& s : doc["segments"]) {
    EXPECT_TRUE(s.contains("curvature") && s.contains("inflection") && s.contains("depth"));
    EXPECT_LE(s["depth"].get<int>(), 8);
  }
  EXPECT_TRUE(doc["spline"].contains("cmrwi"));
  EXPECT_TRUE(doc["spline"].contains("cmr"));
  EXPECT_TRUE(doc["spline"].contains("split"));
}

TEST(Cli, AnalyzeSegmentsReportsTheOthersAsIgnored) {
  const std::string file = std::string(CMR_SOURCE_DIR) + "/examples/figures/fig8b.json";
  const Outcome all = run("analyze " + file);
  const Outcome r = run("analyze " + file + " --segments 1..2");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto full = nlohmann::json::parse(all.out), doc = nlohmann::json::parse(r.out);
  ASSERT_EQ(doc["segments"].size(), 3u);
  EXPECT_EQ(doc["segments"][0]["curvature"], "ignored");
  EXPECT_EQ(doc["segments"][0]["inflection"], "ignored");
  EXPECT_FALSE(doc["segments"][0].contains("depth"));
  EXPECT_EQ(doc["segments"][1], full["segments"][1]);  // judged segments: as without --segments
  EXPECT_EQ(doc["segments"][2], full["segments"][2]);
  EXPECT_EQ(doc["joints"][0]["ignored"], true);  // joint 1 is the range's start
  EXPECT_FALSE(doc["joints"][1].contains("ignored"));
  EXPECT_EQ(doc["spline"]["segments"], nlohmann::json::parse("[1, 2]"));
  EXPECT_FALSE(full["spline"].contains("segments"));
}

TEST(Cli, AnalyzeSeveralJointsGivesTheAlternationAndTheGroups) {
  const std::string file = std::string(CMR_SOURCE_DIR) + "/examples/figures/fig8b.json";
  const Outcome r = run("analyze " + file + " --split 1,2");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(r.out);
  ASSERT_TRUE(doc["spline"].contains("alternation"));
  EXPECT_FALSE(doc["spline"].contains("split"));
  const auto& groups = doc["spline"]["groups"];
  ASSERT_EQ(groups.size(), 3u);
  // One segment per group: each group's direction is its segment's curvature.
  bool alternate = true;
  for (int g = 0; g < 3; ++g) {
    EXPECT_EQ(groups[g]["segments"], nlohmann::json::array({g, g}));
    const std::string c = doc["segments"][g]["curvature"], d = groups[g]["direction"];
    EXPECT_EQ(d, c == "non-monotone" ? "none" : c) << "group " << g;
    alternate = alternate && (c == "increasing" || c == "decreasing") &&
                (g == 0 || doc["segments"][g]["curvature"] != doc["segments"][g - 1]["curvature"]);
  }
  const std::string first = doc["segments"][0]["curvature"];
  EXPECT_EQ(doc["spline"]["alternation"], alternate ? (first == "increasing" ? "inc-first" : "dec-first") : "fail");
}

}  // namespace
