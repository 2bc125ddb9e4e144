// Issue 26 (nothing crashes, nothing is destroyed) and issue 20 items 6-7,
// end to end through the cmr binary: SVG read by an XML parser and drawn
// y-up, outputs that are not regular files, stdout write errors, output sets
// and folders, bounded work.
#include <gtest/gtest.h>
#include <sys/stat.h>

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
  const auto font_flag = run("import " + std::string(CMR_SOURCE_DIR) + "/examples/uniform.json --y-down");
  EXPECT_EQ(font_flag.code, 2);
  expect_one_line(font_flag, "--y-down: only for SVG files", "--y-down on JSON");
}

TEST(ReliabilitySvg, ReportReadsSvgAndRegionSaysToImport) {
  const fs::path d = fresh("report_svg");
  std::ofstream(d / "logo.svg") << "<svg><path d='M0 0 C1 1 2 1 3 0'/><path d='M0 0 Q1 1 2 0'/></svg>";
  const auto rep = run("report " + (d / "logo.svg").string() + " --no-thumbnails --out " + (d / "r").string());
  ASSERT_EQ(rep.code, 0) << rep.err;
  EXPECT_EQ(rep.out.rfind("2 splines: ", 0), 0u) << rep.out;
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
    const auto r = run("region " + font + " --point 1 --backend cpu");
    EXPECT_EQ(r.code, 2);
    expect_one_line(r, "DejaVuSans.ttf: a font file, not a spline file (run `cmr import", "region FONT");
  }
}

}  // namespace
}  // namespace cmr::test
