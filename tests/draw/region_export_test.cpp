// The one region exporter of `cmr region` and the editor's export-region:
// label PGMs (one per point when there are several), the layers picture,
// and the one hand-written SVG opening.
#include "draw/region_export.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "draw/svg_text.hpp"

namespace cmr::draw {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(RegionExport, PgmHeaderAndBytes) {
  EXPECT_EQ(pgm(2, 1, {0, 3}, 3), std::string("P5\n2 1\n3\n") + '\0' + '\3');
  RegionResult r;
  r.width = 3;
  r.height = 1;
  r.labels = {Direction::none, Direction::increasing, Direction::decreasing};
  r.depth = {0, 0, 0};
  EXPECT_EQ(label_pgm(r), std::string("P5\n3 1\n255\n") + '\0' + '\1' + '\2');
}

TEST(RegionExport, PointSuffixGoesBeforeTheExtension) {
  EXPECT_EQ(with_point_suffix("out/r.pgm", 3), fs::path("out/r.P3.pgm"));
  EXPECT_EQ(with_point_suffix("r", 0), fs::path("r.P0"));
  EXPECT_EQ(with_point_suffix("a.b/r.png", 12), fs::path("a.b/r.P12.png")) << "a dot in a folder name is no extension";
}

TEST(RegionExport, LabelPgmsOnePerPointWhenSeveral) {
  const fs::path dir = fs::temp_directory_path() / ("cmr_region_export_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  RegionRequest a, b;
  a.point = 1;
  b.point = 4;
  a.width = a.height = b.width = b.height = 8;
  const BSpline s = BSpline::bezier({{0, 0}, {1, 1}, {2, 0.2}, {3, 1}, {4, 0}});
  CpuRegionBackend cpu;
  const std::vector<RegionResult> layers = {cpu.render(RegionProblem::make(s, a)), cpu.render(RegionProblem::make(s, b))};
  {
    OutputSet out;
    stage_label_pgms(out, dir / "one.pgm", {layers[0]}, {a});
    stage_label_pgms(out, dir / "l.pgm", layers, {a, b});
    out.commit();
  }
  EXPECT_EQ(slurp(dir / "one.pgm"), label_pgm(layers[0]));
  EXPECT_EQ(slurp(dir / "l.P1.pgm"), label_pgm(layers[0]));
  EXPECT_EQ(slurp(dir / "l.P4.pgm"), label_pgm(layers[1]));
  EXPECT_FALSE(fs::exists(dir / "l.pgm"));
  const RegionPicture pic = layers_picture(s, layers, {a, b});
  ASSERT_EQ(pic.layers.size(), 2u);
  EXPECT_EQ(pic.points, (std::vector<int>{1, 4}));
  EXPECT_TRUE(pic.per_point);
  EXPECT_TRUE(pic.legend);
  EXPECT_FALSE(layers_picture(s, {layers[0]}, {a}).per_point);
  fs::remove_all(dir);
}

TEST(SvgText, OpeningTagAndColour) {
  EXPECT_EQ(svg_open({{"width", "440"}, {"class", "plot"}}),
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"440\" class=\"plot\">");
  EXPECT_EQ(svg_open({}), "<svg xmlns=\"http://www.w3.org/2000/svg\">");
  EXPECT_EQ(svg_colour({1, 0.5, 0}), "#ff8000");
  EXPECT_EQ(svg_colour({-1, 2, 0.2}), "#00ff33") << "channels clamped to 0..1";
}

TEST(LabelColour, IsTheLegendColourOfAOnePixelMap) {
  for (const bool split : {false, true})
    for (std::uint8_t code = 0; code < (split ? kSplitLabelCodes : kRegionLabelCodes); ++code) {
      RegionResult one;
      one.width = one.height = 1;
      one.split = split;
      one.depth = {0};
      if (split) one.split_labels = {static_cast<Split>(code)};
      else one.labels = {static_cast<Direction>(code)};
      RegionPicture pic;
      pic.layers = {&one};
      pic.split = split;
      const Rgb want = pixel_colour(pic, 0), got = label_colour(code, split);
      EXPECT_EQ(got.r, want.r) << "code " << int(code) << (split ? " split" : "");
      EXPECT_EQ(got.g, want.g) << "code " << int(code);
      EXPECT_EQ(got.b, want.b) << "code " << int(code);
    }
}

}  // namespace
}  // namespace cmr::draw
