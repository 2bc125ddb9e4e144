// Issue 26 (nothing crashes, nothing is destroyed) and issue 20 items 6-7,
// end to end through the cmr binary: SVG read by an XML parser and drawn
// y-up, outputs that are not regular files, stdout write errors, output sets
// and folders, bounded work.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <algorithm>

#include <nlohmann/json.hpp>

#include "tests/cli_util.hpp"

namespace cmr::test {
namespace {

/// A fresh folder for one test.
fs::path fresh(const std::string& name) {
  const fs::path d = scratch() / ("rel_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// The one line of stderr (and that there is exactly one).
void expect_one_line(const Outcome& r, const std::string& part, const std::string& what) {
  EXPECT_NE(r.err.find(part), std::string::npos) << what << ": " << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << what << ": " << r.err;
}

// cmr ARGS exits 2 with one stderr line holding `part`.
void expect_refused(const std::string& args, const std::string& part) {
  const Outcome r = run(args);
  EXPECT_EQ(r.code, 2) << args;
  expect_one_line(r, part, args);
}

// ---- SVG (issue 26 item 1, issue 20 item 6) ----

TEST(ReliabilitySvg, D1NonFiniteCoordinatesExit2AndWriteNothing) {
  const fs::path d = fresh("d1");
  for (const std::string path : {"M0 0 A 5 50 0 1 1 10 -1e308", "M 1e308 0 l 1e308 0 l 0 1"}) {
    std::ofstream(d / "a.svg") << "<svg><path d=\"" << path << "\"/></svg>";
    const auto r = run("import " + (d / "a.svg").string() + " --out " + (d / "o").string());
    EXPECT_EQ(r.code, 2) << path;
    expect_one_line(r, "a.svg: path 0, d[", path);
    expect_one_line(r, "not finite", path);
    EXPECT_FALSE(fs::exists(d / "o")) << path;
  }
}

TEST(ReliabilitySvg, D4LongPathIsImported) {
  const fs::path d = fresh("d4");
  {
    std::ofstream out(d / "l.svg");
    out << "<svg><path d=\"M0 0 ";
    for (int k = 0; k < 8000; ++k) out << "L1 1 ";
    out << "\"/></svg>\n";
  }
  const auto r = run("import " + (d / "l.svg").string() + " --out " + (d / "o").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(slurp(d / "o" / "l_0.json"));
  EXPECT_EQ(doc["points"].size(), 2u * 8000 + 1);
}

TEST(ReliabilitySvg, CommentedPathIsNotImportedAndTransformsApplyYUp) {
  const fs::path d = fresh("comment");
  std::ofstream(d / "c.svg") << "<svg><!-- <path d='M0 0 L1 1'/> --><g transform='translate(10,5)'>"
                                "<path d='M0 0 L1 2 L3 3'/></g></svg>";
  const auto r = run("import " + (d / "c.svg").string() + " --out " + (d / "o").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("imported 1 subpath"), std::string::npos) << r.out;
  const auto up = nlohmann::json::parse(slurp(d / "o" / "c_0.json"));
  EXPECT_EQ(up["points"][0], nlohmann::json::parse("[10.0, -5.0]"));
  EXPECT_EQ(up["points"][4], nlohmann::json::parse("[13.0, -8.0]"));
  const auto keep = run("import " + (d / "c.svg").string() + " --y-down --out " + (d / "k").string());
  ASSERT_EQ(keep.code, 0) << keep.err;
  const auto down = nlohmann::json::parse(slurp(d / "k" / "c_0.json"));
  EXPECT_EQ(down["points"][4], nlohmann::json::parse("[13.0, 8.0]"));
  expect_refused("import " + std::string(CMR_SOURCE_DIR) + "/examples/uniform.json --y-down",
                 "--y-down: only for SVG files");
}

TEST(ReliabilitySvg, ReportReadsSvgAndRegionSaysToImport) {
  const fs::path d = fresh("report_svg");
  std::ofstream(d / "logo.svg") << "<svg><path d='M0 0 C1 1 2 1 3 0'/><path d='M0 0 Q1 1 2 0'/></svg>";
  const auto rep = run("report " + (d / "logo.svg").string() + " --no-thumbnails --out " + (d / "r").string());
  ASSERT_EQ(rep.code, 0) << rep.err;
  EXPECT_EQ(rep.out.rfind("1 file: 2 splines: ", 0), 0u) << rep.out;  // the corpus run's summary line
  EXPECT_NE(rep.out.find(" 0 invalid"), std::string::npos) << rep.out;
  const auto doc = nlohmann::json::parse(slurp(d / "r" / "report.json"));
  EXPECT_NE(doc.dump().find("logo.svg:logo/path0/s0"), std::string::npos);
  for (const std::string& cmd : {"region " + (d / "logo.svg").string() + " --point 1 --backend cpu",
                                 "analyze " + (d / "logo.svg").string()}) {
    const auto r = run(cmd);
    EXPECT_EQ(r.code, 2) << cmd;
    expect_one_line(r, "logo.svg: an SVG/XML document, not a spline file (run `cmr import", cmd);
    EXPECT_EQ(r.err.find("malformed JSON"), std::string::npos) << r.err;
  }
  const std::string font = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
  if (fs::exists(font)) {
    expect_refused("region " + font + " --point 1 --backend cpu",
                   "DejaVuSans.ttf: a font file, not a spline file (run `cmr import");
  }
}

// ---- stdout and outputs that are not regular files (issue 26 items 2, 3) ----

const std::string kUniform = std::string(CMR_SOURCE_DIR) + "/examples/uniform.json";
const std::string kFig8 = std::string(CMR_SOURCE_DIR) + "/examples/figures/fig8.json";

/// Runs a shell command line (CMR replaced by the binary); stdout and stderr captured.
Outcome shell(std::string line) {
  for (std::size_t at = line.find("CMR"); at != std::string::npos; at = line.find("CMR", at + 1))
    line.replace(at, 3, CMR_BINARY);
  const fs::path script = scratch() / "cmd.sh";
  std::ofstream(script) << line << "\n";
  return run_captured("bash " + script.string());
}

bool is_char_device(const char* p) {
  struct stat st {};
  return ::stat(p, &st) == 0 && S_ISCHR(st.st_mode);
}

// D2: a full stdout is exit 3 with one line, for a small and a large output.
TEST(ReliabilityStdout, D2WriteErrorOnStdoutIsExit3) {
  ASSERT_TRUE(is_char_device("/dev/full"));
  for (const std::string& cmd : {"CMR analyze " + kUniform + " > /dev/full",
                                "CMR knots " + kUniform + " refine > /dev/full",
                                "CMR segments " + kFig8 + " --pretty > /dev/full"}) {
    const auto r = shell(cmd);
    EXPECT_EQ(r.code, 3) << cmd;
    expect_one_line(r, "cmr: stdout: No space left on device", cmd);
  }
  EXPECT_TRUE(is_char_device("/dev/full"));
}

TEST(ReliabilityStdout, BrokenPipeEndsQuietly) {
  // An output far larger than a pipe's buffer, read only in part.
  const fs::path d = fresh("pipe");
  {
    std::ofstream big(d / "big.json");
    big << "{\"degree\": 3, \"knots\": [";
    const int n = 20000;
    for (int k = 0; k < n + 2; ++k) big << (k ? "," : "") << k;
    big << "], \"points\": [";
    for (int k = 0; k < n; ++k) big << (k ? "," : "") << "[" << k << "," << (k % 7) * 0.5 << "]";
    big << "]}";
  }
  const auto r = shell("CMR knots " + (d / "big.json").string() +
                       " refine | head -c 100 > /dev/null; echo ${PIPESTATUS[0]}");
  EXPECT_EQ(r.out, "0\n") << "cmr's exit code";
  EXPECT_EQ(r.err, "") << "a closed pipe is no error to report";
}

// D7: a device, FIFO or stdout as an output is a stream, never replaced.
TEST(ReliabilityOutputs, D7DevicesAndFifosAreStreamsNeverReplaced) {
  const fs::path d = fresh("devices");
  const std::string region = "CMR region " + kUniform + " --point 1 --backend cpu --size 16x16";
  const auto full = shell(region + " --labels /dev/full");
  EXPECT_EQ(full.code, 3);
  expect_one_line(full, "/dev/full: No space left on device", "--labels /dev/full");
  EXPECT_TRUE(is_char_device("/dev/full")) << "/dev/full was replaced";
  EXPECT_TRUE(is_char_device("/dev/null"));
  const auto null = shell(region + " --png /dev/null --labels " + (d / "l.pgm").string());
  EXPECT_EQ(null.code, 0) << null.err;
  EXPECT_TRUE(is_char_device("/dev/null"));
  EXPECT_TRUE(fs::exists(d / "l.pgm"));
  for (const std::string out : {"-", "/dev/stdout"}) {
    const auto png = shell(region + " --png " + out);
    EXPECT_EQ(png.code, 0) << out << ": " << png.err;
    EXPECT_EQ(png.out.substr(0, 4), "\x89PNG") << out;
  }
  const fs::path fifo = d / "fifo.pgm";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto none = shell(region + " --labels " + fifo.string());
  EXPECT_EQ(none.code, 2);
  expect_one_line(none, "fifo.pgm: a FIFO with no reader", "FIFO without a reader");
  const auto read = shell("cat " + fifo.string() + " > " + (d / "got.pgm").string() + " & sleep 0.5; " + region +
                          " --labels " + fifo.string() + "; wait");
  EXPECT_EQ(read.code, 0) << read.err;
  EXPECT_EQ(slurp(d / "got.pgm").substr(0, 2), "P5");
  struct stat st {};
  ASSERT_EQ(::lstat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode)) << "the FIFO was replaced by a file";
}

// ---- folders (issue 20 item 7, issue 26 item 4) ----

TEST(ReliabilityFolders, SweepCreatesItsFolderAndAReusedOneHoldsOnlyThisRun) {
  const fs::path d = fresh("sweep_dir") / "new" / "sweep";
  const std::string sweep = "sweep " + kFig8 + " --point 3 --knot 3 --from 2.6 --to 3.2 --size 8x8 --backend cpu --out-dir " +
                            d.string();
  const auto longer = run(sweep + " --steps 4");
  ASSERT_EQ(longer.code, 0) << longer.err;
  EXPECT_TRUE(fs::exists(d / "frames" / "step_004.png"));
  std::ofstream(d / "frames" / "mine.txt") << "a user's file";
  const auto shorter = run(sweep + " --steps 2");
  ASSERT_EQ(shorter.code, 0) << shorter.err;
  std::vector<std::string> frames;
  for (const auto& e : fs::directory_iterator(d / "frames")) frames.push_back(e.path().filename().string());
  std::sort(frames.begin(), frames.end());
  EXPECT_EQ(frames, (std::vector<std::string>{".cmr-manifest", "mine.txt", "step_000.png", "step_001.png",
                                              "step_002.png"}));
  EXPECT_FALSE(fs::exists(d / "contours" / "step_004.svg"));
  std::ofstream(fresh("sweep_file") / "f") << "x";
  expect_refused("sweep " + kFig8 + " --point 3 --knot 3 --from 2.6 --to 3.2 --steps 1 --size 8x8 --out-dir " +
                     (scratch() / "rel_sweep_file" / "f").string(),
                 "--out-dir");
}

TEST(ReliabilityFolders, ImportIntoAReusedFolderKeepsOnlyThisImport) {
  const fs::path d = fresh("import_dir");
  std::ofstream(d / "a.svg") << "<svg><path d='M0 0 L1 1 M2 2 L3 3 M4 4 L5 5'/></svg>";
  ASSERT_EQ(run("import " + (d / "a.svg").string() + " --out " + (d / "o").string()).code, 0);
  EXPECT_TRUE(fs::exists(d / "o" / "a_2.json"));
  std::ofstream(d / "a.svg") << "<svg><path d='M0 0 L1 1'/></svg>";
  ASSERT_EQ(run("import " + (d / "a.svg").string() + " --out " + (d / "o").string()).code, 0);
  EXPECT_TRUE(fs::exists(d / "o" / "a_0.json"));
  EXPECT_FALSE(fs::exists(d / "o" / "a_1.json"));
  EXPECT_FALSE(fs::exists(d / "o" / "a_2.json"));
}

TEST(ReliabilityFolders, WithNamingAPointTwiceIsRefused) {
  expect_refused("region " + kFig8 + " --point 3 --with 2,1,2 --backend cpu --size 8x8", "--with point 2 is named twice");
  expect_refused("sweep " + kFig8 + " --point 3 --with 2,1,2 --knot 3 --from 2.6 --to 3.2 --steps 1 --size 8x8",
                 "--with point 2 is named twice");
}

// ---- bounded work and far-scale points (issue 26 items 5, D5, D6) ----

TEST(ReliabilityLimits, D6TotalPixelsAreBounded) {
  expect_refused("sweep " + kFig8 + " --point 3 --knot 3 --from 2.6 --to 3.2 --steps 10000 --size 16384x16384",
                 "10001 steps of 16384x16384 pixels: more than the limit of 268435456 pixels");
  expect_refused("region " + kFig8 + " --point all --size 16384x16384 --backend cpu",
                 "points of 16384x16384 pixels: more than the limit");
}

TEST(ReliabilityLimits, D5FarScaleKCurvePointsAreNotCoincident) {
  const fs::path d = fresh("kcurve");
  std::ofstream(d / "u.json") << "{\"points\": [[0,0],[1,2],[3,0],[4,1]]}";
  const auto unit = nlohmann::json::parse(run("kcurve " + (d / "u.json").string()).out);
  for (const auto& [pts, scale] : {std::pair<std::string, double>{"[[0,0],[1e154,2e154],[3e154,0],[4e154,1e154]]", 1e154},
                                   std::pair<std::string, double>{"[[0,0],[1e-200,2e-200],[3e-200,0],[4e-200,1e-200]]", 1e-200}}) {
    std::ofstream(d / "p.json") << "{\"points\": " << pts << "}";
    const auto r = run("kcurve " + (d / "p.json").string());
    EXPECT_EQ(r.code, 0) << pts << ": " << r.err;
    EXPECT_EQ(r.err.find("coincide"), std::string::npos) << r.err;
    const auto doc = nlohmann::json::parse(r.out);
    // The same curve as the unit-scale points, scaled by the same factor.
    ASSERT_EQ(doc["points"].size(), unit["points"].size());
    for (std::size_t k = 0; k < doc["points"].size(); ++k)
      for (int c = 0; c < 2; ++c) {
        const double want = unit["points"][k][c].get<double>() * scale, got = doc["points"][k][c].get<double>();
        EXPECT_NEAR(got / scale, want / scale, 1e-9) << pts << " point " << k << " coordinate " << c;
      }
  }
}

}  // namespace
}  // namespace cmr::test
