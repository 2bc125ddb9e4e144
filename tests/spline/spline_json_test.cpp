#include "spline/spline_json.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "spline/errors.hpp"
#include "spline/limits.hpp"

namespace cmr {
namespace {

using nlohmann::json;

TEST(SplineJson, ReadsBSplineAndRoundTrips) {
  const json doc = json::parse(R"({"name":"u","degree":3,"knots":[0,1,2,3,4,5,6,7],
      "points":[[0,0],[1,2],[3,3],[5,2.5],[6.5,1],[7,-1]]})");
  const BSpline s = spline_from_json(doc);
  EXPECT_EQ(s.name(), "u");
  EXPECT_EQ(s.degree(), 3);
  EXPECT_EQ(s.points()[3], Vec2(5, 2.5));
  const BSpline t = spline_from_json(spline_to_json(s));
  EXPECT_EQ(t.knots(), s.knots());
  EXPECT_EQ(t.points(), s.points());
}

TEST(SplineJson, WithoutKnotsTheFileIsOneBezierCurve) {
  const BSpline s = spline_from_json(json::parse(R"({"points":[[0,0],[1,1],[2,0],[3,1]]})"));
  EXPECT_EQ(s.degree(), 3);
  EXPECT_EQ(s.knots(), (std::vector<double>{0, 0, 0, 1, 1, 1}));
}

struct BadDoc {
  const char* name;
  const char* text;
  const char* message_part;
};

// Printed by its name, so the test's name (ctest lists GetParam()) is stable
// and readable, not the struct's bytes.
void PrintTo(const BadDoc& c, std::ostream* os) { *os << c.name; }

class SplineJsonRejects : public ::testing::TestWithParam<BadDoc> {};

TEST_P(SplineJsonRejects, NamingFieldAndIndex) {
  try {
    (void)spline_from_json(json::parse(GetParam().text));
    FAIL() << "accepted " << GetParam().text;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(GetParam().message_part), std::string::npos) << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(
    Table, SplineJsonRejects,
    ::testing::Values(BadDoc{"not_object", "[1,2]", "not a JSON object"},
                      BadDoc{"no_points", R"({"degree":3})", "points: missing"},
                      BadDoc{"point_not_pair", R"({"points":[[0,0],[1],[2,0]]})", "points[1] is not an [x, y]"},
                      BadDoc{"point_string", R"({"points":[[0,0],[1,"a"],[2,0]]})", "points[1][1] is not a number"},
                      BadDoc{"degree_float", R"({"degree":2.5,"knots":[0,1],"points":[[0,0],[1,1],[2,0]]})",
                             "degree: not an integer"},
                      BadDoc{"degree_mismatch", R"({"degree":2,"points":[[0,0],[1,1],[2,0],[3,3]]})",
                             "has degree 3, not 2"},
                      BadDoc{"knots_no_degree", R"({"knots":[0,0,1,1],"points":[[0,0],[1,1],[2,0]]})",
                             "degree: missing"},
                      BadDoc{"knot_string", R"({"degree":2,"knots":[0,"x",1,1],"points":[[0,0],[1,1],[2,0]]})",
                             "knots[1] is not a number"},
                      BadDoc{"unknown_field", R"({"pts":[],"points":[[0,0],[1,1],[2,0]]})", "unknown field \"pts\""},
                      BadDoc{"name_number", R"({"name":3,"points":[[0,0],[1,1],[2,0]]})", "name: not a string"},
                      BadDoc{"conventional_knots",
                             R"({"degree":2,"knots":[0,0,0,1,1,1],"points":[[0,0],[1,1],[2,0]]})",
                             "knots: 6 values is the conventional (full) knot vector for 3 points of degree 2; drop "
                             "the first and the last knot (cmr uses polar form), or convert the file with `cmr knots FILE "
                             "conventional clamp`"}),  // conventional: a field (spline/fields.hpp), --conventional in cmr
    [](const auto& p) { return std::string(p.param.name); });

TEST(SplineJson, ConventionalKnotsDropTheirEndKnotsWhenAskedTo) {
  const json doc = json::parse(R"({"degree":3,"knots":[-1,0,1,2,3,4,5,6,7,8],
      "points":[[0,0],[1,2],[3,3],[5,2.5],[6.5,1],[7,-1]]})");
  const BSpline s = spline_from_json(doc, {.conventional = true});
  EXPECT_EQ(s.knots(), (std::vector<double>{0, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(s.point_count(), 6);
  // A Bezier file has no knots to drop and reads the same either way.
  const json bezier = json::parse(R"({"points":[[0,0],[1,1],[2,0]]})");
  EXPECT_EQ(spline_from_json(bezier, {.conventional = true}).knots(), spline_from_json(bezier).knots());
  // With the option, a polar vector is the wrong count, and the message says which count is expected.
  const json polar = json::parse(R"({"degree":3,"knots":[0,1,2,3,4,5,6,7],
      "points":[[0,0],[1,2],[3,3],[5,2.5],[6.5,1],[7,-1]]})");
  try {
    (void)spline_from_json(polar, {.conventional = true});
    FAIL() << "a polar vector was read as conventional";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("points + degree + 1 = 10 values"), std::string::npos) << e.what();
  }
}

// read_input_file: regular files only, opened without blocking, size-limited.
std::filesystem::path input_scratch(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("cmr_spline_json_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto p = dir / name;
  std::filesystem::remove(p);
  return p;
}

std::string input_error(const std::filesystem::path& p) {
  try {
    (void)read_input_file(p);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ReadInputFile, ReadsARegularFileWhole) {
  const auto p = input_scratch("plain.json");
  const std::string text = std::string(100000, 'x') + "\0tail";  // larger than any first guess, with a NUL
  std::ofstream(p, std::ios::binary) << text;
  EXPECT_EQ(read_input_file(p), text);
  std::ofstream(p, std::ios::binary | std::ios::trunc);
  EXPECT_EQ(read_input_file(p), "");
}

// A FIFO is read (issue 40: pipes), but one without a writer gives nothing
// and is refused at once, never waited on.
TEST(ReadInputFile, AFifoWithoutWriterIsRefusedAtOnce) {
  const auto p = input_scratch("fifo.json");
  ASSERT_EQ(::mkfifo(p.c_str(), 0600), 0);
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(input_error(p), p.string() + ": empty (nothing came through the FIFO)");
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(5));
}

TEST(ReadInputFile, DevicesFoldersAndMissingFilesAreInputErrors) {
  EXPECT_EQ(input_error("/dev/zero"), "/dev/zero: not a regular file (a character device)");
  EXPECT_EQ(input_error("/"), "/: not a regular file (a folder)");
  EXPECT_EQ(input_error("/nonexistent/x.json"), "/nonexistent/x.json: cannot open the file (No such file or directory)");
}

TEST(ReadInputFile, FilesAboveTheLimitAreRefusedWithoutReadingThem) {
  const auto p = input_scratch("huge.json");
  std::ofstream(p) << "{}";
  std::filesystem::resize_file(p, kMaxInputBytes + 1);  // sparse
  EXPECT_EQ(input_error(p), p.string() + ": larger than the 64 MiB input limit");
  std::filesystem::resize_file(p, kMaxInputBytes);  // exactly the limit is accepted
  EXPECT_EQ(read_input_file(p).size(), kMaxInputBytes);
  std::filesystem::remove(p);
}

TEST(SplineJson, WeightsRoundTripAndAreValidated) {
  const nlohmann::json doc = nlohmann::json::parse(
      R"({"degree": 2, "knots": [0, 0, 1, 1], "points": [[1, 0], [1, 1], [0, 1]], "weights": [2, 1, 1]})");
  const BSpline s = spline_from_json(doc);
  ASSERT_TRUE(s.is_rational());
  EXPECT_EQ(s.weights(), (std::vector<double>{2, 1, 1}));
  EXPECT_EQ(spline_to_json(s)["weights"], doc["weights"]);
  EXPECT_EQ(spline_from_json(spline_to_json(s)).weights(), s.weights());
  // A Bezier file (no knots) takes weights too.
  EXPECT_TRUE(spline_from_json(nlohmann::json::parse(R"({"points": [[1, 0], [1, 1], [0, 1]], "weights": [1, 0.5, 1]})"))
                  .is_rational());
  // A polynomial spline is written without weights.
  EXPECT_FALSE(spline_to_json(BSpline::bezier({{0, 0}, {1, 1}, {2, 0}})).contains("weights"));
  const auto message = [](const char* text) {
    try {
      (void)spline_from_json(nlohmann::json::parse(text));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message(R"({"points": [[1, 0], [1, 1], [0, 1]], "weights": [1, 1]})"),
            "weights: one weight per control point is needed: 3 points, 2 weights");
  EXPECT_EQ(message(R"({"points": [[1, 0], [1, 1], [0, 1]], "weights": [1, "x", 1]})"), "weights[1] is not a number");
  EXPECT_EQ(message(R"({"points": [[1, 0], [1, 1], [0, 1]], "weights": 2})"), "weights: not an array of numbers");
  // Any finite weights, not all 0 (a zero or sign change of W is a pole, analyze.hpp).
  EXPECT_EQ(message(R"({"points": [[1, 0], [1, 1], [0, 1]], "weights": [1, -1, 1]})"), "accepted");
  EXPECT_EQ(message(R"({"points": [[1, 0], [1, 1], [0, 1]], "weights": [0, 0, 0]})"),
            "weights: every weight is 0; at least one must be non-zero");
  // All negative: stored negated (the same curve), and written so.
  EXPECT_EQ(spline_to_json(spline_from_json(nlohmann::json::parse(
                R"({"points": [[1, 0], [1, 1], [0, 1]], "weights": [-2, -1, -1]})")))["weights"],
            nlohmann::json::parse("[2, 1, 1]"));
}

}  // namespace
}  // namespace cmr
