// End-to-end tests of `cmr knots`: every operation prints a spline that reads
// back (and is the same curve where the operation promises it), --out writes
// atomically, and bad input exits 2 with one line and no output file.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bezierize/knot_ops.hpp"
#include "spline/spline_json.hpp"
#include "tests/cli_util.hpp"

namespace {

using cmr::BSpline;
using cmr::test::Outcome;
using cmr::test::run;
using cmr::test::scratch;
using cmr::test::write;
namespace fs = std::filesystem;

const std::string kSource = CMR_SOURCE_DIR;
const std::string kUniform = kSource + "/examples/uniform.json";  // cubic, knots 0..7, domain [2, 5]
const std::string kClamped = kSource + "/examples/clamped.json";  // cubic, knots 0,0,0,1,2,3,3,3
const std::string kSixPoints = R"("points":[[0,0],[1,2],[3,3],[5,2.5],[6.5,1],[7,-1]])";

/// Same curve on the same domain, sampled, to 1e-12 of the extent.
void expect_same_curve(const BSpline& a, const BSpline& b, const std::string& label) {
  ASSERT_EQ(a.domain_begin(), b.domain_begin()) << label;
  ASSERT_EQ(a.domain_end(), b.domain_end()) << label;
  for (int i = 0; i <= 200; ++i) {
    const double t = a.domain_begin() + (a.domain_end() - a.domain_begin()) * i / 200;
    const cmr::Vec2 p = cmr::evaluate(a, t), q = cmr::evaluate(b, t);
    ASSERT_LE(std::hypot(p.x - q.x, p.y - q.y), 1e-12 * cmr::extent(a)) << label << " at t = " << t;
  }
}

BSpline parse(const Outcome& r) { return cmr::spline_from_json(nlohmann::json::parse(r.out)); }

struct SameCurveOp {
  const char* name;
  std::string args;
  int degree_change;
};

// Printed by its name, so the test's name (ctest lists GetParam()) is stable
// and readable, not the struct's bytes.
void PrintTo(const SameCurveOp& c, std::ostream* os) { *os << c.name; }

class KnotsCliKeepsTheCurve : public ::testing::TestWithParam<SameCurveOp> {};

TEST_P(KnotsCliKeepsTheCurve, AndPrintsAValidSpline) {
  const SameCurveOp& c = GetParam();
  for (const std::string& file : {kUniform, kClamped}) {
    const Outcome r = run("knots " + file + " " + c.args);
    ASSERT_EQ(r.code, 0) << c.name << " on " << file << ": " << r.err;
    EXPECT_TRUE(r.err.empty()) << c.name << ": " << r.err;
    const BSpline before = cmr::read_spline_file(file), after = parse(r);
    EXPECT_EQ(after.degree(), before.degree() + c.degree_change) << c.name;
    EXPECT_EQ(after.name(), before.name()) << c.name;
    expect_same_curve(before, after, std::string(c.name) + " on " + file);
  }
}

INSTANTIATE_TEST_SUITE_P(Ops, KnotsCliKeepsTheCurve,
                         ::testing::Values(SameCurveOp{"insert", "insert 2.25", 0},
                                           SameCurveOp{"insert_twice", "insert 2.25 --times 2", 0},
                                           SameCurveOp{"insert_existing", "insert 2 --times 2", 0},
                                           SameCurveOp{"elevate", "elevate", 1},
                                           SameCurveOp{"refine", "refine", 0},
                                           SameCurveOp{"clamp", "clamp", 0}),
                         [](const auto& p) { return std::string(p.param.name); });

TEST(KnotsCli, RemovesAnInsertedKnotAndGivesTheOriginalBack) {
  const Outcome inserted = run("knots " + kUniform + " insert 3.25");
  ASSERT_EQ(inserted.code, 0) << inserted.err;
  const std::string file = write("inserted.json", inserted.out);
  const Outcome back = run("knots " + file + " remove 3.25");
  ASSERT_EQ(back.code, 0) << back.err;
  const BSpline original = cmr::read_spline_file(kUniform), restored = parse(back);
  EXPECT_EQ(restored.knots(), original.knots());
  expect_same_curve(original, restored, "insert then remove");
}

TEST(KnotsCli, SetAndUniformChangeTheKnotsAndKeepThePoints) {
  const BSpline original = cmr::read_spline_file(kClamped);
  const Outcome set = run("knots " + kClamped + " set 3 1.5");
  ASSERT_EQ(set.code, 0) << set.err;
  std::vector<double> want = original.knots();
  want[3] = 1.5;
  EXPECT_EQ(parse(set).knots(), want);
  EXPECT_EQ(parse(set).points(), original.points());
  const Outcome uniform = run("knots " + kClamped + " uniform");
  ASSERT_EQ(uniform.code, 0) << uniform.err;
  EXPECT_EQ(parse(uniform).knots(), (std::vector<double>{0, 1, 2, 3, 4, 5, 6, 7}));
  EXPECT_EQ(parse(uniform).points(), original.points());
}

TEST(KnotsCli, ConventionalKnotsAreRecognisedAndAcceptedOnRequest) {
  const std::string file =
      write("conventional.json", "{\"degree\":3,\"knots\":[-1,0,1,2,3,4,5,6,7,8]," + kSixPoints + "}");
  const Outcome refused = run("knots " + file + " refine");
  EXPECT_EQ(refused.code, 2);
  EXPECT_NE(refused.err.find("conventional (full) knot vector for 6 points of degree 3; drop the first and the last "
                             "knot (cmr uses polar form), or convert the file with `cmr knots FILE --conventional clamp`"),
            std::string::npos)
      << refused.err;
  const Outcome accepted = run("knots " + file + " --conventional clamp");
  ASSERT_EQ(accepted.code, 0) << accepted.err;
  const BSpline polar = cmr::spline_from_json(
      nlohmann::json::parse("{\"degree\":3,\"knots\":[0,1,2,3,4,5,6,7]," + kSixPoints + "}"));
  expect_same_curve(polar, parse(accepted), "--conventional");
}

TEST(KnotsCli, OutWritesTheFileAtomicallyAndNothingElse) {
  const fs::path dir = scratch() / "knots_out";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const Outcome r = run("knots " + kUniform + " elevate --out " + (dir / "elevated.json").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  EXPECT_EQ(names, std::vector<std::string>{"elevated.json"}) << "a temporary was left behind";
  EXPECT_EQ(cmr::read_spline_file(dir / "elevated.json").degree(), 4);
  // A refused operation leaves an existing output untouched.
  const std::string before = cmr::test::slurp(dir / "elevated.json");
  const Outcome bad = run("knots " + kUniform + " insert 9 --out " + (dir / "elevated.json").string());
  EXPECT_EQ(bad.code, 2);
  EXPECT_EQ(cmr::test::slurp(dir / "elevated.json"), before);
}

struct BadInput {
  const char* name;
  std::string args;       // FILE is replaced by the written file (or by kUniform without file_text)
  std::string file_text;  // empty: kUniform
  const char* message_part;
};

// Printed by its name, so the test's name (ctest lists GetParam()) is stable
// and readable, not the struct's bytes.
void PrintTo(const BadInput& c, std::ostream* os) { *os << c.name; }

class KnotsCliRejects : public ::testing::TestWithParam<BadInput> {};

TEST_P(KnotsCliRejects, WithExit2AndOneLine) {
  const BadInput& c = GetParam();
  std::string args = c.args;
  const std::string path = c.file_text.empty() ? kUniform : write(std::string(c.name) + ".json", c.file_text);
  args.replace(args.find("FILE"), 4, path);
  const fs::path out = scratch() / (std::string(c.name) + ".out.json");
  fs::remove(out);
  const Outcome r = run(args + " --out " + out.string());
  EXPECT_EQ(r.code, 2) << c.name << ": " << r.err;
  EXPECT_TRUE(r.out.empty()) << c.name << " printed: " << r.out;
  EXPECT_FALSE(fs::exists(out)) << c.name << " wrote " << out;
  ASSERT_FALSE(r.err.empty()) << c.name;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << c.name << ": not one line: " << r.err;
  EXPECT_NE(r.err.find(c.message_part), std::string::npos) << c.name << ": " << r.err;
}

std::string degree30_bezier() {
  std::string pts;
  for (int i = 0; i <= 30; ++i) {
    if (i > 0) pts += ',';
    pts += '[';
    pts += std::to_string(i);
    pts += ',';
    pts += std::to_string(i % 3);
    pts += ']';
  }
  return "{\"points\":[" + pts + "]}";
}

INSTANTIATE_TEST_SUITE_P(
    Table, KnotsCliRejects,
    ::testing::Values(
        BadInput{"outside_domain", "knots FILE insert 5.5", "", "knot 5.5 lies outside the domain [2, 5]"},
        BadInput{"times_beyond_degree", "knots FILE insert 3 --times 3", "", "makes 4, above the degree 3"},
        BadInput{"times_zero", "knots FILE insert 3.5 --times 0", "", "--times: 0 is outside 1..30"},
        BadInput{"not_a_number", "knots FILE insert abc", "", "U"},
        BadInput{"remove_essential", "knots FILE remove 3", "", "moves the curve by up to"},
        BadInput{"remove_tolerance_named", "knots FILE remove 3 --tol 0.001", "", "more than the tolerance 0.001"},
        BadInput{"remove_not_a_knot", "knots FILE remove 3.5", "", "not in the knot vector"},
        BadInput{"remove_end", "knots FILE remove 5", "", "only interior knots"},
        BadInput{"index_out_of_range", "knots FILE set 8 3", "", "knot index 8 is out of range 0..7"},
        BadInput{"set_breaks_order", "knots FILE set 4 2.5", "", "knots[4] (2.5) is smaller than knots[3] (3)"},
        BadInput{"conventional_wrong_count", "knots FILE --conventional refine", "",
                 "--conventional expects the full vector"},
        BadInput{"elevate_beyond_max", "knots FILE elevate", degree30_bezier(), "highest degree supported"},
        BadInput{"no_operation", "knots FILE", "", "name an operation"},
        BadInput{"unknown_operation", "knots FILE smooth", "", "smooth"}),
    [](const auto& p) { return std::string(p.param.name); });

}  // namespace
