// tools/figures: every claim about the paper's figures holds (CPU backend),
// the files are written and readable, and examples/figures/ is current.
#include <cairo.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "spline/errors.hpp"
#include "spline/spline_json.hpp"
#include "tools/figures.hpp"

namespace cmr::fig {
namespace {

namespace fs = std::filesystem;

/// A fresh folder (removed first) under this process's scratch folder.
fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("cmr_figures_test_" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  return dir;
}

const fs::path& out_dir() {
  static const fs::path dir = scratch("out");
  return dir;
}

/// One run for the whole suite: the claims and files are what every test looks at.
const FiguresResult& run_once() {
  static const FiguresResult result = [] {
    FiguresOptions o;
    o.out = out_dir();
    o.backend = std::make_shared<CpuRegionBackend>();
    return make_figures(o);
  }();
  return result;
}

TEST(Figures, EveryClaimPasses) {
  const FiguresResult& r = run_once();
  EXPECT_GE(r.claims.size(), 20u);
  for (const Claim& c : r.claims) EXPECT_TRUE(c.pass) << c.figure << ": " << c.text << " -- measured: " << c.detail;
  EXPECT_TRUE(r.all_pass());
}

TEST(Figures, EveryFigureOfSection4HasClaims) {
  const FiguresResult& r = run_once();
  for (const char* f : {"Fig. 2", "Fig. 3", "Fig. 5", "Fig. 6", "Fig. 7", "Fig. 8", "Fig. 9", "Fig. 10", "Fig. 13"}) {
    const std::string prefix = f;
    const auto n = std::count_if(r.claims.begin(), r.claims.end(), [&](const Claim& c) {
      if (c.figure.rfind(prefix, 0) != 0) return false;
      // "Fig. 1" must not count "Fig. 10a".
      return c.figure.size() == prefix.size() || !std::isdigit(static_cast<unsigned char>(c.figure[prefix.size()]));
    });
    EXPECT_GT(n, 0) << f;
  }
}

TEST(Figures, WritesValidPngsAndAnIndex) {
  const FiguresResult& r = run_once();
  ASSERT_EQ(r.figures.size(), 9u);
  for (const FigureFile& f : r.figures) {
    const fs::path png = out_dir() / (f.id + ".png");
    ASSERT_TRUE(fs::exists(png)) << png;
    cairo_surface_t* s = cairo_image_surface_create_from_png(png.c_str());
    EXPECT_EQ(cairo_surface_status(s), CAIRO_STATUS_SUCCESS) << png;
    EXPECT_GE(cairo_image_surface_get_width(s), 400) << png;
    cairo_surface_destroy(s);
  }
  for (const fs::path& p : r.written) EXPECT_TRUE(fs::exists(p)) << p;
  const fs::path index = r.written.back();
  ASSERT_EQ(index.filename(), "index.html");
  std::ifstream in(index);
  std::stringstream html;
  html << in.rdbuf();
  for (const FigureFile& f : r.figures) EXPECT_NE(html.str().find(f.id + ".png"), std::string::npos) << f.id;
  EXPECT_EQ(html.str().find(">FAIL<"), std::string::npos);
}

TEST(Figures, ExampleFilesAreCurrent) {
  for (const BSpline& s : figure_splines()) {
    const fs::path p = fs::path(CMR_SOURCE_DIR) / "examples" / "figures" / (s.name() + ".json");
    ASSERT_TRUE(fs::exists(p)) << p << " is missing: run `cmr figures --out DIR` and copy DIR/*.json there";
    const BSpline f = read_spline_file(p);
    EXPECT_EQ(f.degree(), s.degree()) << p;
    EXPECT_EQ(f.knots(), s.knots()) << p;
    ASSERT_EQ(f.point_count(), s.point_count()) << p;
    for (int i = 0; i < s.point_count(); ++i) {
      EXPECT_EQ(f.points()[i].x, s.points()[i].x) << p << " point " << i;
      EXPECT_EQ(f.points()[i].y, s.points()[i].y) << p << " point " << i;
    }
  }
}

TEST(Figures, BadOptionsAreInputErrors) {
  FiguresOptions o;
  o.backend = std::make_shared<CpuRegionBackend>();
  o.size = 10;
  o.out = scratch("small");
  EXPECT_THROW(make_figures(o), InputError);
  o.size = 400;
  const fs::path blocker = scratch("blocker");
  fs::create_directories(blocker.parent_path());
  std::ofstream(blocker) << "a file where the folder should go";
  o.out = blocker / "figures";
  EXPECT_THROW(make_figures(o), InputError);
}

}  // namespace
}  // namespace cmr::fig
