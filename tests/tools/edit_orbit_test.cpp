// `cmr edit SPACE.json` for real: the orbit view in a window under Xvfb
// (lavapipe), driven by scripts; the presented image is read back as a PNG
// and its pixels checked (region colours in the plane, the torsion-coloured
// curve, a rotation changes the picture), a scripted drag is saved and its
// point checked against its plane and against `cmr region`'s label there.
#include <gtest/gtest.h>

#include <cairo.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <vector>

#include "tests/cli_util.hpp"

namespace {

using cmr::test::Outcome;
using cmr::test::scratch;
using cmr::test::write;
namespace fs = std::filesystem;

const std::string kLifted = std::string(CMR_SOURCE_DIR) + "/examples/space/fig8b_lifted.json";
const std::string kFailing = std::string(CMR_SOURCE_DIR) + "/examples/space/fig8_lifted.json";
constexpr int kW = 640, kH = 480;

bool have_xvfb() { return std::system("command -v xvfb-run >/dev/null 2>&1") == 0; }

/// cmr edit FILE --script (the text) --screenshot SHOT under xvfb-run.
Outcome run_edit(const std::string& file, const std::string& script_text, const fs::path& shot,
                 const std::string& options = "") {
  const std::string script = write("orbit_script.txt", script_text);
  const fs::path dir = scratch();
  // The X server's own cursor starts at the screen's centre and reaches the
  // window as a real pointer event: a screen twice the window's size keeps it outside.
  // -f: an X authority file of the run's own (edit_test.cpp's kXvfbAuth says why).
  const std::string line = "xvfb-run -a -f \"$(mktemp)\" -s '-screen 0 1280x960x24' " + std::string(CMR_BINARY) + " edit " + file +
                           " --size " + std::to_string(kW) + "x" + std::to_string(kH) + options + " --script " +
                           script + " --screenshot " + shot.string() + " >" + (dir / "oout").string() + " 2>" +
                           (dir / "oerr").string();
  Outcome r;
  const int status = std::system(line.c_str());
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.out = cmr::test::slurp(dir / "oout");
  r.err = cmr::test::slurp(dir / "oerr");
  return r;
}

struct Image {
  int width = 0, height = 0;
  std::vector<std::array<int, 3>> rgb;
  const std::array<int, 3>& at(int x, int y) const { return rgb[static_cast<std::size_t>(y) * width + x]; }
};

Image read_png(const fs::path& p) {
  cairo_surface_t* s = cairo_image_surface_create_from_png(p.c_str());
  Image img;
  if (cairo_surface_status(s) == CAIRO_STATUS_SUCCESS) {
    img.width = cairo_image_surface_get_width(s);
    img.height = cairo_image_surface_get_height(s);
    const unsigned char* data = cairo_image_surface_get_data(s);
    const int stride = cairo_image_surface_get_stride(s);
    for (int j = 0; j < img.height; ++j) {
      const auto* row = reinterpret_cast<const uint32_t*>(data + j * stride);
      for (int i = 0; i < img.width; ++i)
        img.rgb.push_back({static_cast<int>(row[i] >> 16 & 255), static_cast<int>(row[i] >> 8 & 255),
                           static_cast<int>(row[i] & 255)});
    }
  }
  cairo_surface_destroy(s);
  return img;
}

/// Pixels of the legend's region colours (draw::label_colour: increasing
/// 255,102,102, decreasing 102,102,255, exact: the region is drawn opaque).
int region_pixels(const Image& img) {
  int n = 0;
  for (const auto& c : img.rgb)
    if (c == std::array<int, 3>{255, 102, 102} || c == std::array<int, 3>{102, 102, 255}) ++n;
  return n;
}

/// Pixels of the torsion colours (green where tau > 0, purple where tau < 0),
/// which no region, plane, polygon or comb colour is near.
int torsion_pixels(const Image& img) {
  int n = 0;
  for (const auto& c : img.rgb) {
    const bool green = c[1] - std::max(c[0], c[2]) > 50;
    const bool purple = c[0] - c[1] > 50 && c[2] - c[1] > 90 && c[0] < 230;
    if (green || purple) ++n;
  }
  return n;
}

TEST(EditOrbitWindow, OpensASpaceCurveAndWritesAScreenshot) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed (tools/setup.sh installs it)";
  const fs::path shot = scratch() / "orbit_a.png";
  fs::remove(shot);
  const Outcome r = run_edit(kLifted, "plane xy\norbit -60 35\nlegend\nui off\n", shot, " --point 3");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("a space curve, in the orbit view"), std::string::npos) << r.err;
  // The legend names the colours the picture shows (the script's `legend`: kind, colour bytes, words).
  EXPECT_NE(r.err.find("legend title 0,0,0 Where P3 may go in its xy plane"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("legend swatch 255,102,102 increasing"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("legend swatch 102,102,255 decreasing"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("legend line 0,158,64 curve: torsion > 0"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("legend line 140,26,191 curve: torsion < 0"), std::string::npos) << r.err;
  const Image img = read_png(shot);
  ASSERT_EQ(img.width, kW);
  ASSERT_EQ(img.height, kH);
  EXPECT_GT(region_pixels(img), 100) << "P3's region in the xy plane shows";
  EXPECT_GT(torsion_pixels(img), 20) << "the curve in its torsion colours shows";
}

TEST(EditOrbitWindow, RotatingTheViewChangesThePicture) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed";
  const fs::path a = scratch() / "orbit_r1.png", b = scratch() / "orbit_r2.png";
  ASSERT_EQ(run_edit(kLifted, "plane xy\norbit -60 35\nui off\n", a, " --point 3").code, 0);
  const Outcome r = run_edit(kLifted, "plane xy\norbit 30 60\nui off\n", b, " --point 3");
  ASSERT_EQ(r.code, 0) << r.err;
  const Image x = read_png(a), y = read_png(b);
  ASSERT_EQ(x.rgb.size(), y.rgb.size());
  long differ = 0;
  for (std::size_t i = 0; i < x.rgb.size(); ++i) differ += x.rgb[i] != y.rgb[i];
  EXPECT_GT(differ, static_cast<long>(x.rgb.size() / 50));
  EXPECT_GT(region_pixels(y), 100);
  // A region drawn edge-on is a line: looking along the plane, hardly any region pixel.
  const fs::path c = scratch() / "orbit_r3.png";
  ASSERT_EQ(run_edit(kLifted, "plane xy\norbit -60 0\nui off\n", c, " --point 3").code, 0);
  EXPECT_LT(region_pixels(read_png(c)), region_pixels(y) / 10);
}

TEST(EditOrbitWindow, ADragStaysInItsPlaneAndCmrRegionAgreesWithTheLabelThere) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed";
  const fs::path dir = scratch();
  const fs::path saved = dir / "orbit_dragged.json", shot = dir / "orbit_drag.png";
  fs::remove(saved);
  const Outcome r = run_edit(kLifted,
                             "plane xy\norbit -60 35\ndrag 3 -0.3 -0.2 6\nstatus\nsave " + saved.string() + "\n",
                             shot, " --point 3");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto doc = nlohmann::json::parse(cmr::test::slurp(saved));
  const auto before = nlohmann::json::parse(cmr::test::slurp(kLifted));
  const double x0 = before["points"][3][0], y0 = before["points"][3][1], z0 = before["points"][3][2];
  const double x = doc["points"][3][0], y = doc["points"][3][1], z = doc["points"][3][2];
  EXPECT_EQ(z, z0) << "the xy plane through P3: z stays exactly";
  EXPECT_NEAR(x - x0, -0.3, 1e-6);
  EXPECT_NEAR(y - y0, -0.2, 1e-6);
  for (int k : {0, 1, 2, 4, 5}) EXPECT_EQ(doc["points"][k], before["points"][k]);
  // The status line's label at the dropped point against cmr region's, one pixel centred there.
  const auto here = r.err.find("; here ");
  ASSERT_NE(here, std::string::npos) << r.err;
  const std::string label = r.err.substr(here + 7, r.err.find(';', here + 7) - here - 7);
  const double a = x - x0, b = y - y0, e = 1e-9;
  const fs::path pgm = dir / "orbit_here.pgm";
  char view[160];
  std::snprintf(view, sizeof view, "%.17g,%.17g,%.17g,%.17g", a - e, b - e, a + e, b + e);
  const Outcome reg = cmr::test::run("region " + kLifted + " --point 3 --plane xy --view " + view +
                                     " --size 1x1 --backend cpu --labels " + pgm.string());
  ASSERT_EQ(reg.code, 0) << reg.err;
  const std::string bytes = cmr::test::slurp(pgm);
  ASSERT_FALSE(bytes.empty());
  const int code = static_cast<unsigned char>(bytes.back());
  const char* names[] = {"none", "increasing", "decreasing", "undecided"};
  ASSERT_LT(code, 4);
  EXPECT_EQ(label, names[code]);
}

TEST(EditOrbitWindow, FixMovesAPointAndTheSavedCurveIsMonotone) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed";
  const fs::path saved = scratch() / "orbit_fixed.json", shot = scratch() / "orbit_fix.png";
  fs::remove(saved);
  const Outcome r = run_edit(kFailing, "fix\nsave " + saved.string() + "\n", shot);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("fix (cmrwi): moved P"), std::string::npos) << r.err;
  const Outcome an = cmr::test::run("analyze " + saved.string());
  ASSERT_EQ(an.code, 0) << an.err;
  const auto j = nlohmann::json::parse(an.out);
  const std::string verdict = j["spline"]["curvature"];
  EXPECT_TRUE(verdict == "increasing" || verdict == "decreasing") << an.out;
}

TEST(EditOrbitWindow, RefusesPlanarOnlyCommandsAndOptionsInOneLine) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed";
  const fs::path shot = scratch() / "orbit_bad.png";
  fs::remove(shot);
  Outcome r = run_edit(kLifted, "knot 1 2.5\n", shot);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("'knot' is not available in the orbit view"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(shot));
  r = run_edit(kLifted, "plane sideways\n", shot);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("plane: expected region, screen, xy, yz or zx"), std::string::npos) << r.err;
  r = run_edit(kLifted, "", shot, " --point 9");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--point: no point 9"), std::string::npos) << r.err;
  r = run_edit(kLifted, "", shot, " --glyph O");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("is a spline file, not a font"), std::string::npos) << r.err;
  r = run_edit(kLifted, "", shot, " --region-path gpu");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--region-path: the orbit view of a space curve computes its region on the CPU"),
            std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(shot));
}

// `cmr edit MODEL.step --edge '#ID'` opens that edge of the model (the
// class-A-style wire: four quintic edges) in the orbit view: the first line
// names the model and the edge, the screenshot shows the curve, and `save`
// writes MODEL_ID.json beside the model, the very spline `cmr import` writes
// for that edge (every point and knot equal), never the model. An unknown id,
// a STEP file without --edge, --edge on a spline file and two ids are one
// line, exit 2, and no screenshot.
TEST(EditOrbitWindow, OpensAStepModelsEdgeByItsEntityId) {
#ifndef CMR_STEP_MODEL
  GTEST_SKIP() << "cmr was built without the STEP importer (OpenCASCADE)";
#else
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed";
  const fs::path dir = scratch() / "orbit_step";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path model = dir / "wire.step";
  ASSERT_EQ(std::system((std::string(CMR_STEP_MODEL) + " " + model.string() + " wire >/dev/null").c_str()), 0);
  const Outcome imported = cmr::test::run("import " + model.string() + " --out " + (dir / "imported").string());
  ASSERT_EQ(imported.code, 0) << imported.err;
  const std::size_t chain = imported.out.find("chain 1: #");
  ASSERT_NE(chain, std::string::npos) << imported.out;
  const std::string id = imported.out.substr(chain + 10, imported.out.find(' ', chain + 10) - chain - 10);  // "54"
  const std::string second = imported.out.substr(imported.out.find("> #", chain) + 3);
  const std::string id2 = second.substr(0, second.find(' '));  // the chain's second edge: edit that one
  const fs::path shot = dir / "edge.png";
  const Outcome r = run_edit(model.string(), "plane xy\nsave\n", shot, " --edge '#" + id2 + "'");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("cmr edit: wire.step, edge #" + id2 + " ("), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("a space curve, in the orbit view"), std::string::npos) << r.err;
  const Image img = read_png(shot);
  ASSERT_EQ(img.width, kW);
  int curve = 0;  // the curve of a planar edge: dark grey (77, 77, 77)
  for (const auto& c : img.rgb) curve += c == std::array<int, 3>{77, 77, 77};
  EXPECT_GT(curve, 50) << "the edge's curve shows";
  const fs::path saved = dir / ("wire_" + id2 + ".json");
  ASSERT_TRUE(fs::exists(saved)) << r.err;
  const nlohmann::json mine = nlohmann::json::parse(cmr::test::slurp(saved));
  const nlohmann::json theirs = nlohmann::json::parse(cmr::test::slurp(dir / "imported" / ("wire_" + id2 + ".json")));
  EXPECT_EQ(mine["points"], theirs["points"]);
  EXPECT_EQ(mine["knots"], theirs["knots"]);
  EXPECT_EQ(mine["degree"], theirs["degree"]);
  EXPECT_EQ(mine["name"], theirs["name"]);
  EXPECT_NE(id, id2);
  // Bad requests: one line each, exit 2, nothing drawn.
  const auto refused = [&](const std::string& file, const std::string& options, const std::string& part) {
    fs::remove(shot);
    const Outcome b = run_edit(file, "", shot, options);
    EXPECT_EQ(b.code, 2) << options << ": " << b.err;
    EXPECT_NE(b.err.find(part), std::string::npos) << options << ": " << b.err;
    EXPECT_EQ(std::count(b.err.begin(), b.err.end(), '\n'), 1) << options << ": " << b.err;
    EXPECT_FALSE(fs::exists(shot)) << options;
  };
  refused(model.string(), " --edge '#99999'", "--edge: #99999 is not a B-spline or Bezier edge of");
  refused(model.string(), "", "a STEP model: name the edge to edit with --edge");
  refused(model.string(), " --edge '#" + id + ",#" + id2 + "'", "--edge: one edge to edit");
  refused(kLifted, " --edge '#" + id + "'", "--edge: for STEP models");
  fs::remove_all(dir);
#endif
}

TEST(EditOrbitWindow, BenchDragsAPointOfASpaceCurve) {
  if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed";
  const Outcome r = cmr::test::run_captured("xvfb-run -a -s '-screen 0 1280x960x24' " + std::string(CMR_BINARY) +
                                            " edit --bench " + kLifted + " --frames 5 --size 640x480");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("benchmark (orbit view): fig8b_lifted.json, 5 frames of a drag of P3"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("p95"), std::string::npos) << r.out;
  const Outcome bad = cmr::test::run_captured("xvfb-run -a -s '-screen 0 1280x960x24' " + std::string(CMR_BINARY) +
                                              " edit --bench " + kLifted + " --point 6 --frames 5");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("--point: no point 6"), std::string::npos) << bad.err;
}

}  // namespace
