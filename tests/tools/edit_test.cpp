// cmr edit, driven for real: the window opens under Xvfb, a script moves
// points, knots and toggles through the editor's input handlers, and the
// presented swapchain image is read back. Region pixels are checked against
// `cmr region` labels for the same state and view, saved files against the
// edit.
#include <gtest/gtest.h>

#include <cairo.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <vector>

#include "design/fix.hpp"
#include "design/kcurve.hpp"
#include "bezierize/knot_ops.hpp"
#include "region/region.hpp"
#include "spline/spline_json.hpp"
#include "tests/cli_util.hpp"

namespace {

using cmr::test::Outcome;
using cmr::test::run;
using cmr::test::scratch;
using cmr::test::write;
namespace fs = std::filesystem;

const std::string kFig8 = std::string(CMR_SOURCE_DIR) + "/examples/figures/fig8.json";
// A view with the same aspect as the window, around fig8's P3 (1.97, -3.83).
constexpr int kW = 320, kH = 240;
const std::string kView = "-1 -7 5 -2.5";
const std::string kViewComma = "-1,-7,5,-2.5";

double norm(cmr::Vec2 a) { return std::hypot(a.x, a.y); }

bool have_xvfb() { return std::system("command -v xvfb-run >/dev/null 2>&1") == 0; }

/// xvfb-run's options: a free display, and an X authority file of the run's
/// own (in TMPDIR, the tests' scratch folder). Without -f, xvfb-run makes a
/// temporary folder for it, and when removing that folder fails (runs
/// sharing the folder) it exits 5 before it stops its Xvfb, which then
/// outlives the test (scratch_cleanup names it).
const std::string kXvfbAuth = "-a -f \"$(mktemp)\"";

Outcome run_edit(const std::string& file, const std::string& script_text, const fs::path& shot,
                 const std::string& size = std::to_string(kW) + "x" + std::to_string(kH),
                 const std::string& options = "", const fs::path& cwd = {}) {
  const std::string script = write("edit_script.txt", script_text);
  const std::string cmd = "edit " + file + " --size " + size + options +
                          " --script " + script + " --screenshot " + shot.string();
  // xvfb-run wraps the binary: run() prefixes CMR_BINARY, so call the shell directly.
  const fs::path dir = scratch();
  const std::string line = (cwd.empty() ? std::string() : "cd '" + cwd.string() + "' && ") +
                           "xvfb-run " + kXvfbAuth + " -s '-screen 0 800x600x24' " + std::string(CMR_BINARY) + " " +
                           cmd + " >" + (dir / "eout").string() + " 2>" + (dir / "eerr").string();
  Outcome r;
  const int status = std::system(line.c_str());
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.out = cmr::test::slurp(dir / "eout");
  r.err = cmr::test::slurp(dir / "eerr");
  return r;
}

struct Image {
  int width = 0, height = 0;
  std::vector<std::array<int, 3>> rgb;
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

std::vector<uint8_t> read_pgm(const fs::path& p, int& w, int& h) {
  std::ifstream in(p, std::ios::binary);
  std::string magic;
  int maxval = 0;
  in >> magic >> w >> h >> maxval;
  in.get();
  std::vector<uint8_t> v(static_cast<std::size_t>(w) * h);
  in.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(v.size()));
  return v;
}

/// The legend of cmr region --png (draw/draw.hpp), written out here: each
/// layer takes (0, .6, .6) from white where increasing, (.6, .6, 0) where
/// decreasing; nothing otherwise.
std::array<int, 3> expected_colour(const std::vector<uint8_t>& labels_per_layer) {
  double r = 0, g = 0, b = 0;
  for (uint8_t l : labels_per_layer) {
    if (l == 1) g += 0.6, b += 0.6;
    if (l == 2) r += 0.6, g += 0.6;
  }
  const auto byte = [](double absorb) { return static_cast<int>(std::lround(255 * std::max(0.0, 1 - absorb))); };
  return {byte(r), byte(g), byte(b)};
}

/// Compares every pixel of the screenshot with the colours of the label
/// maps; returns the number of pixels per label seen (so callers can check
/// the picture is not trivially uniform).
std::array<int, 4> compare_with_labels(const Image& shot, const std::vector<fs::path>& label_files) {
  std::vector<std::vector<uint8_t>> layers;
  for (const fs::path& f : label_files) {
    int w = 0, h = 0;
    layers.push_back(read_pgm(f, w, h));
    EXPECT_EQ(w, shot.width) << f;
    EXPECT_EQ(h, shot.height) << f;
  }
  std::array<int, 4> seen{};
  int wrong = 0;
  for (std::size_t i = 0; i < shot.rgb.size() && !layers.empty() && i < layers[0].size(); ++i) {
    std::vector<uint8_t> at;
    for (const auto& l : layers) at.push_back(l[i]);
    ++seen[std::min<int>(at[0], 3)];
    const auto want = expected_colour(at);
    if (shot.rgb[i] != want && ++wrong <= 5) {
      ADD_FAILURE() << "pixel (" << i % shot.width << ", " << i / shot.width << "): screenshot " << shot.rgb[i][0]
                    << "," << shot.rgb[i][1] << "," << shot.rgb[i][2] << " but label " << int(at[0]) << " wants "
                    << want[0] << "," << want[1] << "," << want[2];
    }
  }
  EXPECT_EQ(wrong, 0);
  return seen;
}

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

class EditTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed (tools/setup.sh installs it)";
    dir_ = scratch() / ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  fs::path dir_;
};

TEST(EditNoDisplay, ExitsThreeWithOneLine) {
  const fs::path dir = scratch();
  const std::string line = "env -u DISPLAY -u WAYLAND_DISPLAY " + std::string(CMR_BINARY) + " edit " + kFig8 + " >" +
                           (dir / "nd_out").string() + " 2>" + (dir / "nd_err").string();
  const int status = std::system(line.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 3);
  const std::string err = cmr::test::slurp(dir / "nd_err");
  EXPECT_NE(err.find("no display"), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
}

// `cmr edit --bench --points N`: N is 0 (skip the locality frames) or 7..10^6;
// anything else is refused before a window opens (exit 2, one line).
TEST(EditBenchPoints, OutOfRangeIsRefusedWithOneLine) {
  const fs::path dir = scratch();
  for (const char* n : {"3", "-1", "2000000"}) {
    const std::string line = "env -u DISPLAY -u WAYLAND_DISPLAY " + std::string(CMR_BINARY) + " edit --bench --points " +
                             n + " >" + (dir / "bp_out").string() + " 2>" + (dir / "bp_err").string();
    const int status = std::system(line.c_str());
    ASSERT_TRUE(WIFEXITED(status)) << n;
    EXPECT_EQ(WEXITSTATUS(status), 2) << n;
    const std::string err = cmr::test::slurp(dir / "bp_err");
    EXPECT_NE(err.find("--points must be 0 or lie in 7..1000000"), std::string::npos) << n << ": " << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << n << ": " << err;
  }
}

TEST_F(EditTest, DragSavesTheEditedSplineAndRegionPixelsMatchCmrRegion) {
  const fs::path saved = dir_ / "saved.json", shot = dir_ / "shot.png";
  const Outcome r = run_edit(kFig8,
                             "ui off\noverlay off\nview " + kView + "\ndrag 3 2.5 -4 6\nsave " + saved.string() + "\n",
                             shot);
  ASSERT_EQ(r.code, 0) << r.err;
  // The saved spline is fig8 with P3 where the drag put it, nothing else changed.
  const nlohmann::json before = read_json(kFig8), after = read_json(saved);
  EXPECT_EQ(after["knots"], before["knots"]);
  EXPECT_EQ(after["degree"], before["degree"]);
  for (int i = 0; i < 6; ++i) {
    if (i == 3) continue;
    EXPECT_EQ(after["points"][i], before["points"][i]) << "point " << i;
  }
  EXPECT_NEAR(after["points"][3][0].get<double>(), 2.5, 1e-9);
  EXPECT_NEAR(after["points"][3][1].get<double>(), -4.0, 1e-9);
  // Every pixel is the colour of `cmr region`'s label for the saved state.
  const fs::path labels = dir_ / "labels.pgm";
  const Outcome region = run("region " + saved.string() + " --point 3 --view " + kViewComma + " --size " +
                             std::to_string(kW) + "x" + std::to_string(kH) + " --backend cpu --labels " +
                             labels.string());
  ASSERT_EQ(region.code, 0) << region.err;
  const Image img = read_png(shot);
  ASSERT_EQ(img.width, kW);
  ASSERT_EQ(img.height, kH);
  const auto seen = compare_with_labels(img, {labels});
  EXPECT_GT(seen[0], 0) << "the view should show non-monotone pixels";
  EXPECT_GT(seen[1] + seen[2], 0) << "the view should show region pixels";
}

TEST_F(EditTest, RationalSplineKeepsItsWeightsAndRegionPixelsMatchCmrRegion) {
  const std::string nurbs = std::string(CMR_SOURCE_DIR) + "/examples/rational/nurbs_cubic.json";
  const fs::path saved = dir_ / "saved.json", shot = dir_ / "shot.png";
  const Outcome r = run_edit(nurbs,
                             "ui off\noverlay off\nview 2.8 -2.6 4.4 -1.4\nknot 3 1.25\ndrag 3 3.5 -2 6\nsave " +
                                 saved.string() + "\n",
                             shot);
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json before = read_json(nurbs), after = read_json(saved);
  EXPECT_EQ(after["weights"], before["weights"]) << "moving a knot and a point keeps the weights";
  EXPECT_EQ(after["knots"][3].get<double>(), 1.25);
  EXPECT_NEAR(after["points"][3][0].get<double>(), 3.5, 1e-9);
  const fs::path labels = dir_ / "labels.pgm";
  const Outcome region = run("region " + saved.string() + " --point 3 --view 2.8,-2.6,4.4,-1.4 --size " +
                             std::to_string(kW) + "x" + std::to_string(kH) + " --backend cpu --labels " +
                             labels.string());
  ASSERT_EQ(region.code, 0) << region.err;
  const auto seen = compare_with_labels(read_png(shot), {labels});
  EXPECT_GT(seen[0], 0) << "the view should show non-monotone pixels";
  EXPECT_GT(seen[1] + seen[2], 0) << "the view should show region pixels";
}

// Weights in the editor: `weight K W` sets one (the polynomial fig8 becomes
// rational), any sign is kept (-2 is saved as -2) and |w| > 1000 is clamped
// with a note, undo takes one
// weight change back, shift+wheel over P3 scales its weight by 1.1; the saved
// JSON carries the weights, and every pixel of the screenshot is `cmr region`
// of the saved file. The region is drawn once before the weights change, so
// a cache that ignored weights would show the old region (and the old region
// differs: checked).
TEST_F(EditTest, WeightEditsAreSavedUndoneAndRegionPixelsMatchCmrRegion) {
  const fs::path clamped = dir_ / "clamped.json", saved = dir_ / "saved.json", shot = dir_ / "shot.png";
  // P3 (1.97, -3.83) in window pixels of the view -1..5 x -7..-2.5 at 320x240.
  const double px = (1.97 + 1) / 6 * kW, py = (-2.5 + 3.83) / 4.5 * kH;
  const Outcome r = run_edit(kFig8,
                             "ui off\noverlay off\nview " + kView + "\nselect 3\nwait 2\nweight 3 1.1\nweight 1 -2\nweight 4 5000\n" +
                                 "save " + clamped.string() + "\nundo\nundo\nmouse " + std::to_string(px) + " " +
                                 std::to_string(py) + "\nscroll 1 shift\nsave " + saved.string() + "\n",
                             shot);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("weight of P4 set to 1000 (clamped to -1000..1000)"), std::string::npos) << r.err;
  const nlohmann::json before = read_json(kFig8), c = read_json(clamped), after = read_json(saved);
  EXPECT_FALSE(before.contains("weights"));
  ASSERT_TRUE(c.contains("weights")) << c.dump();
  EXPECT_EQ(c["weights"], nlohmann::json({1.0, -2.0, 1.0, 1.1, 1000.0, 1.0}));
  ASSERT_TRUE(after.contains("weights")) << after.dump();
  EXPECT_EQ(after["weights"][1].get<double>(), 1.0) << "undo restores P1's weight";
  EXPECT_EQ(after["weights"][4].get<double>(), 1.0) << "undo restores P4's weight";
  EXPECT_NEAR(after["weights"][3].get<double>(), 1.1 * 1.1, 1e-12) << "shift+wheel scales P3's weight";
  EXPECT_EQ(after["points"], before["points"]);
  EXPECT_EQ(after["knots"], before["knots"]);
  const std::string size = " --size " + std::to_string(kW) + "x" + std::to_string(kH);
  const fs::path labels = dir_ / "labels.pgm", old_labels = dir_ / "old.pgm";
  const Outcome region = run("region " + saved.string() + " --point 3 --view " + kViewComma + size +
                             " --backend cpu --labels " + labels.string());
  ASSERT_EQ(region.code, 0) << region.err;
  const auto seen = compare_with_labels(read_png(shot), {labels});
  EXPECT_GT(seen[0], 0) << "the view should show non-monotone pixels";
  EXPECT_GT(seen[1] + seen[2], 0) << "the view should show region pixels";
  const Outcome old = run("region " + kFig8 + " --point 3 --view " + kViewComma + size + " --backend cpu --labels " +
                          old_labels.string());
  ASSERT_EQ(old.code, 0) << old.err;
  int w = 0, h = 0;
  const std::vector<uint8_t> a = read_pgm(labels, w, h), b = read_pgm(old_labels, w, h);
  EXPECT_NE(a, b) << "the weight must change P3's region, or the test proves nothing about the cache";
}

TEST_F(EditTest, KnotMoveModeToggleAndAllPointsMatchCmrRegion) {
  const fs::path saved = dir_ / "saved.json", shot = dir_ / "shot.png";
  const Outcome r = run_edit(kFig8,
                             "ui off\noverlay off\nview " + kView + "\nknot 4 3.6\nmode cmr\nall on\nsave " +
                                 saved.string() + "\n",
                             shot);
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json after = read_json(saved);
  EXPECT_EQ(after["knots"][4].get<double>(), 3.6);
  const fs::path labels = dir_ / "labels.pgm";
  const Outcome region = run("region " + saved.string() + " --point all --mode cmr --view " + kViewComma +
                             " --size " + std::to_string(kW) + "x" + std::to_string(kH) +
                             " --backend cpu --labels " + labels.string());
  ASSERT_EQ(region.code, 0) << region.err;
  std::vector<fs::path> layers;
  for (int k = 0; k < 6; ++k) layers.push_back(dir_ / ("labels.P" + std::to_string(k) + ".pgm"));
  compare_with_labels(read_png(shot), layers);
}

TEST_F(EditTest, UndoRestoresAndRedoReapplies) {
  const fs::path undone = dir_ / "undone.json", redone = dir_ / "redone.json", shot = dir_ / "shot.png";
  const Outcome r = run_edit(kFig8,
                             "view " + kView + "\ndrag 3 2.5 -4 4\nknot 4 3.5\nundo\nundo\nsave " + undone.string() +
                                 "\nredo\nsave " + redone.string() + "\n",
                             shot);
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json before = read_json(kFig8);
  EXPECT_EQ(read_json(undone)["points"], before["points"]);
  EXPECT_EQ(read_json(undone)["knots"], before["knots"]);
  const nlohmann::json re = read_json(redone);
  EXPECT_NEAR(re["points"][3][0].get<double>(), 2.5, 1e-9);
  EXPECT_EQ(re["knots"], before["knots"]) << "redo reapplies the drag only";
}

TEST_F(EditTest, DepthShadingChangesThePicture) {
  const fs::path plain = dir_ / "plain.png", shaded = dir_ / "shaded.png";
  const std::string base = "ui off\noverlay off\nview " + kView + "\n";
  ASSERT_EQ(run_edit(kFig8, base, plain).code, 0);
  ASSERT_EQ(run_edit(kFig8, base + "shading on\n", shaded).code, 0);
  const Image a = read_png(plain), b = read_png(shaded);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  int white_a = 0, white_b = 0, differ = 0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) {
    white_a += a.rgb[i] == std::array<int, 3>{255, 255, 255};
    white_b += b.rgb[i] == std::array<int, 3>{255, 255, 255};
    differ += a.rgb[i] != b.rgb[i];
  }
  EXPECT_GT(white_a, 0) << "plain: not monotone is white";
  EXPECT_EQ(white_b, 0) << "Fig. 7 shading: not monotone is grey";
  EXPECT_EQ(differ, static_cast<int>(a.rgb.size())) << "every pixel is shaded by its level";
}

TEST_F(EditTest, KnotOperationsAndRulerDragThroughTheWindow) {
  const fs::path a = dir_ / "a.json", b = dir_ / "b.json", c = dir_ / "c.json", d = dir_ / "d.json";
  const Outcome r = run_edit(kFig8,
                             "insert 3.5\nremove 3\nsave " + a.string() + "\ndrag-knot 4 3.8 8\nsave " + b.string() +
                                 "\nelevate\nclamp\nuniform\nsave " + c.string() + "\nundo\nundo\nsave " +
                                 d.string() + "\n",
                             dir_ / "shot.png", "1024x768");  // the panels need room
  ASSERT_EQ(r.code, 0) << r.err;
  // Insertion keeps the curve: the knot_ops result, bit for bit.
  const cmr::BSpline fig8 = cmr::read_spline_file(kFig8);
  const cmr::BSpline inserted = cmr::insert_knot(fig8, 3.5, 1);
  const cmr::BSpline sa = cmr::read_spline_file(a);
  EXPECT_EQ(sa.knots(), inserted.knots());
  EXPECT_EQ(sa.points(), inserted.points());
  // Knot 3 of fig8 is not removable within the default tolerance: refused, said, nothing changed.
  EXPECT_NE(r.err.find("refused: removing knot 3"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("more than the tolerance"), std::string::npos) << r.err;
  // The pointer dragged knot 4 (3.5) along the ruler to about 3.8 (a pixel
  // of the ruler is under (7 - 0) / 300 in knot units); nothing else moved.
  const cmr::BSpline sb = cmr::read_spline_file(b);
  EXPECT_NEAR(sb.knots()[4], 3.8, 0.03);
  EXPECT_NE(sb.knots()[4], 3.5);
  std::vector<double> others = sb.knots();
  others[4] = 3.5;
  EXPECT_EQ(others, inserted.knots());
  EXPECT_EQ(sb.points(), inserted.points());
  // Elevation, clamping, uniform knots: knot_ops' results; two undos go back to elevate.
  const cmr::BSpline elevated = cmr::elevate_degree(sb);
  const cmr::BSpline want = cmr::make_uniform(cmr::clamp(elevated));
  const cmr::BSpline sc = cmr::read_spline_file(c);
  EXPECT_EQ(sc.degree(), 4);
  EXPECT_EQ(sc.knots(), want.knots());
  EXPECT_EQ(sc.points(), want.points());
  const cmr::BSpline sd = cmr::read_spline_file(d);
  EXPECT_EQ(sd.knots(), elevated.knots());
  EXPECT_EQ(sd.points(), elevated.points());
}

TEST_F(EditTest, ResizeRecreatesTheSwapchainAndExportsAreCmrRegions) {
  const fs::path view_png = dir_ / "view.png", region_png = dir_ / "region.png", region_pgm = dir_ / "region.pgm",
                 shot = dir_ / "shot.png";
  constexpr int W = 400, H = 300;
  const Outcome r = run_edit(kFig8,
                             "ui off\noverlay off\nselect 3\nresize 400 300\nview " + kView + "\nexport-view " +
                                 view_png.string() + "\nexport-region " + region_png.string() + "\nexport-region " +
                                 region_pgm.string() + "\n",
                             shot);
  ASSERT_EQ(r.code, 0) << r.err;
  const Image s = read_png(shot), v = read_png(view_png);
  ASSERT_EQ(s.width, W) << "the swapchain follows the window";
  ASSERT_EQ(s.height, H);
  EXPECT_TRUE(v.rgb == s.rgb) << "export-view writes the presented frame";
  // The exports are what `cmr region` writes for the same state, view and size.
  const std::string size = " --size " + std::to_string(W) + "x" + std::to_string(H);
  const Outcome cli = run("region " + kFig8 + " --point 3 --view " + kViewComma + size + " --backend cpu --png " +
                          (dir_ / "cli.png").string() + " --labels " + (dir_ / "cli.pgm").string());
  ASSERT_EQ(cli.code, 0) << cli.err;
  EXPECT_EQ(cmr::test::slurp(region_pgm), cmr::test::slurp(dir_ / "cli.pgm"));
  EXPECT_EQ(cmr::test::slurp(region_png), cmr::test::slurp(dir_ / "cli.png"));
  const auto seen = compare_with_labels(s, {dir_ / "cli.pgm"});
  EXPECT_GT(seen[1] + seen[2], 0) << "the view should show region pixels";
}

// On lavapipe under Xvfb (MIT-SHM offered) frames reach the window through
// MIT-SHM, after a resize too; CMR_EDIT_PRESENT=swapchain takes the
// swapchain, and both paths present the same bytes.
TEST_F(EditTest, PresentsThroughMitShmOnACpuDeviceAndTheSwapchainShowsTheSame) {
  const std::string script = "ui off\noverlay off\nselect 3\nresize 400 300\nview " + kView + "\n";
  const fs::path shm_png = dir_ / "shm.png", swapchain_png = dir_ / "swapchain.png";
  const Outcome shm = run_edit(kFig8, script, shm_png);
  ASSERT_EQ(shm.code, 0) << shm.err;
  if (shm.err.find("is a CPU") == std::string::npos) GTEST_SKIP() << "not a CPU Vulkan device: " << shm.err;
  EXPECT_NE(shm.err.find("; presented through MIT-SHM"), std::string::npos) << shm.err;
  ::setenv("CMR_EDIT_PRESENT", "swapchain", 1);
  const Outcome sc = run_edit(kFig8, script, swapchain_png);
  ::unsetenv("CMR_EDIT_PRESENT");
  ASSERT_EQ(sc.code, 0) << sc.err;
  EXPECT_NE(sc.err.find("; presented through the Vulkan swapchain (MIT-SHM switched off)"), std::string::npos)
      << sc.err;
  const Image a = read_png(shm_png), b = read_png(swapchain_png);
  ASSERT_EQ(a.width, 400) << "the offscreen image follows the window";
  ASSERT_EQ(a.height, 300);
  EXPECT_TRUE(a.rgb == b.rgb) << "MIT-SHM and the swapchain present the same pixels";
}

// An X server without MIT-SHM (Xvfb -extension MIT-SHM): the swapchain,
// and the startup line says why.
TEST_F(EditTest, FallsBackToTheSwapchainWithoutMitShm) {
  const std::string script = write("edit_script.txt", "ui off\nselect 3\n");
  const fs::path err = dir_ / "noshm.err";
  const std::string line = "xvfb-run " + kXvfbAuth + " -s '-screen 0 800x600x24 -extension MIT-SHM' " + std::string(CMR_BINARY) +
                           " edit " + kFig8 + " --size 320x240 --script " + script + " --screenshot " +
                           (dir_ / "noshm.png").string() + " >/dev/null 2>" + err.string();
  const int status = std::system(line.c_str());
  const std::string text = cmr::test::slurp(err);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << text;
  if (text.find("is a CPU") == std::string::npos) GTEST_SKIP() << "not a CPU Vulkan device: " << text;
  EXPECT_NE(text.find("; presented through the Vulkan swapchain (MIT-SHM not used: the X server has no MIT-SHM)"),
            std::string::npos)
      << text;
  EXPECT_EQ(read_png(dir_ / "noshm.png").width, 320) << "the swapchain presented";
}

TEST_F(EditTest, KappaCurveModeClicksModifiesAndShowsTheHandlesRegion) {
  // Fig. 13's closed six-point blob, clicked at whole pixels of a known view.
  const cmr::View v{-2, -1.5, 7, 5.25};  // 320x240: square pixels
  const std::vector<std::array<int, 2>> clicks = {{71, 178}, {178, 196}, {249, 142}, {213, 64}, {124, 53}, {53, 107}};
  std::string script = "ui off\nview -2 -1.5 7 5.25\nkcurve points\nclosed on\n";
  std::vector<cmr::Vec2> points;
  for (const auto& [px, py] : clicks) {
    script += "mouse " + std::to_string(px) + " " + std::to_string(py) + "\npress left\nrelease left\n";
    points.push_back({v.x0 + (v.x1 - v.x0) * px / kW, v.y1 - (v.y1 - v.y0) * py / kH});  // Viewport::to_world
  }
  const cmr::KCurve kc = cmr::kcurve(points, {.closed = true});
  const cmr::BSpline chain = cmr::kcurve_cubic_chain(kc);
  int k = -1;
  for (int m : cmr::kcurve_cubic_maxima(kc))
    if (m > 0 && k < 0) k = m;
  ASSERT_GE(k, 3);
  const auto& P = chain.points();
  // Fig. 13c's move: P_{k+1} turned by -0.05 rad about P_k and pulled in to 0.9.
  const cmr::Vec2 d = P[k + 1] - P[k];
  const double c = std::cos(-0.05), sn = std::sin(-0.05);
  const cmr::Vec2 target = P[k] + 0.9 * cmr::Vec2(c * d.x - sn * d.y, sn * d.x + c * d.y);
  const fs::path quad = dir_ / "quad.json", start = dir_ / "chain.json", edited = dir_ / "edited.json",
                 shot = dir_ / "shot.png";
  script += "save " + quad.string() + "\nkcurve modify\nsave " + start.string() + "\nselect " +
            std::to_string(k + 1) + "\noverlay off\ndrag " + std::to_string(k + 1) + " " +
            std::to_string(target.x) + " " + std::to_string(target.y) + " 6\nsave " + edited.string() + "\n";
  const Outcome r = run_edit(kFig8, script, shot);
  ASSERT_EQ(r.code, 0) << r.err;
  // The clicks made the κ-curve, and modify its cubic chain (knot_ops-free: kcurve.hpp's own results).
  const cmr::BSpline q = cmr::read_spline_file(quad), s0 = cmr::read_spline_file(start);
  EXPECT_EQ(q.points(), cmr::kcurve_quadratic_spline(kc).points());
  EXPECT_EQ(s0.points(), chain.points());
  EXPECT_EQ(s0.knots(), chain.knots());
  // The drag moved the handle pair only, keeping it collinear through P_k (G1)
  // and the opposite handle's length.
  const cmr::BSpline s1 = cmr::read_spline_file(edited);
  const auto& Q = s1.points();
  for (int i = 0; i < s1.point_count(); ++i) {
    if (i == k - 1 || i == k + 1) continue;
    EXPECT_EQ(Q[i], P[i]) << "point " << i;
  }
  EXPECT_LT(norm(Q[k + 1] - target), 0.05) << "the handle is where the drag left it";
  const cmr::Vec2 in = Q[k] - Q[k - 1], out = Q[k + 1] - Q[k];
  EXPECT_LT(std::abs(cmr::det(in, out)) / (norm(in) * norm(out)), 1e-12) << "G1 at P_k";
  EXPECT_GT(cmr::dot(in, out), 0);
  EXPECT_NEAR(norm(in), norm(P[k] - P[k - 1]), 1e-12);
  // Every pixel is the colour of RegionProblem::classify for P_{k+1} in the
  // piece after P_k (as a Bezier curve), for the edited state.
  const cmr::BSpline piece = cmr::BSpline::bezier({Q[k], Q[k + 1], Q[k + 2], Q[k + 3]});
  cmr::RegionRequest rq;
  rq.point = 1;
  rq.view = v;
  rq.width = kW;
  rq.height = kH;
  const cmr::RegionProblem problem = cmr::RegionProblem::make(piece, rq);
  const Image img = read_png(shot);
  ASSERT_EQ(img.width, kW);
  int wrong = 0, monotone = 0;
  for (int j = 0; j < kH; ++j)
    for (int i = 0; i < kW; ++i) {
      const cmr::Direction l = problem.classify(cmr::pixel_center(v, kW, kH, i, j)).label;
      monotone += l != cmr::Direction::none;
      const auto want = expected_colour({cmr::code(l)});
      if (img.rgb[j * kW + i] != want && ++wrong <= 5) ADD_FAILURE() << "pixel " << i << "," << j;
    }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(monotone, 0) << "the handle's region is in view";
  // Where the handle went, its piece still has monotone curvature: no new extremum.
  EXPECT_EQ(problem.classify(Q[k + 1]).label, cmr::Direction::decreasing);
}

TEST_F(EditTest, GpuPathDrawsTheCpuLabelsIntoTheWindow) {
  // The region shader drawn straight into the swapchain image (forced on
  // lavapipe): after a few frames (uncertain pixels decided on the host) every
  // pixel is the colour of `cmr region`'s CPU labels.
  const std::string size = std::to_string(kW) + "x" + std::to_string(kH);
  const std::string base = "ui off\noverlay off\nview " + kView + "\n";
  {
    const fs::path shot = dir_ / "one.png", labels = dir_ / "one.pgm";
    const Outcome r = run_edit(kFig8, base + "select 3\nwait 4\n", shot, size, " --region-path gpu");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("region shader drawn into the window"), std::string::npos) << r.err;
    ASSERT_EQ(run("region " + kFig8 + " --point 3 --view " + kViewComma + " --size " + size +
                  " --backend cpu --labels " + labels.string())
                  .code,
              0);
    const auto seen = compare_with_labels(read_png(shot), {labels});
    EXPECT_GT(seen[1] + seen[2], 0) << "the view should show region pixels";
  }
  {
    const fs::path shot = dir_ / "all.png";
    const Outcome r = run_edit(kFig8, base + "all on\nmode cmr\nwait 4\n", shot, size, " --region-path gpu");
    ASSERT_EQ(r.code, 0) << r.err;
    ASSERT_EQ(run("region " + kFig8 + " --point all --mode cmr --view " + kViewComma + " --size " + size +
                  " --backend cpu --labels " + (dir_ / "all.pgm").string())
                  .code,
              0);
    std::vector<fs::path> layers;
    for (int k = 0; k < 6; ++k) layers.push_back(dir_ / ("all.P" + std::to_string(k) + ".pgm"));
    compare_with_labels(read_png(shot), layers);
  }
  {
    // fp32 arithmetic on a boundary zoomed 1000 times: the shader cannot
    // certify some pixels; the host decides them and the window shows the
    // CPU labels all the same.
    const std::string zoom = "1.15225,-3.637375,1.16025,-3.631375";
    std::string script = "ui off\noverlay off\nselect 3\nview " + zoom + "\nwait 4\n";
    std::replace(script.begin(), script.end(), ',', ' ');
    const fs::path shot = dir_ / "zoom.png", labels = dir_ / "zoom.pgm";
    const Outcome r = run_edit(kFig8, script, shot, size, " --region-path gpu --precision fp32");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto at = r.err.rfind(" pixels decided on the host");
    ASSERT_NE(at, std::string::npos) << r.err;
    const auto from = r.err.rfind(' ', at - 1) + 1;
    const std::string count = r.err.substr(from, at - from);
    ASSERT_FALSE(count.empty()) << r.err;
    EXPECT_GT(std::atoi(count.c_str()), 0) << "the override path should be exercised: " << r.err;
    ASSERT_EQ(run("region " + kFig8 + " --point 3 --view " + zoom + " --size " + size + " --backend cpu --labels " +
                  labels.string())
                  .code,
              0);
    const auto seen = compare_with_labels(read_png(shot), {labels});
    EXPECT_GT(seen[0], 0);
    EXPECT_GT(seen[1] + seen[2], 0) << "the zoomed view should hold the boundary";
  }
  // Split labels (their darker legend) and depth shading (drawn by the
  // upload path inside the gpu painter): the same bytes as the upload path.
  for (const std::string& extra : {std::string("select 3\nsplit 2\n"), std::string("select 3\nshading on\n")}) {
    const std::string script = base + extra + "wait 4\n";
    const fs::path gpu = dir_ / "same_gpu.png", upload = dir_ / "same_upload.png";
    ASSERT_EQ(run_edit(kFig8, script, gpu, size, " --region-path gpu").code, 0);
    ASSERT_EQ(run_edit(kFig8, script, upload, size, " --region-path upload").code, 0);
    const Image a = read_png(gpu), b = read_png(upload);
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    EXPECT_TRUE(a.rgb == b.rgb) << extra;
    int coloured = 0;
    for (const auto& c : a.rgb) coloured += c != std::array<int, 3>{255, 255, 255};
    EXPECT_GT(coloured, 0) << extra;
  }
}

TEST_F(EditTest, SegmentRangeIsWhatCmrRegionJudges) {
  const fs::path shot = dir_ / "shot.png", labels = dir_ / "labels.pgm", all = dir_ / "all.pgm";
  const Outcome r = run_edit(kFig8, "ui off\noverlay off\nview " + kView + "\nselect 3\nsegments 1..2\n", shot);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string common = " --point 3 --view " + kViewComma + " --size " + std::to_string(kW) + "x" +
                             std::to_string(kH) + " --backend cpu --labels ";
  ASSERT_EQ(run("region " + kFig8 + " --segments 1..2" + common + labels.string()).code, 0);
  ASSERT_EQ(run("region " + kFig8 + common + all.string()).code, 0);
  const auto seen = compare_with_labels(read_png(shot), {labels});
  EXPECT_GT(seen[1] + seen[2], 0);
  EXPECT_NE(cmr::test::slurp(labels), cmr::test::slurp(all)) << "the range should change the region in this view";
  // A range the curve lacks is a bad script line: exit 2, one message.
  const Outcome bad = run_edit(kFig8, "segments 1..7\n", dir_ / "bad.png");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("the curve has segments 0..2"), std::string::npos) << bad.err;
}

TEST_F(EditTest, BadScriptIsAnInputError) {
  const Outcome r = run_edit(kFig8, "jump 3\n", dir_ / "x.png");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("unknown command 'jump'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "x.png"));
}

// The opening selection (Editor::open_on_region_point, tested in detail in
// edit_repair_test.cpp) through `cmr edit`: the first point whose region
// shows, or --point's; a point the curve lacks is a bad option (exit 2).
TEST_F(EditTest, OpensOnAPointWithARegionOrTheNamedOne) {
  const Outcome r = run_edit(kFig8, "status\n", dir_ / "a.png", "1024x768");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto at = r.err.find("script line 1: selected P");
  ASSERT_NE(at, std::string::npos) << r.err;
  const std::string k = r.err.substr(at + 25, 1);
  EXPECT_NE(k, "0") << "fig8's P0 has no region: " << r.err;
  EXPECT_NE(r.err.find("opened on P" + k + ": the first point whose region shows in this view"), std::string::npos)
      << r.err;
  const Outcome named = run_edit(kFig8, "status\n", dir_ / "b.png", "1024x768", " --point 0");
  ASSERT_EQ(named.code, 0) << named.err;
  EXPECT_NE(named.err.find("selected P0; opened on P0 (--point); segment 1 is non-monotone whatever P0 does"),
            std::string::npos)
      << named.err;
  const Outcome bad = run_edit(kFig8, "status\n", dir_ / "c.png", "1024x768", " --point 6");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("--point: the curve has points 0..5 (got 6)"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir_ / "c.png"));
  // Fig. 10, a closed contour (its points' supports judged), and a quadratic
  // zigzag where no point has a region: the status line of the opened window.
  std::vector<cmr::Vec2> ellipse, zig;
  std::vector<double> knots;
  for (int i = 0; i < 20; ++i) {
    const double a = 2 * M_PI * i / 20;
    ellipse.push_back({2 * std::cos(a), std::sin(a)});
    knots.push_back(i);
  }
  knots.push_back(20);
  for (int i = 0; i < 8; ++i) zig.push_back({static_cast<double>(i), i % 2 ? 1.0 : -1.0});
  const fs::path closed = dir_ / "closed.json", zigzag = dir_ / "zigzag.json";
  std::ofstream(closed) << cmr::spline_to_json(cmr::BSpline::make_closed(3, knots, ellipse)).dump();
  std::ofstream(zigzag) << cmr::spline_to_json(cmr::BSpline::make(2, {0, 1, 2, 3, 4, 5, 6, 7, 8}, zig)).dump();
  for (const std::string& f : {std::string(CMR_SOURCE_DIR) + "/examples/figures/fig10a.json", closed.string()}) {
    const Outcome o = run_edit(f, "status\n", dir_ / "d.png", "1024x768");
    ASSERT_EQ(o.code, 0) << o.err;
    const bool first = o.err.find(": the first point whose region shows in this view") != std::string::npos;
    const bool largest = o.err.find(": the largest region in this view, and a small one") != std::string::npos;
    EXPECT_TRUE(first || largest) << f << o.err;
  }
  const Outcome none = run_edit(zigzag.string(), "status\n", dir_ / "e.png", "1024x768");
  ASSERT_EQ(none.code, 0) << none.err;
  EXPECT_NE(none.err.find("selected P0; no point has a region in this view: segments 1..5 are non-monotone whatever "
                          "P0 does (P0 acts on segment 0)"),
            std::string::npos)
      << none.err;
}

// fix and snap as scripted commands and keys in the real window: the fixed
// curve passes analyze for the view's requirement, snap puts the selected
// point in its region by bezierize/fix's distance, undo restores the exact
// coordinates. The screenshots before and after are kept for a look.
TEST_F(EditTest, FixAndSnapThroughTheWindowAreCertifiedAndUndone) {
  const fs::path fixed = dir_ / "fixed.json", undone = dir_ / "undone.json", snapped = dir_ / "snapped.json",
                 split = dir_ / "split.json", back = dir_ / "back.json";
  const Outcome r = run_edit(kFig8,
                             "select 2\nscreenshot " + (dir_ / "before.png").string() + "\nfix\nscreenshot " +
                                 (dir_ / "after.png").string() + "\nsave " + fixed.string() + "\nundo\nsave " +
                                 undone.string() + "\nkey s\nsave " + snapped.string() + "\nundo\nsplit 2\nkey x\nsave " +
                                 split.string() + "\nundo\nsave " + back.string() + "\n",
                             dir_ / "shot.png", "1024x768");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("script line 3: fix (cmrwi): moved P"), std::string::npos) << r.err;
  const cmr::BSpline fig8 = cmr::read_spline_file(kFig8);
  const cmr::FixRequirement cmrwi = cmr::parse_fix_requirement("cmrwi");
  const cmr::BSpline f = cmr::read_spline_file(fixed);
  EXPECT_TRUE(cmr::requirement_holds(f, cmrwi)) << "the fixed curve, re-judged by analyze";
  EXPECT_NE(f.points(), fig8.points());
  EXPECT_EQ(read_json(undone)["points"], read_json(kFig8)["points"]) << "undo restores the exact coordinates";
  // snap (key s): P2 alone, by the distance bezierize/fix finds, into its region.
  cmr::FixRequest q;
  q.requirement = cmrwi;
  q.points = {2};
  q.keep = cmr::Keep::none;
  const cmr::FixResult want = cmr::fix(fig8, q);
  ASSERT_TRUE(want.fixed) << want.reason;
  const cmr::BSpline s = cmr::read_spline_file(snapped);
  for (int i = 0; i < 6; ++i)
    if (i != 2) {
      EXPECT_EQ(s.points()[i], fig8.points()[i]) << "P" << i;
    }
  EXPECT_DOUBLE_EQ(norm(s.points()[2] - fig8.points()[2]), want.moves.at(0).distance);
  cmr::RegionRequest rq;
  rq.point = 2;
  const cmr::Direction l = cmr::RegionProblem::make(fig8, rq).classify(s.points()[2]).label;
  EXPECT_TRUE(l == cmr::Direction::increasing || l == cmr::Direction::decreasing) << "P2 is in its region";
  // split 2 then key x: the fix of split:2.
  EXPECT_NE(r.err.find("fix (split:2): moved P"), std::string::npos) << r.err;
  EXPECT_TRUE(cmr::requirement_holds(cmr::read_spline_file(split), cmr::parse_fix_requirement("split:2")));
  EXPECT_EQ(read_json(back)["points"], read_json(kFig8)["points"]);
  // The picture changed where the curve moved.
  const Image a = read_png(dir_ / "before.png"), b = read_png(dir_ / "after.png");
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  EXPECT_NE(a.rgb, b.rgb);
}


// ---- issue 21: the designer's legend, numbers, comb (tools/edit/designer.hpp) ----

/// The legend lines the script's `legend` command printed: kind, the colour's
/// bytes (and a gradient's deep end), the words.
struct LegendLine {
  std::string kind;
  std::array<int, 3> from{}, to{};
  std::string text;
};

std::vector<LegendLine> legend_lines(const std::string& err) {
  std::vector<LegendLine> out;
  std::istringstream in(err);
  for (std::string line; std::getline(in, line);) {
    const std::string tag = "cmr edit: legend ";
    if (line.rfind(tag, 0) != 0) continue;
    std::istringstream w(line.substr(tag.size()));
    LegendLine l;
    std::string a, b;
    w >> l.kind >> a >> b;
    std::getline(w >> std::ws, l.text);
    if (sscanf(a.c_str(), "%d,%d,%d", &l.from[0], &l.from[1], &l.from[2]) != 3) continue;
    if (sscanf(b.c_str(), "%d,%d,%d", &l.to[0], &l.to[1], &l.to[2]) != 3) continue;
    out.push_back(l);
  }
  return out;
}

TEST_F(EditTest, LegendNamesEveryColourShownInEachMode) {
  // The canvas without panels or overlay: every pixel is a region colour,
  // and each must be a swatch of the legend (depth shading: within one of
  // its gradients).
  const std::string base = "ui off\noverlay off\nview " + kView + "\nselect 3\n";
  const std::vector<std::pair<std::string, std::string>> modes = {
      {"cmrwi", ""},          {"cmr", "mode cmr\n"},         {"split 2", "split 2\n"},
      {"each piece", "chain on\n"}, {"depth shading", "shading on\n"}, {"all points", "all on\n"},
      {"all points but P3", "all on\nshow-point 3 off\n"}};
  for (const auto& [name, script] : modes) {
    const fs::path shot = dir_ / "legend.png";
    const Outcome r = run_edit(kFig8, base + script + "legend\n", shot);
    ASSERT_EQ(r.code, 0) << name << ": " << r.err;
    const std::vector<LegendLine> legend = legend_lines(r.err);
    ASSERT_FALSE(legend.empty()) << name << ": " << r.err;
    EXPECT_NE(r.err.find("cmr edit: legend: "), std::string::npos) << "a title: " << r.err;
    const Image img = read_png(shot);
    ASSERT_EQ(img.width, kW);
    std::set<std::array<int, 3>> shown(img.rgb.begin(), img.rgb.end());
    EXPECT_GE(shown.size(), name == "all points but P3" ? 1u : 2u) << name;
    for (const auto& c : shown) {
      const bool named = std::any_of(legend.begin(), legend.end(), [&](const LegendLine& l) {
        if (l.kind == "swatch") return l.from == c;
        if (l.kind != "gradient") return false;
        for (int k = 0; k < 3; ++k)
          if (c[k] < std::min(l.from[k], l.to[k]) - 1 || c[k] > std::max(l.from[k], l.to[k]) + 1) return false;
        return true;
      });
      EXPECT_TRUE(named) << name << ": colour " << c[0] << "," << c[1] << "," << c[2] << " is not in the legend\n"
                         << r.err;
    }
    if (name.rfind("all points", 0) == 0)  // each shown point's outline hue, under its name
      for (int k = 0; k < 6; ++k) {
        std::string want = "P";  // (built with +=: GCC 12 warns falsely on "P" + std::to_string)
        want += std::to_string(k);
        want += "'s region";
        const bool listed = std::any_of(legend.begin(), legend.end(),
                                        [&](const LegendLine& l) { return l.kind == "outline" && l.text.rfind(want, 0) == 0; });
        EXPECT_EQ(listed, !(name == "all points but P3" && k == 3)) << name << " P" << k;
      }
  }
}

TEST_F(EditTest, TypedCoordinatesMoveThePointExactly) {
  // The pointer clicks into the panel's x, y and w fields and types, as a
  // user does; the saved file holds exactly the doubles typed.
  const fs::path saved = dir_ / "typed.json";
  const std::string x = "2.123456789012345", y = "-4.4400000000000004", w = "1.75";
  const Outcome r = run_edit(kFig8,
                             "select 3\ntype x " + x + "\ntype y " + y + "\ntype w " + w + "\nsave " +
                                 saved.string() + "\nscreenshot " + (dir_ / "typed.png").string() + "\n",
                             dir_ / "shot.png", "1024x768");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json before = read_json(kFig8), after = read_json(saved);
  EXPECT_EQ(after["points"][3][0].get<double>(), std::strtod(x.c_str(), nullptr)) << "bit for bit";
  EXPECT_EQ(after["points"][3][1].get<double>(), std::strtod(y.c_str(), nullptr)) << "bit for bit";
  for (int i = 0; i < 6; ++i)
    if (i != 3) {
      EXPECT_EQ(after["points"][i], before["points"][i]) << "point " << i;
    }
  ASSERT_TRUE(after.contains("weights")) << after.dump();
  EXPECT_EQ(after["weights"][3].get<double>(), 1.75);
  const Outcome bad = run_edit(kFig8, "ui off\ntype x 1\n", dir_ / "bad.png", "1024x768");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("type: no field 'x' is shown"), std::string::npos) << bad.err;
}

/// The comb's pixels (its dark greens) in a screenshot without panels: some,
/// and none on the window's outer frame (a comb that runs off the canvas
/// reaches the edge).
void expect_comb_inside(const Image& img, const std::string& what) {
  int comb = 0, edge = 0;
  for (int j = 0; j < img.height; ++j)
    for (int i = 0; i < img.width; ++i) {
      const auto& c = img.rgb[j * img.width + i];
      if (!(c[1] > c[0] + 35 && c[1] > c[2] + 35 && c[1] < 200)) continue;
      ++comb;
      if (i < 3 || j < 3 || i >= img.width - 3 || j >= img.height - 3) ++edge;
    }
  EXPECT_GT(comb, 200) << what << ": the comb is drawn";
  EXPECT_EQ(edge, 0) << what << ": the comb reaches the window's edge";
}

TEST_F(EditTest, CombFitsTheViewOnFig8AndOnAGlyph) {
  const fs::path fig8 = dir_ / "comb_fig8.png";
  // fit (key f) frames the curve and its comb; the comb fits that view.
  const Outcome r = run_edit(kFig8, "ui off\nfit\n", fig8, "640x480");
  ASSERT_EQ(r.code, 0) << r.err;
  expect_comb_inside(read_png(fig8), "fig8");
  const std::string font = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
  if (!fs::exists(font)) GTEST_SKIP() << font << " is missing (fonts-dejavu-core)";
  const Outcome imp = run("import " + font + " --glyphs O --out " + (dir_ / "glyph").string());
  ASSERT_EQ(imp.code, 0) << imp.err;
  const fs::path glyph = dir_ / "comb_glyph.png";
  const Outcome g = run_edit((dir_ / "glyph" / "O_c0.json").string(), "ui off\nfit\n", glyph, "640x480");
  ASSERT_EQ(g.code, 0) << g.err;
  expect_comb_inside(read_png(glyph), "glyph O");
}


// ---- issue 21, item 5: a font's glyph and an SVG's paths opened directly ----

const std::string kFont = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

/// The fields cmr import writes and the editor saves: they must agree.
void expect_same_curve(const fs::path& saved, const fs::path& imported) {
  const nlohmann::json a = read_json(saved), b = read_json(imported);
  for (const char* k : {"degree", "knots", "points", "closed", "point_names", "weights"})
    EXPECT_EQ(a.contains(k) ? a[k] : nlohmann::json(), b.contains(k) ? b[k] : nlohmann::json()) << saved << " " << k;
}

TEST_F(EditTest, GlyphFromAFontOpensAllContoursWithTheReportsNames) {
  if (!fs::exists(kFont)) GTEST_SKIP() << kFont << " is missing (fonts-dejavu-core)";
  const Outcome imp = run("import " + kFont + " --glyphs O --out " + (dir_ / "imported").string());
  ASSERT_EQ(imp.code, 0) << imp.err;
  const cmr::BSpline c0 = cmr::read_spline_file(dir_ / "imported" / "O_c0.json");
  const cmr::BSpline c1 = cmr::read_spline_file(dir_ / "imported" / "O_c1.json");
  // ui off, a known view: the points of both contours are drawn (the active
  // one's white or red markers, the other's light grey).
  const cmr::View v{-100, -100, 1700, 1700};
  const int W = 400, H = 400;
  const fs::path shot = dir_ / "glyph.png";
  const Outcome r = run_edit(kFont,
                             "ui off\ncomb off\nview -100 -100 1700 1700\nstatus\nscreenshot " + shot.string() +
                                 "\ncontour 1\nstatus\nsave-all\nglyph C\nstatus\n",
                             dir_ / "last.png", "400x400", " --glyph O", dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("cmr edit: glyph O of DejaVuSans.ttf: 2 contours (O/c0, O/c1)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("(O/c0/p"), std::string::npos) << "the report's node names: " << r.err;
  EXPECT_NE(r.err.find("selected P0 (O/c1/p0); editing O/c1 (2 of 2)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("saved 2 spline JSON files: ./O_c0.json, ./O_c1.json"), std::string::npos) << r.err;
  // The glyph picker (the panel's glyph field; the script's glyph): C's one contour.
  EXPECT_NE(r.err.find("selected P0 (C/c0/p0); opened glyph C of DejaVuSans.ttf: 1 contour"), std::string::npos)
      << r.err;
  expect_same_curve(dir_ / "O_c0.json", dir_ / "imported" / "O_c0.json");
  expect_same_curve(dir_ / "O_c1.json", dir_ / "imported" / "O_c1.json");
  const Image img = read_png(shot);
  ASSERT_EQ(img.width, W);
  const auto pixel = [&](cmr::Vec2 p) {
    const int i = static_cast<int>((p.x - v.x0) / (v.x1 - v.x0) * W), j = static_cast<int>((v.y1 - p.y) / (v.y1 - v.y0) * H);
    if (i < 0 || j < 0 || i >= W || j >= H) return std::array<int, 3>{-1, -1, -1};  // out of view: fails below
    return img.rgb[j * W + i];
  };
  for (int k = 0; k < c0.unique_point_count(); ++k) {
    const auto c = pixel(c0.points()[k]);
    EXPECT_TRUE(c == (std::array<int, 3>{255, 255, 255}) || c == (std::array<int, 3>{230, 30, 30}))
        << "O/c0/p" << k << " (active) drawn: " << c[0] << "," << c[1] << "," << c[2];
  }
  for (int k = 0; k < c1.unique_point_count(); ++k)
    EXPECT_EQ(pixel(c1.points()[k]), (std::array<int, 3>{235, 235, 235})) << "O/c1/p" << k << " drawn beside it";
  // Bad inputs: one line, exit 2.
  const Outcome no_glyph = run_edit(kFont, "status\n", dir_ / "x.png", "400x400");
  EXPECT_EQ(no_glyph.code, 2);
  EXPECT_NE(no_glyph.err.find("a font; name the glyph to edit with --glyph X"), std::string::npos) << no_glyph.err;
  const Outcome not_font = run_edit(kFig8, "status\n", dir_ / "x.png", "400x400", " --glyph O");
  EXPECT_EQ(not_font.code, 2);
  EXPECT_NE(not_font.err.find("--glyph: only for fonts"), std::string::npos) << not_font.err;
  const Outcome missing = run_edit(kFont, "status\n", dir_ / "x.png", "400x400", " --glyph U+E000");
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.err.find("DejaVuSans.ttf has no glyph for 'U+E000'"), std::string::npos) << missing.err;
  EXPECT_FALSE(fs::exists(dir_ / "x.png"));
}

TEST_F(EditTest, SvgPathsOpenTogetherAndSaveAsSplineJson) {
  const fs::path svg = dir_ / "two.svg";
  std::ofstream(svg) << "<svg xmlns='http://www.w3.org/2000/svg'>"
                        "<path d='M 0 0 C 30 -40 70 -40 100 0'/>"
                        "<path d='M 0 60 Q 50 10 100 60 Q 150 110 200 60'/></svg>\n";
  const Outcome imp = run("import " + svg.string() + " --out " + (dir_ / "imported").string());
  ASSERT_EQ(imp.code, 0) << imp.err;
  const Outcome r = run_edit(svg.string(), "contour 1\ntype x 75.5\nsave-all\n", dir_ / "svg.png", "1024x768", "", dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("two.svg: 2 paths"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("saved 2 spline JSON files: ./two_0.json, ./two_1.json"), std::string::npos) << r.err;
  expect_same_curve(dir_ / "two_0.json", dir_ / "imported" / "two_0.json");
  const nlohmann::json edited = read_json(dir_ / "two_1.json"), before = read_json(dir_ / "imported" / "two_1.json");
  EXPECT_EQ(edited["knots"], before["knots"]);
  EXPECT_NE(edited["points"], before["points"]) << "the typed x moved the selected point of path 1";
  int moved = 0;
  for (std::size_t i = 0; i < before["points"].size(); ++i)
    if (edited["points"][i] != before["points"][i]) {
      ++moved;
      EXPECT_EQ(edited["points"][i][0].get<double>(), 75.5);
      EXPECT_EQ(edited["points"][i][1], before["points"][i][1]);
    }
  EXPECT_EQ(moved, 1);
}

TEST_F(EditTest, ConstrainedDragStopsInsideTheRegion) {
  // P3 first onto a position deep inside its region (RegionProblem::classify
  // on a grid), then dragged far out with "keep in region" on: it stops on
  // a certified position inside, short of the pointer.
  const cmr::BSpline fig8 = cmr::read_spline_file(kFig8);
  cmr::RegionRequest rq;
  rq.point = 3;
  const cmr::RegionProblem problem = cmr::RegionProblem::make(fig8, rq);
  const auto inside = [&](cmr::Vec2 p) {
    const cmr::Direction l = problem.classify(p).label;
    return l == cmr::Direction::increasing || l == cmr::Direction::decreasing;
  };
  std::optional<cmr::Vec2> deep;
  for (double y = -6.5; y < -3 && !deep; y += 0.05)
    for (double x = -0.5; x < 4.5 && !deep; x += 0.05) {
      bool all = true;
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) all = all && inside({x + 0.05 * dx, y + 0.05 * dy});
      if (all) deep = cmr::Vec2{x, y};
    }
  ASSERT_TRUE(deep.has_value());
  const cmr::Vec2 far = *deep + cmr::Vec2{2.5, 2.0};
  ASSERT_FALSE(inside(far));
  const fs::path saved = dir_ / "kept.json";
  const auto num = [](double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return std::string(b);
  };
  const Outcome r = run_edit(kFig8,
                             "ui off\nview " + kView + "\nselect 3\ndrag 3 " + num(deep->x) + " " + num(deep->y) +
                                 "\nconstrain on\ndrag 3 " + num(far.x) + " " + num(far.y) + " 8\nsave " +
                                 saved.string() + "\n",
                             dir_ / "shot.png");
  ASSERT_EQ(r.code, 0) << r.err;
  const cmr::Vec2 p = cmr::read_spline_file(saved).points()[3];
  EXPECT_TRUE(inside(p)) << "certified inside: " << p.x << ", " << p.y;
  EXPECT_GT(norm(p - far), 0.1) << "stopped short of the pointer";
  EXPECT_GT(norm(p - *deep), 1e-3) << "moved towards the pointer";
}

}  // namespace

// ---- issue 36: a font source's glyph (a UFO), saved back into its .glif ----

namespace {

std::map<std::string, std::string> files_under(const fs::path& root) {
  std::map<std::string, std::string> out;
  for (const auto& f : fs::recursive_directory_iterator(root))
    if (f.is_regular_file()) out[f.path().lexically_relative(root).string()] = cmr::test::slurp(f.path());
  return out;
}

std::vector<std::string> text_lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

/// The number in attribute `name` of a .glif <point> line.
double attribute(const std::string& line, const std::string& name) {
  const std::size_t at = line.find(" " + name + "=\"");
  if (at == std::string::npos) return NAN;
  return std::stod(line.substr(at + name.size() + 3));
}

/// Pixels that differ between two screenshots inside a box.
int differing(const Image& a, const Image& b, int x0, int y0, int x1, int y1) {
  int n = 0;
  for (int j = y0; j < y1; ++j)
    for (int i = x0; i < x1; ++i) n += a.rgb[j * a.width + i] != b.rgb[j * b.width + i];
  return n;
}

}  // namespace

TEST_F(EditTest, UfoGlyphSavesOnlyTheDraggedPointsXYIntoItsGlif) {
  const fs::path ufo = dir_ / "Sans.ufo";
  fs::copy(fs::path(CMR_SOURCE_DIR) / "examples/ufo/Sans.ufo", ufo, fs::copy_options::recursive);
  const auto before = files_under(ufo);
  // Drag O/c0/p3 to a position off the grid, save (the panel's save), then
  // the same view three ways: the legend docked (a glyph's default), floating,
  // and no panels at all; the comb off (it is fitted to the canvas, which the
  // panels change) and the pointer in the canvas's empty corner.
  const fs::path docked = dir_ / "docked.png", floating = dir_ / "floating.png", bare = dir_ / "bare.png";
  const Outcome r = run_edit("Sans.ufo",
                             "select 3\ndrag 3 700.3 299.6\nstatus\nsave\ncomb off\nmouse 3 3\nscreenshot " +
                                 docked.string() + "\nlegend-dock off\nscreenshot " + floating.string() +
                                 "\nui off\nscreenshot " + bare.string() + "\n",
                             dir_ / "last.png", "1024x768", " --glyph O", dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("cmr edit: glyph O of Sans.ufo: 2 contours (O/c0, O/c1)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("selected P3 (O/c0/p3)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("saved 1 moved point(s) into Sans.ufo/glyphs/O_.glif (x and y only, on the font's grid)"),
            std::string::npos)
      << r.err;
  // Every other file byte for byte; in the .glif one line, and in it only x and y.
  const auto after = files_under(ufo);
  ASSERT_EQ(after.size(), before.size());
  for (const auto& [name, bytes] : before) {
    if (name == "glyphs/O_.glif") continue;
    EXPECT_EQ(after.at(name), bytes) << name << " was touched";
  }
  const auto a = text_lines(before.at("glyphs/O_.glif")), b = text_lines(after.at("glyphs/O_.glif"));
  ASSERT_EQ(a.size(), b.size());
  int changed = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i] == b[i]) continue;
    ++changed;
    const double x = attribute(b[i], "x"), y = attribute(b[i], "y");
    EXPECT_EQ(x, std::round(x)) << b[i] << ": on the font's grid";
    EXPECT_EQ(y, std::round(y)) << b[i];
    EXPECT_NEAR(x, 700.3, 3) << b[i];
    EXPECT_NEAR(y, 299.6, 3) << b[i];
    std::string p = a[i], q = b[i];
    for (std::string* s : {&p, &q})
      for (const char* n : {" x=\"", " y=\""}) {
        const std::size_t at = s->find(n);
        s->erase(at + 4, s->find('"', at + 4) - (at + 4));
      }
    EXPECT_EQ(p, q) << "only x and y differ: " << a[i] << " -> " << b[i];
  }
  EXPECT_EQ(changed, 1);
  // Docked, the legend covers nothing of the canvas: its top left is the
  // same as without panels; floating, it is not.
  const Image d = read_png(docked), f = read_png(floating), n = read_png(bare);
  ASSERT_EQ(d.width, 1024);
  ASSERT_EQ(n.width, 1024);
  EXPECT_EQ(differing(d, n, 0, 0, 320, 200), 0) << "the docked legend covers the canvas";
  EXPECT_GT(differing(f, n, 0, 0, 320, 200), 2000) << "the floating legend is where the test looks";
}

namespace {

/// The comb's dark green pixels (expect_comb_inside's test).
int comb_pixels(const Image& img) {
  int n = 0;
  for (const auto& c : img.rgb) n += c[1] > c[0] + 35 && c[1] > c[2] + 35 && c[1] < 200;
  return n;
}

/// Near-black pixels in a box (a point marker's outline, a label's text).
int dark_pixels(const Image& img, int x0, int y0, int x1, int y1) {
  int n = 0;
  for (int j = std::max(0, y0); j < std::min(img.height, y1); ++j)
    for (int i = std::max(0, x0); i < std::min(img.width, x1); ++i) {
      const auto& c = img.rgb[j * img.width + i];
      n += c[0] < 80 && c[1] < 80 && c[2] < 80;
    }
  return n;
}

}  // namespace

TEST_F(EditTest, GlyphCombOnEveryContourAndNoMarkersOnALinesAddedPoints) {
  // A .glif alone: p0 -> p1 is a line, whose added inner points (at about
  // x = 100 and 200, y = 0) are neither drawn nor picked.
  const fs::path glif = dir_ / "D_.glif";
  std::ofstream(glif) << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<glyph name=\"D\" format=\"2\">\n<outline>\n"
                         "<contour>\n<point x=\"0\" y=\"0\" type=\"line\"/>\n<point x=\"300\" y=\"0\" type=\"line\"/>\n"
                         "<point x=\"450\" y=\"0\"/>\n<point x=\"500\" y=\"150\"/>\n"
                         "<point x=\"500\" y=\"300\" type=\"curve\" smooth=\"yes\"/>\n<point x=\"500\" y=\"450\"/>\n"
                         "<point x=\"450\" y=\"600\"/>\n<point x=\"300\" y=\"600\" type=\"curve\"/>\n"
                         "<point x=\"0\" y=\"600\" type=\"line\"/>\n</contour>\n</outline>\n</glyph>\n";
  const fs::path shot = dir_ / "d.png";
  // View -100..700 both ways on 400x400: world (x, y) at pixel ((x + 100) / 2, (700 - y) / 2).
  const Outcome r = run_edit(glif.string(),
                             "ui off\ncomb off\nview -100 -100 700 700\nselect 4\nmouse 100 350\npress left\n"
                             "release left\nstatus\nscreenshot " + shot.string() + "\n",
                             dir_ / "last.png", "400x400", "", dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("glyph D of D_.glif: 1 contour"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("selected P4 (D/c0/p2)"), std::string::npos) << "a press on a line's added point picks nothing: "
                                                                       << r.err;
  const Image img = read_png(shot);
  ASSERT_EQ(img.width, 400);
  // Above the line (y = 0 at row 350): a marker's outline at the nodes p0
  // (pixel 50) and p1 (200), nothing at the added points (100, 150).
  EXPECT_GT(dark_pixels(img, 193, 343, 208, 348), 3) << "p1's marker";
  EXPECT_EQ(dark_pixels(img, 93, 343, 108, 348), 0) << "an added point's marker at x = 100";
  EXPECT_EQ(dark_pixels(img, 143, 343, 158, 348), 0) << "an added point's marker at x = 200";
  // A UFO's O: the comb of the edited contour, then of both.
  const fs::path one = dir_ / "one.png", both = dir_ / "both.png";
  const Outcome o = run_edit((fs::path(CMR_SOURCE_DIR) / "examples/ufo/Sans.ufo").string(),
                             "ui off\nfit\nscreenshot " + one.string() + "\ncomb-all on\nscreenshot " + both.string() + "\n",
                             dir_ / "last.png", "640x480", " --glyph O", dir_);
  ASSERT_EQ(o.code, 0) << o.err;
  const int c1 = comb_pixels(read_png(one)), c2 = comb_pixels(read_png(both));
  EXPECT_GT(c1, 200);
  EXPECT_GT(c2, c1 + 500) << "the other contour's comb is drawn too";
}
