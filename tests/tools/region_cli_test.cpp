// End-to-end tests of `cmr region`: bad inputs (exit 2, one line, no output
// files), a missing Vulkan device (exit 3), and the outputs themselves (label
// and depth PGMs, the PNG, the JSON counts, CPU and Vulkan giving the same
// bytes).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/cli_util.hpp"

namespace {

using cmr::test::Outcome;
using cmr::test::run;
using cmr::test::scratch;
using cmr::test::write;
namespace fs = std::filesystem;

const std::string kSource = CMR_SOURCE_DIR;
const std::string kUniform = kSource + "/examples/uniform.json";  // 6 points, 3 segments
const std::string kClamped = kSource + "/examples/clamped.json";  // 6 points, 3 segments
// Examples whose default views hold more than one label (the two above are
// label 0 everywhere), so that the backend comparison cannot pass vacuously.
const std::string kFig2 = kSource + "/examples/figures/fig2.json";   // cubic Bezier, 4 points
const std::string kFig8b = kSource + "/examples/figures/fig8b.json"; // uniform cubic, 6 points
const std::string kNurbs = kSource + "/examples/rational/nurbs_cubic.json";  // rational cubic, 6 points
const std::string kCircle = kSource + "/examples/rational/circle.json";      // 4 rational quadratic arcs

// A fresh, empty folder for one test's output files.
fs::path out_dir(const std::string& name) {
  const fs::path dir = scratch() / ("region_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::vector<std::string> files_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  return names;
}

std::string binary(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Sets an environment variable for the lifetime of the guard (std::system
// hands the test's environment to the cmr process).
class EnvGuard {
 public:
  EnvGuard(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    ::setenv(name, value, 1);
  }
  ~EnvGuard() {
    if (old_) ::setenv(name_, old_->c_str(), 1);
    else ::unsetenv(name_);
  }
  EnvGuard(const EnvGuard&) = delete;
  EnvGuard& operator=(const EnvGuard&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

struct Pgm {
  int width = 0, height = 0, maxval = 0;
  std::vector<std::uint8_t> pixels;
};

// Parses a binary PGM as cmr writes it ("P5\nW H\n255\n" then W*H bytes);
// nullopt for anything else, with the reason in *why.
std::optional<Pgm> read_pgm(const fs::path& p, std::string* why) {
  const std::string bytes = binary(p);
  std::istringstream in(bytes);
  std::string magic;
  Pgm g;
  if (!(in >> magic >> g.width >> g.height >> g.maxval) || magic != "P5") {
    *why = "bad header";
    return std::nullopt;
  }
  if (in.get() != '\n') {
    *why = "no single newline after the header";
    return std::nullopt;
  }
  const std::size_t at = static_cast<std::size_t>(in.tellg());
  const std::size_t n = static_cast<std::size_t>(g.width) * g.height;
  if (bytes.size() != at + n) {
    *why = "expected " + std::to_string(n) + " pixel bytes, got " + std::to_string(bytes.size() - at);
    return std::nullopt;
  }
  g.pixels.assign(bytes.begin() + static_cast<std::ptrdiff_t>(at), bytes.end());
  return g;
}

// Asserts a PGM label map of the given size whose histogram is the JSON
// "counts" object of one point.
void expect_labels_match_counts(const fs::path& pgm, int width, int height, const nlohmann::json& counts,
                                int labels, const std::string& what) {
  std::string why;
  const auto g = read_pgm(pgm, &why);
  ASSERT_TRUE(g) << what << ": " << pgm << ": " << why;
  EXPECT_EQ(g->width, width) << what;
  EXPECT_EQ(g->height, height) << what;
  EXPECT_EQ(g->maxval, 255) << what;
  std::vector<std::uint64_t> hist(256, 0);
  for (std::uint8_t v : g->pixels) ++hist[v];
  for (int v = labels; v < 256; ++v) EXPECT_EQ(hist[v], 0u) << what << ": label " << v << " is not a label";
  ASSERT_EQ(counts.size(), static_cast<std::size_t>(labels)) << what << ": " << counts.dump();
  // The counts are keyed by the labels' names (README), in code order.
  static const char* plain[] = {"none", "increasing", "decreasing", "undecided"};
  static const char* split[] = {"none", "inc-inc", "inc-dec", "dec-inc", "dec-dec", "undecided"};
  static const char* alternating[] = {"fail", "inc-first", "dec-first", "undecided"};
  const bool alternates = counts.contains("fail");  // several split joints (Alternation)
  for (int v = 0; v < labels; ++v) {
    const char* name = labels == 6 ? split[v] : (alternates ? alternating[v] : plain[v]);
    ASSERT_TRUE(counts.contains(name)) << what << ": no count named " << name << " in " << counts.dump();
    EXPECT_EQ(hist[v], counts[name].get<std::uint64_t>()) << what << ": count of label " << v << " (" << name << ")";
  }
}

// ---------------------------------------------------------------- bad inputs

struct BadRegion {
  const char* name;
  std::string args;       // FILE is replaced by the spline, OUT by the output folder
  std::string spline;     // a path, or the text of a file to write when it starts with '{'
  const char* message_part;
};

void PrintTo(const BadRegion& c, std::ostream* os) { *os << c.name; }

class RegionRejects : public ::testing::TestWithParam<BadRegion> {};

TEST_P(RegionRejects, WithExit2OneLineAndNoOutputFiles) {
  const BadRegion& c = GetParam();
  const fs::path dir = out_dir(c.name);
  std::string file = c.spline;
  if (!file.empty() && file[0] == '{') file = write(std::string(c.name) + ".json", c.spline);
  std::string args = "region " + c.args;
  for (std::size_t at; (at = args.find("FILE")) != std::string::npos;) args.replace(at, 4, file);
  for (std::size_t at; (at = args.find("OUT")) != std::string::npos;) args.replace(at, 3, dir.string());
  // Every output kind is asked for (in the folder, unless the case names its
  // own), so that none of them may appear.
  for (const auto& [flag, value] : std::vector<std::array<std::string, 2>>{{"--size", "24x16"},
                                                                           {"--png", (dir / "r.png").string()},
                                                                           {"--labels", (dir / "r.pgm").string()},
                                                                           {"--depth-map", (dir / "d.pgm").string()}})
    if (c.args.find(flag + " ") == std::string::npos) args += " " + flag + " " + value;
  const Outcome r = run(args);
  EXPECT_EQ(r.code, 2) << c.name << ": " << r.err;
  EXPECT_TRUE(r.out.empty()) << c.name << " printed to stdout: " << r.out;
  ASSERT_FALSE(r.err.empty()) << c.name;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << c.name << ": not one line: " << r.err;
  EXPECT_NE(r.err.find(c.message_part), std::string::npos)
      << c.name << ": expected '" << c.message_part << "' in: " << r.err;
  const std::vector<std::string> left = files_in(dir);
  EXPECT_TRUE(left.empty()) << c.name << " left " << left.size() << " file(s) behind, first: "
                            << (left.empty() ? "" : left[0]);
}

const std::string kBezier = R"({"points":[[0,0],[1,1],[2,0.5],[3,0]]})";

INSTANTIATE_TEST_SUITE_P(
    Table, RegionRejects,
    ::testing::Values(
        BadRegion{"point_minus_1", "FILE --point -1", kUniform, "point -1 is out of range 0..5"},
        BadRegion{"point_6_of_6", "FILE --point 6", kUniform, "point 6 is out of range 0..5"},
        BadRegion{"point_foo", "FILE --point foo", kUniform, "--point"},
        BadRegion{"with_out_of_range", "FILE --point 2 --with 9", kUniform, "--with point 9 is out of range 0..5"},
        BadRegion{"with_negative", "FILE --point 2 --with 3,-1", kUniform, "--with point -1 is out of range"},
        BadRegion{"with_equal_to_point", "FILE --point 2 --with 2", kUniform, "--with point 2 is the moved point"},
        BadRegion{"with_and_point_all", "FILE --point all --with 2", kUniform, "--with"},
        BadRegion{"size_0x100", "FILE --point 2 --size 0x100", kUniform, "0x100"},
        BadRegion{"size_16385x10", "FILE --point 2 --size 16385x10", kUniform, "16385x10"},
        BadRegion{"size_10", "FILE --point 2 --size 10", kUniform, "--size"},
        BadRegion{"size_axb", "FILE --point 2 --size axb", kUniform, "--size"},
        BadRegion{"split_0", "FILE --point 2 --split 0", kUniform, "split 0 is outside 1..2"},
        BadRegion{"split_3", "FILE --point 2 --split 3", kUniform, "split 3 is outside 1..2"},
        BadRegion{"split_on_bezier", "FILE --point 1 --split 1", kBezier, "one segment"},
        BadRegion{"splits_not_increasing", "FILE --point 2 --split 2,1", kUniform, "split joints must increase"},
        BadRegion{"splits_outside", "FILE --point 2 --split 1,3", kUniform, "split 3 is outside 1..2"},
        BadRegion{"segments_past_the_end", "FILE --point 2 --segments 1..3", kUniform,
                  "segments 1..3: the curve has segments 0..2"},
        BadRegion{"segments_reversed", "FILE --point 2 --segments 2..1", kUniform, "the first segment is after the last"},
        BadRegion{"segments_word", "FILE --point 2 --segments one..two", kUniform, "--segments: expected A..B"},
        BadRegion{"split_outside_segments", "FILE --point 2 --segments 1..2 --split 1", kUniform,
                  "split 1 is outside 2..2"},
        BadRegion{"depth_31", "FILE --point 2 --depth 31", kUniform, "--depth: 31 is outside 0..30"},
        BadRegion{"depth_minus_1", "FILE --point 2 --depth -1", kUniform, "--depth: -1 is outside 0..30"},
        BadRegion{"view_3_numbers", "FILE --point 2 --view 0,0,1", kUniform, "four numbers"},
        BadRegion{"view_x0_above_x1", "FILE --point 2 --view 2,0,1,1", kUniform, "X0 < X1"},
        BadRegion{"view_x0_equal_x1", "FILE --point 2 --view 1,0,1,1", kUniform, "X0 < X1"},
        BadRegion{"view_y0_above_y1", "FILE --point 2 --view 0,2,1,1", kUniform, "Y0 < Y1"},
        BadRegion{"view_nan", "FILE --point 2 --view nan,0,1,1", kUniform, "finite"},
        BadRegion{"view_word", "FILE --point 2 --view 0,0,1,one", kUniform, "'one' is not a number"},
        BadRegion{"view_overflows", "FILE --point 2 --view -1e308,-1e308,1e308,1e308", kUniform, "overflows"},
        BadRegion{"mode_foo", "FILE --point 2 --mode foo", kUniform, "--mode"},
        BadRegion{"backend_foo", "FILE --point 2 --backend foo", kUniform, "--backend"},
        BadRegion{"precision_foo", "FILE --point 2 --precision fp16", kUniform, "--precision"},
        BadRegion{"malformed_json", "FILE --point 1", "{\"points\": [[0,0],", "malformed JSON"},
        BadRegion{"missing_file", "FILE --point 1", "/nonexistent/spline.json", "cannot open"},
        // An output that cannot be written must not leave the others behind
        // (the labels are written before the PNG and the depth map).
        BadRegion{"png_folder_missing", "FILE --point 1 --png /nonexistent/cmr/r.png", kFig2, "/nonexistent/cmr/r.png"},
        BadRegion{"depth_map_folder_missing", "FILE --point 1 --depth-map /nonexistent/cmr/d.pgm", kFig2,
                  "/nonexistent/cmr/d.pgm"}),
    [](const auto& p) { return std::string(p.param.name); });

// --------------------------------------------------------------- environment

TEST(RegionEnvironment, NoVulkanDeviceExits3AndSaysHowToSelectLavapipe) {
  const fs::path dir = out_dir("no_device");
  const EnvGuard env("VK_DRIVER_FILES", "/nonexistent.json");
  // Point 2 of the uniform example touches every segment, so the host cannot
  // decide every pixel alone and the device is needed.
  const Outcome r = run("region " + kUniform + " --point 2 --size 32x32 --backend vulkan --png " +
                        (dir / "r.png").string() + " --labels " + (dir / "r.pgm").string());
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  ASSERT_FALSE(r.err.empty());
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "not one line: " << r.err;
  EXPECT_NE(r.err.find("lavapipe"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("VK_DRIVER_FILES=/usr/share/vulkan/icd.d/lvp_icd"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "r.png")) << "a PNG was written without a device";
  EXPECT_TRUE(files_in(dir).empty()) << "files left behind: " << files_in(dir).size();
}

TEST(RegionEnvironment, CpuBackendNeedsNoDevice) {
  const fs::path dir = out_dir("cpu_no_device");
  const EnvGuard env("VK_DRIVER_FILES", "/nonexistent.json");
  const Outcome r = run("region " + kUniform + " --point 2 --size 32x32 --backend cpu --labels " +
                        (dir / "r.pgm").string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "r.pgm"));
}

TEST(RegionInputs, SubnormalViewIsANumberAndHugeCoordinatesDoNotCrash) {
  // Subnormal coordinates are valid doubles; a curve near the overflow limit
  // is still judged (exactly, where double arithmetic overflows).
  const Outcome tiny = run("region " + kUniform + " --point 2 --size 8x8 --backend cpu --view 0,0,1e-310,1e-310");
  EXPECT_EQ(tiny.code, 0) << tiny.err;
  const std::string huge = cmr::test::write("huge.json", "{\"points\":[[-1e300,0],[0,1e300],[1e300,0]]}");
  const Outcome r = run("region " + huge + " --point 1 --size 8x8 --backend cpu");
  EXPECT_EQ(r.code, 0) << r.err;
  const Outcome a = run("analyze " + huge);
  EXPECT_EQ(a.code, 0) << a.err;
  EXPECT_NE(a.out.find("non-monotone"), std::string::npos) << a.out;  // a symmetric parabola: maximum at the middle
}

// ------------------------------------------------------------------- outputs

nlohmann::json parse_or_fail(const Outcome& r, const std::string& what) {
  EXPECT_EQ(r.code, 0) << what << ": " << r.err;
  try {
    return nlohmann::json::parse(r.out);
  } catch (const std::exception& e) {
    ADD_FAILURE() << what << ": stdout is not JSON (" << e.what() << "): " << r.out;
    return {};
  }
}

TEST(RegionOutputs, LabelsPgmHasTheRequestedSizeAndTheJsonCounts) {
  struct Case {
    std::string file, args;
    int width, height, labels;
  };
  const std::vector<Case> cases = {{kUniform, "--point 2", 40, 24, 4},
                                   {kFig2, "--point 1", 37, 29, 4},
                                   {kFig2, "--point 3 --mode cmr", 30, 30, 4},
                                   {kFig8b, "--point 4 --split 2", 33, 21, 6},
                                   {kFig8b, "--point 4 --split 1,2", 33, 21, 4},
                                   {kFig8b, "--point 4 --segments 1..2 --split 2", 33, 21, 6},
                                   {kUniform, "--point 2 --segments 1..2", 40, 24, 4}};
  for (const Case& c : cases) {
    const fs::path dir = out_dir("labels_pgm");
    const std::string what = c.file + " " + c.args;
    const fs::path pgm = dir / "out.pgm";
    const Outcome r = run("region " + c.file + " " + c.args + " --size " + std::to_string(c.width) + "x" +
                          std::to_string(c.height) + " --labels " + pgm.string());
    const nlohmann::json doc = parse_or_fail(r, what);
    ASSERT_TRUE(doc.contains("points")) << what;
    ASSERT_EQ(doc["points"].size(), 1u) << what;
    EXPECT_EQ(doc["width"], c.width) << what;
    EXPECT_EQ(doc["height"], c.height) << what;
    EXPECT_FALSE(doc["points"][0].contains("exact_share")) << what << ": exact_share without --stats";
    expect_labels_match_counts(pgm, c.width, c.height, doc["points"][0]["counts"], c.labels, what);
    EXPECT_EQ(files_in(dir).size(), 1u) << what << ": temporary files left behind";
  }
}

// --segments names the judged and the ignored segments; --split with several
// joints echoes them and uses the four alternating labels.
TEST(RegionOutputs, SegmentsAndSplitsAreEchoed) {
  const Outcome r = run("region " + kFig8b + " --point 4 --backend cpu --size 16x16 --segments 1..2");
  const nlohmann::json doc = parse_or_fail(r, "segments");
  EXPECT_EQ(doc["segments"], nlohmann::json::parse("[1, 2]"));
  EXPECT_EQ(doc["ignored_segments"], nlohmann::json::parse("[0]"));
  const Outcome s = run("region " + kFig8b + " --point 4 --backend cpu --size 16x16 --split 1,2");
  const nlohmann::json sdoc = parse_or_fail(s, "splits");
  EXPECT_EQ(sdoc["split"], nlohmann::json::parse("[1, 2]"));
  EXPECT_EQ(sdoc["points"][0]["counts"].size(), 4u);
  EXPECT_FALSE(sdoc.contains("ignored_segments"));
}

TEST(RegionOutputs, PointAllWritesOneLabelMapPerPoint) {
  const fs::path dir = out_dir("point_all");
  const Outcome r = run("region " + kFig8b + " --point all --size 32x24 --labels " + (dir / "OUT.pgm").string());
  const nlohmann::json doc = parse_or_fail(r, "--point all");
  ASSERT_EQ(doc["points"].size(), 6u) << r.out;
  for (int k = 0; k < 6; ++k) {
    const fs::path p = dir / ("OUT.P" + std::to_string(k) + ".pgm");
    ASSERT_TRUE(fs::exists(p)) << p;
    EXPECT_EQ(doc["points"][k]["point"], k);
    expect_labels_match_counts(p, 32, 24, doc["points"][k]["counts"], 4, "point " + std::to_string(k));
  }
  EXPECT_FALSE(fs::exists(dir / "OUT.pgm")) << "--point all also wrote the unsuffixed name";
  EXPECT_EQ(files_in(dir).size(), 6u);
}

TEST(RegionOutputs, DepthMapValuesAreAtMostTheDepth) {
  for (const int depth : {0, 3, 7}) {
    const fs::path dir = out_dir("depth_map");
    const fs::path p = dir / "d.pgm";
    const Outcome r = run("region " + kFig2 + " --point 3 --size 40x30 --depth " + std::to_string(depth) +
                          " --depth-map " + p.string());
    ASSERT_EQ(r.code, 0) << "depth " << depth << ": " << r.err;
    std::string why;
    const auto g = read_pgm(p, &why);
    ASSERT_TRUE(g) << "depth " << depth << ": " << why;
    EXPECT_EQ(g->width, 40);
    EXPECT_EQ(g->height, 30);
    EXPECT_EQ(g->maxval, std::max(depth, 1)) << "maxval D, so that viewers stretch the levels to black..white";
    int most = 0;
    for (std::size_t at = 0; at < g->pixels.size(); ++at) {
      ASSERT_LE(int(g->pixels[at]), depth) << "depth " << depth << " pixel (" << at % 40 << ", " << at / 40 << ")";
      most = std::max(most, int(g->pixels[at]));
    }
    // Fig. 2's regions have pixels decided below level 0 (so the map is not all zero).
    if (depth > 0) {
      EXPECT_GT(most, 0) << "depth " << depth << ": every pixel decided at level 0";
    }
  }
}

TEST(RegionOutputs, DepthMapAsPngIsTheShadedPicture) {
  const fs::path dir = out_dir("depth_png");
  const fs::path p = dir / "d.png";
  const Outcome r = run("region " + kFig2 + " --point 0 --size 64x48 --backend cpu --depth-map " + p.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string b = binary(p);
  ASSERT_GE(b.size(), 24u);
  EXPECT_EQ(b.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  // IHDR: width and height, big-endian, at bytes 16..23.
  auto be32 = [&](std::size_t at) {
    return (static_cast<unsigned char>(b[at]) << 24) | (static_cast<unsigned char>(b[at + 1]) << 16) |
           (static_cast<unsigned char>(b[at + 2]) << 8) | static_cast<unsigned char>(b[at + 3]);
  };
  EXPECT_EQ(be32(16), 64u);
  EXPECT_EQ(be32(20), 48u);
}

TEST(RegionOutputs, AnEmptyRegionPrintsANoteAndSucceeds) {
  // Fig. 8(a)'s P0 has no CMRWI in the default view (the figure's claim, for CMRs); P3 has one.
  const std::string fig8 = kSource + "/examples/figures/fig8.json";
  const Outcome empty = run("region " + fig8 + " --point 0 --size 48x48 --backend cpu");
  EXPECT_EQ(empty.code, 0) << empty.err;
  EXPECT_NE(empty.err.find("note: P0 has no CMRWI in this view"), std::string::npos) << empty.err;
  const nlohmann::json doc = parse_or_fail(empty, "empty region");
  EXPECT_EQ(doc["points"][0]["counts"]["increasing"], 0);
  EXPECT_EQ(doc["points"][0]["counts"]["decreasing"], 0);
  const Outcome full = run("region " + fig8 + " --point 3 --size 48x48 --backend cpu");
  EXPECT_EQ(full.code, 0) << full.err;
  EXPECT_EQ(full.err.find("note:"), std::string::npos) << full.err;
}

TEST(RegionOutputs, PngHasTheRequestedSize) {
  const fs::path dir = out_dir("png");
  const fs::path p = dir / "r.png";
  const Outcome r = run("region " + kFig2 + " --point 2 --size 70x45 --png " + p.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string b = binary(p);
  ASSERT_GE(b.size(), 24u);
  const std::string signature = "\x89PNG\r\n\x1a\n";
  EXPECT_EQ(b.substr(0, 8), signature);
  EXPECT_EQ(b.substr(12, 4), "IHDR");
  auto be32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 4; ++k) v = (v << 8) | static_cast<unsigned char>(b[at + k]);
    return v;
  };
  EXPECT_EQ(be32(16), 70u) << "IHDR width";
  EXPECT_EQ(be32(20), 45u) << "IHDR height";
  EXPECT_EQ(files_in(dir).size(), 1u) << "temporary files left behind";
}

TEST(RegionOutputs, StatsAddsTheExactShare) {
  const Outcome r = run("region " + kFig2 + " --point 1 --size 32x32 --stats");
  const nlohmann::json doc = parse_or_fail(r, "--stats");
  ASSERT_EQ(doc["points"].size(), 1u);
  const auto& p = doc["points"][0];
  ASSERT_TRUE(p.contains("exact_share")) << r.out;
  ASSERT_TRUE(p.contains("exact_pixels")) << r.out;
  const double share = p["exact_share"].get<double>();
  EXPECT_GE(share, 0.0);
  EXPECT_LE(share, 1.0);
  EXPECT_DOUBLE_EQ(share, p["exact_pixels"].get<double>() / (32.0 * 32.0));
}

// CPU and Vulkan (fp64 and fp32) give byte-identical label maps.
struct Same {
  const char* name;
  std::string file, args;
};

void PrintTo(const Same& c, std::ostream* os) { *os << c.name; }

class RegionBackendsAgree : public ::testing::TestWithParam<Same> {};

TEST_P(RegionBackendsAgree, ByteIdenticalLabelMaps) {
  const Same& c = GetParam();
  const fs::path dir = out_dir(c.name);
  const std::string base = "region " + c.file + " " + c.args + " --size 48x40 --labels ";
  const Outcome cpu = run(base + (dir / "cpu.pgm").string() + " --backend cpu");
  ASSERT_EQ(cpu.code, 0) << c.name << " cpu: " << cpu.err;
  const std::string want = binary(dir / "cpu.pgm");
  ASSERT_FALSE(want.empty()) << c.name;
  for (const char* precision : {"fp64", "fp32"}) {
    const fs::path p = dir / (std::string("vk_") + precision + ".pgm");
    const Outcome vk = run(base + p.string() + " --backend vulkan --precision " + precision);
    ASSERT_EQ(vk.code, 0) << c.name << " " << precision << ": " << vk.err;
    const std::string got = binary(p);
    ASSERT_EQ(got.size(), want.size()) << c.name << " " << precision;
    for (std::size_t at = 0; at < got.size(); ++at)
      ASSERT_EQ(int(static_cast<unsigned char>(got[at])), int(static_cast<unsigned char>(want[at])))
          << c.name << " " << precision << ": byte " << at << " of the PGM";
    // The JSON counts agree too.
    EXPECT_EQ(nlohmann::json::parse(vk.out)["points"], nlohmann::json::parse(cpu.out)["points"])
        << c.name << " " << precision;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Examples, RegionBackendsAgree,
    ::testing::Values(Same{"uniform_P0", kUniform, "--point 0"}, Same{"uniform_P2", kUniform, "--point 2"},
                      Same{"uniform_P3_cmr", kUniform, "--point 3 --mode cmr"},
                      Same{"uniform_P5", kUniform, "--point 5"},
                      Same{"uniform_split2_cmr_P2", kUniform, "--point 2 --split 2 --mode cmr"},
                      Same{"clamped_P0", kClamped, "--point 0"}, Same{"clamped_P2", kClamped, "--point 2"},
                      Same{"clamped_P4", kClamped, "--point 4"},
                      Same{"clamped_split2_cmr_P3", kClamped, "--point 3 --split 2 --mode cmr"},
                      Same{"clamped_P2_with_P3", kClamped, "--point 2 --with 3"},
                      // More examples with regions:
                      Same{"fig2_P0", kFig2, "--point 0"}, Same{"fig2_P3_cmr", kFig2, "--point 3 --mode cmr"},
                      Same{"fig8b_P5", kFig8b, "--point 5"},
                      Same{"fig8b_split2_cmr_P4", kFig8b, "--point 4 --split 2 --mode cmr"},
                      // Rational curves:
                      Same{"nurbs_P3", kNurbs, "--point 3 --view 2.9,-2.6,4.1,-1.4"},
                      Same{"nurbs_P5_cmr", kNurbs, "--point 5 --mode cmr"},
                      Same{"circle_P2", kCircle, "--point 2"}),
    [](const auto& p) { return std::string(p.param.name); });

TEST(RegionBackendsAgree, EveryPointOverlappedGivesTheSameMapsAndPicture) {
  // --point all: one label map per point, and the overlapped picture, from both backends.
  const fs::path dir = out_dir("point_all_agree");
  for (const char* backend : {"cpu", "vulkan"}) {
    const Outcome r = run("region " + kUniform + " --point all --size 48x40 --backend " + backend + " --labels " +
                          (dir / (std::string(backend) + ".pgm")).string() + " --png " +
                          (dir / (std::string(backend) + ".png")).string());
    ASSERT_EQ(r.code, 0) << backend << ": " << r.err;
  }
  int with_region = 0;
  for (int k = 0; k < 6; ++k) {
    const std::string suffix = ".P" + std::to_string(k) + ".pgm";
    const std::string cpu = binary(dir / ("cpu" + suffix)), vk = binary(dir / ("vulkan" + suffix));
    ASSERT_FALSE(cpu.empty()) << "P" << k;
    EXPECT_EQ(cpu, vk) << "P" << k << " label maps differ";
    with_region += cpu.find_first_of(std::string("\x01\x02", 2), cpu.find('\n', cpu.find('\n', 3) + 1) + 1) !=
                   std::string::npos;
  }
  EXPECT_EQ(binary(dir / "cpu.png"), binary(dir / "vulkan.png")) << "the overlapped pictures differ";
  EXPECT_GE(with_region, 3) << "the uniform example has regions for P1, P2, P3";
}

TEST(RegionBackendsAgree, SomeComparedMapHasSeveralLabels) {
  // Guards RegionBackendsAgree against comparing only all-zero maps.
  for (const auto& [file, args] : std::vector<std::array<std::string, 2>>{{kFig2, "--point 0"},
                                                                          {kFig8b, "--point 5"}}) {
    const Outcome r = run("region " + file + " " + args + " --size 48x40 --backend cpu");
    const nlohmann::json doc = parse_or_fail(r, file);
    int present = 0;
    for (const auto& [label, count] : doc["points"][0]["counts"].items()) present += count.get<int>() > 0;
    EXPECT_GE(present, 2) << file << " " << args << ": " << r.out;
  }
}

}  // namespace

// Issue 20, item 2: a reason for every empty or full region, naming the
// segments responsible (region/region_reason.hpp), on stderr and in the
// PNG's legend.
namespace {

const std::string kFig8 = kSource + "/examples/figures/fig8.json";  // uniform cubic, 6 points, 3 segments

TEST(RegionReason, PointOutsideTheJudgedSegmentsSaysAllOrNothing) {
  const fs::path dir = out_dir("reason_support");
  const Outcome o = run("region " + kFig8 + " --point 0 --segments 2 --backend cpu --size 40x40 --png " +
                        (dir / "r.png").string());
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_NE(o.err.find("P0 does not act on segment 2: every position gives the same answer"), std::string::npos)
      << o.err;
  EXPECT_TRUE(fs::exists(dir / "r.png"));
}

TEST(RegionReason, FailingSegmentThePointDoesNotActOnIsNamed) {
  // fig8's first two segments are not monotone; P5 acts on segment 2 only.
  const Outcome o = run("region " + kFig8 + " --point 5 --backend cpu --size 40x40");
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_NE(o.err.find("segments 0..1 are non-monotone whatever P5 does (P5 acts on segment 2)"), std::string::npos)
      << o.err;
  // One line per note.
  EXPECT_EQ(std::count(o.err.begin(), o.err.end(), '\n'), 1) << o.err;
}

TEST(RegionReason, ClosedCurveJudgesTheMovedPointsSupport) {
  const std::string file = write("reason_loop.json",
        R"({"degree": 2, "closed": true, "knots": [0, 1, 2, 3, 4, 5, 6],
            "points": [[1, 0], [0.4, 0.9], [-0.6, 0.8], [-1.1, -0.1], [-0.3, -1], [0.7, -0.8]]})");
  const Outcome o = run("region " + file + " --point 2 --backend cpu --size 40x40");
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_NE(o.err.find("closed curve: P2's region judges the spans it acts on, segments 0..2"), std::string::npos)
      << o.err;
  const nlohmann::json doc = nlohmann::json::parse(o.out);
  EXPECT_EQ(doc["segments"], nlohmann::json({0, 2}));
  EXPECT_EQ(doc["ignored_segments"], nlohmann::json({3, 4, 5}));
}

TEST(RegionReason, EachPieceOnTheCliAndItsBadInput) {
  const Outcome o = run("region " + kFig8 + " --point 3 --each-piece --backend cpu --size 40x40");
  ASSERT_EQ(o.code, 0) << o.err;
  const nlohmann::json doc = nlohmann::json::parse(o.out);
  EXPECT_EQ(doc["each_piece"], nlohmann::json({1, 2}));
  EXPECT_TRUE(doc["points"][0]["counts"].contains("each-monotone"));
  const Outcome bad = run("region " + kFig8 + " --point 3 --each-piece 1,x --backend cpu --size 8x8");
  EXPECT_EQ(bad.code, 2);
  EXPECT_EQ(bad.err.find('\n'), bad.err.size() - 1) << bad.err;
  EXPECT_NE(bad.err.find("--each-piece: expected joints S1,S2,... (got '1,x')"), std::string::npos) << bad.err;
  const Outcome both = run("region " + kFig8 + " --point 3 --each-piece 1 --split 2 --backend cpu --size 8x8");
  EXPECT_EQ(both.code, 2);
  EXPECT_NE(both.err.find("drop --split"), std::string::npos) << both.err;
  const Outcome outside = run("analyze " + kFig8 + " --each-piece 3");
  EXPECT_EQ(outside.code, 2);
  EXPECT_NE(outside.err.find("split 3 is outside 1..2"), std::string::npos) << outside.err;
}

}  // namespace

// Issue 40 item 6: without --view the view is the union of the point's
// region and the moved point with a margin (region/view_fit.hpp:
// fit_region_view), so a region is not drawn as a speck; with --view
// nothing changes.
namespace {

struct PgmRegion {
  int width = 0, height = 0, pixels = 0;   // region pixels (labels 1 and 2)
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;  // their box, inclusive
};

PgmRegion region_of(const fs::path& pgm) {
  std::string why;
  const auto g = read_pgm(pgm, &why);
  EXPECT_TRUE(g) << pgm << ": " << why;
  PgmRegion r;
  if (!g) return r;
  r.width = g->width, r.height = g->height;
  for (int y = 0; y < g->height; ++y)
    for (int x = 0; x < g->width; ++x)
      if (const int v = g->pixels[static_cast<std::size_t>(y) * g->width + x]; v == 1 || v == 2)
        ++r.pixels, r.x0 = std::min(r.x0, x), r.x1 = std::max(r.x1, x), r.y0 = std::min(r.y0, y), r.y1 = std::max(r.y1, y);
  return r;
}

std::string view_flag(const nlohmann::json& v) {
  std::ostringstream s;
  s.precision(17);
  s << " --view " << v[0].get<double>() << "," << v[1].get<double>() << "," << v[2].get<double>() << ","
    << v[3].get<double>();
  return s.str();
}

TEST(RegionDefaultView, IsTheRegionAndTheMovedPointWithAMargin) {
  struct Case {
    std::string file;
    int point;
  };
  const std::vector<Case> cases = {{kFig2, 0},    {kFig2, 1},   {kFig2, 2},   {kFig2, 3},   {kFig8b, 2},
                                   {kFig8b, 3},   {kFig8b, 4},  {kUniform, 2}, {kClamped, 3}, {kNurbs, 3}};
  for (const Case& c : cases) {
    const std::string what = c.file + " P" + std::to_string(c.point);
    const fs::path dir = out_dir("default_view");
    const std::string args = "region " + c.file + " --point " + std::to_string(c.point) + " --size 64x48 --backend cpu";
    const Outcome r = run(args + " --labels " + (dir / "fit.pgm").string());
    const nlohmann::json doc = parse_or_fail(r, what);
    ASSERT_TRUE(doc.contains("view_fitted")) << what << ": " << r.out;
    ASSERT_TRUE(doc["view_fitted"].get<bool>()) << what << ": " << r.out << r.err;
    const auto& v = doc["view"];
    const double vx0 = v[0], vy0 = v[1], vx1 = v[2], vy1 = v[3];
    EXPECT_NEAR((vx1 - vx0) / (vy1 - vy0), 64.0 / 48.0, 1e-9) << what << ": square pixels";
    // The moved point is inside, at least 10% of the view in from its edges (the 15% margin).
    const nlohmann::json k = nlohmann::json::parse(cmr::test::slurp(c.file))["points"][c.point];
    const double kx = k[0], ky = k[1];
    EXPECT_GT(kx, vx0 + 0.1 * (vx1 - vx0)) << what;
    EXPECT_LT(kx, vx1 - 0.1 * (vx1 - vx0)) << what;
    EXPECT_GT(ky, vy0 + 0.1 * (vy1 - vy0)) << what;
    EXPECT_LT(ky, vy1 - 0.1 * (vy1 - vy0)) << what;
    // The region and K span at least half the view along one axis (the box
    // with its margin is 1.3 times theirs, less the probe's pixel).
    PgmRegion g = region_of(dir / "fit.pgm");
    ASSERT_GT(g.pixels, 0) << what;
    const int ki = static_cast<int>((kx - vx0) / (vx1 - vx0) * 64), kj = static_cast<int>((vy1 - ky) / (vy1 - vy0) * 48);
    g.x0 = std::min(g.x0, ki), g.x1 = std::max(g.x1, ki), g.y0 = std::min(g.y0, kj), g.y1 = std::max(g.y1, kj);
    EXPECT_TRUE((g.x1 - g.x0 + 1) * 2 >= 64 || (g.y1 - g.y0 + 1) * 2 >= 48)
        << what << ": region and K span " << g.x1 - g.x0 + 1 << " x " << g.y1 - g.y0 + 1 << " of 64 x 48";
    // The fitted view is an ordinary view: given as --view, the same labels.
    const Outcome again = run(args + view_flag(v) + " --labels " + (dir / "given.pgm").string());
    ASSERT_EQ(again.code, 0) << what << ": " << again.err;
    EXPECT_EQ(binary(dir / "fit.pgm"), binary(dir / "given.pgm")) << what;
    EXPECT_FALSE(nlohmann::json::parse(again.out).contains("view_fitted")) << what << ": with --view, as before";
  }
}

TEST(RegionDefaultView, PointAllFitsEveryPointsRegion) {
  const fs::path dir = out_dir("default_view_all");
  const Outcome r = run("region " + kFig8b + " --point all --size 48x48 --backend cpu --labels " +
                        (dir / "OUT.pgm").string());
  const nlohmann::json doc = parse_or_fail(r, "--point all");
  ASSERT_TRUE(doc["view_fitted"].get<bool>()) << r.out;
  const auto& v = doc["view"];
  const nlohmann::json points = nlohmann::json::parse(cmr::test::slurp(kFig8b))["points"];
  int shown = 0;
  for (int k = 0; k < 6; ++k) {
    const PgmRegion g = region_of(dir / ("OUT.P" + std::to_string(k) + ".pgm"));
    if (g.pixels == 0) continue;
    ++shown;  // a point whose region shows is inside the view
    const double kx = points[k][0], ky = points[k][1];
    EXPECT_TRUE(kx > v[0].get<double>() && kx < v[2].get<double>() && ky > v[1].get<double>() && ky < v[3].get<double>())
        << "P" << k << " outside " << v;
  }
  EXPECT_GE(shown, 3) << r.out;
}

TEST(RegionDefaultView, NoRegionNearTheCurveKeepsThePolygonsViewAndSaysSo) {
  // Fig. 8(a)'s P0 has no CMRWI near the curve (the figure's claim, for CMRs).
  const std::string fig8 = kSource + "/examples/figures/fig8.json";
  const Outcome r = run("region " + fig8 + " --point 0 --size 48x48 --backend cpu");
  const nlohmann::json doc = parse_or_fail(r, "fig8 P0");
  EXPECT_FALSE(doc["view_fitted"].get<bool>()) << r.out;
  EXPECT_NE(r.err.find("(its region is empty here, and in three times the polygon's view)"), std::string::npos)
      << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  // The polygon's view: its box with a 25% margin, square pixels (cmr::default_view).
  const nlohmann::json p = nlohmann::json::parse(cmr::test::slurp(fig8))["points"];
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const auto& q : p) x0 = std::min(x0, q[0].get<double>()), x1 = std::max(x1, q[0].get<double>()),
                          y0 = std::min(y0, q[1].get<double>()), y1 = std::max(y1, q[1].get<double>());
  const double side = 1.5 * std::max(x1 - x0, y1 - y0);
  EXPECT_NEAR(doc["view"][2].get<double>() - doc["view"][0].get<double>(), side, 1e-12 * side) << doc["view"];
  EXPECT_NEAR(doc["view"][0].get<double>() + doc["view"][2].get<double>(), x0 + x1, 1e-12 * side) << doc["view"];
}

}  // namespace
