// draw/draw: region pictures as PNG bytes in memory and as files, colours by label, atomic writes.
#include <cairo.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string_view>

#include "spline/errors.hpp"
#include "draw/draw.hpp"
#include "io/output.hpp"

namespace cmr::draw {
namespace {

namespace fs = std::filesystem;

fs::path scratch() {
  const fs::path dir = fs::temp_directory_path() / ("cmr_draw_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

/// A W x H image whose left half is label `left` and right half `right`.
RegionResult halves(const BSpline& s, int W, int H, Direction left, Direction right) {
  RegionResult r;
  r.width = W;
  r.height = H;
  r.view = default_view(s, W, H);
  r.labels.resize(static_cast<std::size_t>(W) * H);
  r.depth.assign(r.labels.size(), 0);
  for (int j = 0; j < H; ++j)
    for (int i = 0; i < W; ++i) r.labels[static_cast<std::size_t>(j) * W + i] = i < W / 2 ? left : right;
  return r;
}

struct Png {
  int width = 0, height = 0;
  std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> surface{nullptr, &cairo_surface_destroy};
  /// (r, g, b) in 0..255 of pixel (i, j).
  std::array<int, 3> at(int i, int j) const {
    const unsigned char* data = cairo_image_surface_get_data(surface.get());
    const int stride = cairo_image_surface_get_stride(surface.get());
    const uint32_t v = reinterpret_cast<const uint32_t*>(data + static_cast<std::ptrdiff_t>(j) * stride)[i];
    return {static_cast<int>(v >> 16 & 0xff), static_cast<int>(v >> 8 & 0xff), static_cast<int>(v & 0xff)};
  }
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

Png read_png(const fs::path& p) {
  Png png;
  png.surface.reset(cairo_image_surface_create_from_png(p.c_str()));
  EXPECT_EQ(cairo_surface_status(png.surface.get()), CAIRO_STATUS_SUCCESS) << p;
  png.width = cairo_image_surface_get_width(png.surface.get());
  png.height = cairo_image_surface_get_height(png.surface.get());
  return png;
}

const BSpline kCubic = BSpline::bezier({{0, 0}, {1, 1}, {2, 1}, {3, 0}});

TEST(WriteRegionPng, SizeAndColoursFollowTheLabels) {
  const RegionResult r = halves(kCubic, 120, 90, Direction::increasing, Direction::none);
  RegionPicture p;
  p.spline = &kCubic;
  p.layers = {&r};
  const fs::path path = scratch() / "halves.png";
  write_region_png(path, p);
  const Png png = read_png(path);
  ASSERT_EQ(png.width, 120);
  ASSERT_EQ(png.height, 90);
  // Corners: inside the 25% margin of the default view, so nothing is drawn over them.
  const auto red = png.at(3, 3), white = png.at(116, 86);
  EXPECT_GT(red[0], 200) << "label 1 pixel (3,3)";
  EXPECT_LT(red[1], 150) << "label 1 pixel (3,3)";
  EXPECT_LT(red[2], 150) << "label 1 pixel (3,3)";
  for (int c : white) EXPECT_GE(c, 250) << "label 0 pixel (116,86)";
  // No staged temporary or backup (io/output.hpp names them .cmr-tmp.* and .cmr-bak.*) is left beside it.
  for (const fs::directory_entry& e : fs::directory_iterator(path.parent_path())) {
    const std::string name = e.path().filename().string();
    EXPECT_NE(name.rfind(".cmr-tmp.", 0), 0u) << name;
    EXPECT_NE(name.rfind(".cmr-bak.", 0), 0u) << name;
  }
}

TEST(WriteRegionPng, MissingFolderThrowsAndLeavesNothing) {
  const RegionResult r = halves(kCubic, 32, 32, Direction::increasing, Direction::decreasing);
  RegionPicture p;
  p.spline = &kCubic;
  p.layers = {&r};
  const fs::path dir = scratch() / "does_not_exist";
  EXPECT_THROW(write_region_png(dir / "x.png", p), InputError);
  EXPECT_FALSE(fs::exists(dir / "x.png"));
  EXPECT_FALSE(fs::exists(dir));  // nor anything in it: no temporary either
}

TEST(PixelColour, OverlapsAreDarkerThanOneRegion) {
  const RegionResult a = halves(kCubic, 4, 1, Direction::increasing, Direction::none), b = halves(kCubic, 4, 1, Direction::increasing, Direction::increasing);
  RegionPicture one, two;
  one.layers = {&a};
  two.layers = {&a, &b};
  const Rgb single = pixel_colour(one, 0), both = pixel_colour(two, 0), none = pixel_colour(one, 3);
  EXPECT_EQ(single.r, 1.0);
  EXPECT_LT(both.g, single.g);
  EXPECT_LT(both.b, single.b);
  EXPECT_EQ(none.r + none.g + none.b, 3.0) << "label 0 is white";
}

TEST(PixelColour, SplitLabelsShowTheSecondPartsDirectionAndTheJoint) {
  RegionResult r = halves(kCubic, 6, 1, Direction::none, Direction::none);
  r.split = true;
  r.labels.clear();
  r.split_labels = {Split::inc_inc, Split::inc_dec, Split::dec_inc,
                    Split::dec_dec, Split::undecided, Split::none};
  RegionPicture p;
  p.layers = {&r};
  p.split = true;
  const Rgb inc_inc = pixel_colour(p, 0), inc_dec = pixel_colour(p, 1), dec_inc = pixel_colour(p, 2),
            dec_dec = pixel_colour(p, 3), undecided = pixel_colour(p, 4);
  EXPECT_GT(inc_inc.r, inc_inc.b);  // second part increasing: red
  EXPECT_GT(dec_inc.r, dec_inc.b);
  EXPECT_GT(dec_dec.b, dec_dec.r);  // second part decreasing: blue
  EXPECT_GT(inc_dec.b, inc_dec.r);
  EXPECT_LT(dec_inc.r, inc_inc.r) << "an extremum at the joint is the darker shade";
  EXPECT_LT(inc_dec.b, dec_dec.b) << "an extremum at the joint is the darker shade";
  EXPECT_EQ(undecided.r + undecided.g + undecided.b, 3.0);
}

TEST(PixelColour, AlternatingLabelsShowTheFirstGroupsDirection) {
  RegionResult r = halves(kCubic, 4, 1, Direction::none, Direction::none);
  r.alternating = true;
  r.labels.clear();
  r.alternating_labels = {Alternation::first_increasing, Alternation::first_decreasing,
                          Alternation::undecided, Alternation::fail};
  RegionPicture p;
  p.layers = {&r};
  p.alternating = true;
  const Rgb inc = pixel_colour(p, 0), dec = pixel_colour(p, 1), undecided = pixel_colour(p, 2), fail = pixel_colour(p, 3);
  EXPECT_GT(inc.r, inc.b);  // group 0 increasing: red
  EXPECT_GT(dec.b, dec.r);  // group 0 decreasing: blue
  EXPECT_EQ(undecided.r + undecided.g + undecided.b, 3.0);
  EXPECT_EQ(fail.r + fail.g + fail.b, 3.0);
  p.spline = &kCubic;
  EXPECT_FALSE(region_png(p).empty());  // the legend for alternating labels draws
}

TEST(PixelColour, DepthShadingDarkensWithTheLevel) {
  RegionResult r = halves(kCubic, 4, 1, Direction::none, Direction::none);
  r.labels = {Direction::increasing, Direction::increasing, Direction::none, Direction::none};
  r.depth = {0, 6, 0, 6};
  RegionPicture p;
  p.layers = {&r};
  p.depth_shading = true;
  EXPECT_LT(pixel_colour(p, 1).r, pixel_colour(p, 0).r) << "red at level 6 vs 0";
  EXPECT_LT(pixel_colour(p, 3).g, pixel_colour(p, 2).g) << "grey at level 6 vs 0";
  EXPECT_LT(pixel_colour(p, 2).g, 1.0) << "not monotone is grey, not white";
}

TEST(WriteFigurePng, CompositeIsAValidPng) {
  const RegionResult r = halves(kCubic, 100, 100, Direction::decreasing, Direction::none);
  RegionPicture p;
  p.spline = &kCubic;
  p.layers = {&r};
  p.moved = std::make_pair(Vec2(0, 0), Vec2(0.5, 0.2));
  const SplineAnalysis a = analyze(kCubic);
  Figure f;
  f.title = "test figure";
  f.rows = {{{p, "(a) region"}, {CurvaturePlot{&kCubic, &a}, "(b) plot"}}};
  f.legend = legend_for(p);
  f.caption = "a caption long enough to wrap over more than one line of the page, so that wrapping is exercised";
  f.panel_size = 100;
  const fs::path path = scratch() / "figure.png";
  const std::string bytes = figure_png(f);
  cmr::write_file_atomic(path, bytes);
  const Png png = read_png(path);
  EXPECT_GE(png.width, 200);
  EXPECT_GE(png.height, 100);
  EXPECT_EQ(figure_png(f), bytes) << "rendering is deterministic";
}

/// Reads PNG bytes from memory, chunk by chunk as Cairo asks for them.
struct PngReader {
  std::string_view bytes;
  static cairo_status_t read(void* self, unsigned char* data, unsigned int length) {
    auto* r = static_cast<PngReader*>(self);
    if (r->bytes.size() < length) return CAIRO_STATUS_READ_ERROR;
    std::memcpy(data, r->bytes.data(), length);
    r->bytes.remove_prefix(length);
    return CAIRO_STATUS_SUCCESS;
  }
};

TEST(RegionPng, InMemoryBytesDecodeAndEqualTheFile) {
  const RegionResult r = halves(kCubic, 64, 48, Direction::decreasing, Direction::increasing);
  RegionPicture p;
  p.spline = &kCubic;
  p.layers = {&r};
  const std::string bytes = region_png(p);
  ASSERT_GE(bytes.size(), 8u);
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << "PNG signature";
  PngReader reader{bytes};
  std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> decoded(
      cairo_image_surface_create_from_png_stream(&PngReader::read, &reader), &cairo_surface_destroy);
  ASSERT_EQ(cairo_surface_status(decoded.get()), CAIRO_STATUS_SUCCESS);
  EXPECT_EQ(cairo_image_surface_get_width(decoded.get()), 64);
  EXPECT_EQ(cairo_image_surface_get_height(decoded.get()), 48);
  EXPECT_TRUE(reader.bytes.empty()) << reader.bytes.size() << " bytes after the PNG's end";
  const fs::path path = scratch() / "memory.png";
  write_region_png(path, p);
  EXPECT_EQ(slurp(path), bytes);
}

TEST(WriteRegionPng, DirectoryAsOutputIsAnInputErrorAndStaysADirectory) {
  const RegionResult r = halves(kCubic, 16, 16, Direction::increasing, Direction::decreasing);
  RegionPicture p;
  p.spline = &kCubic;
  p.layers = {&r};
  const fs::path dir = scratch() / "a_folder.png";
  fs::create_directories(dir);
  EXPECT_THROW(write_region_png(dir, p), InputError);
  EXPECT_TRUE(fs::is_directory(dir));
}

// The legend lists exactly the colours drawn: every non-white label colour
// of the layers appears in it, and each entry's colour occurs in the picture
// (or is the white of "not monotone").
TEST(LegendFor, ListsExactlyTheColoursDrawn) {
  // Layer a: increasing left half; layer b: decreasing columns 0..1 and increasing 6..7.
  RegionResult a = halves(kCubic, 8, 2, Direction::increasing, Direction::none);
  RegionResult b = halves(kCubic, 8, 2, Direction::none, Direction::none);
  for (int j = 0; j < 2; ++j) {
    b.labels[j * 8 + 0] = b.labels[j * 8 + 1] = Direction::decreasing;
    b.labels[j * 8 + 6] = b.labels[j * 8 + 7] = Direction::increasing;
  }
  RegionPicture p;
  p.spline = &kCubic;
  p.layers = {&a, &b};
  const std::vector<LegendEntry> legend = legend_for(p);
  auto same = [](Rgb x, Rgb y) { return std::abs(x.r - y.r) + std::abs(x.g - y.g) + std::abs(x.b - y.b) < 1e-9; };
  for (std::size_t i = 0; i < 16; ++i) {
    const Rgb c = pixel_colour(p, i);
    EXPECT_TRUE(std::any_of(legend.begin(), legend.end(), [&](const LegendEntry& e) { return same(e.colour, c); }))
        << "pixel " << i << " colour missing from the legend";
  }
  for (const LegendEntry& e : legend) {
    bool drawn = e.colour.r == 1 && e.colour.g == 1 && e.colour.b == 1;
    for (std::size_t i = 0; i < 16; ++i) drawn = drawn || same(pixel_colour(p, i), e.colour);
    EXPECT_TRUE(drawn) << "'" << e.text << "' is not drawn";
  }
  // Three colours (increasing + decreasing overlap, increasing alone, a second increasing alone is the same) and white.
  EXPECT_EQ(legend.size(), 3u);
  EXPECT_NE(std::find_if(legend.begin(), legend.end(),
                         [](const LegendEntry& e) { return e.text == "increasing + decreasing overlap"; }),
            legend.end());
}

// --point all: each point's region in its own colour, decreasing hatched.
TEST(PixelColour, PerPointColoursFillIncreasingAndHatchDecreasing) {
  const RegionResult a = halves(kCubic, 12, 12, Direction::increasing, Direction::decreasing);
  const RegionResult b = halves(kCubic, 12, 12, Direction::none, Direction::increasing);
  RegionPicture p;
  p.spline = &kCubic;
  p.layers = {&a, &b};
  p.points = {2, 5};
  p.per_point = true;
  const Rgb p2 = pixel_colour(p, 0);  // only point 2, increasing: filled in point 2's colour
  const Rgb p2_colour = point_colour(2), p5_colour = point_colour(5);
  EXPECT_NEAR(p2.r, 1 - 0.6 * (1 - p2_colour.r), 1e-12);
  EXPECT_NEAR(p2.g, 1 - 0.6 * (1 - p2_colour.g), 1e-12);
  EXPECT_NEAR(p2.b, 1 - 0.6 * (1 - p2_colour.b), 1e-12);
  EXPECT_GT(std::abs(p2_colour.r - p5_colour.r) + std::abs(p2_colour.g - p5_colour.g) +
                std::abs(p2_colour.b - p5_colour.b),
            0.5)
      << "points 2 and 5 must be told apart";
  // Right half: point 2 decreasing (hatched: rows of stripes differ) under point 5 increasing.
  std::set<std::array<long, 3>> right;
  for (int j = 0; j < 12; ++j)
    for (int i = 6; i < 12; ++i) {
      const Rgb c = pixel_colour(p, static_cast<std::size_t>(j) * 12 + i);
      right.insert({std::lround(c.r * 1e6), std::lround(c.g * 1e6), std::lround(c.b * 1e6)});
    }
  EXPECT_EQ(right.size(), 2u) << "hatching alternates two shades";
  const std::vector<LegendEntry> legend = legend_for(p);
  ASSERT_GE(legend.size(), 2u);
  EXPECT_EQ(legend[0].text, "P2");
  EXPECT_EQ(legend[1].text, "P5");
  EXPECT_TRUE(std::any_of(legend.begin(), legend.end(), [](const LegendEntry& e) { return e.hatched; }));
}

// A region picture with a legend and a marked point: still the layers' size,
// and the legend box covers a corner (its white shows where the region was red).
TEST(RegionPng, LegendAndMarkedPointAreDrawnInside) {
  const RegionResult r = halves(kCubic, 300, 200, Direction::increasing, Direction::increasing);
  RegionPicture p;
  p.spline = &kCubic;
  p.layers = {&r};
  p.points = {1};
  const fs::path plain = scratch() / "plain.png", with = scratch() / "legend.png";
  write_region_png(plain, p);
  p.legend = true;
  write_region_png(with, p);
  const Png a = read_png(plain), b = read_png(with);
  ASSERT_EQ(b.width, 300);
  ASSERT_EQ(b.height, 200);
  int whiter = 0;
  for (const auto& [i, j] : {std::pair{8, 8}, std::pair{291, 8}, std::pair{8, 191}, std::pair{291, 191}})
    whiter += b.at(i, j)[1] > a.at(i, j)[1] + 60;  // red (g ~ 102) under white (g > 200)
  EXPECT_EQ(whiter, 1) << "one corner holds the legend";
  const std::vector<LegendEntry> legend = legend_for(p);
  EXPECT_TRUE(std::any_of(legend.begin(), legend.end(), [](const LegendEntry& e) { return e.ring && e.text == "P1, the moved point"; }));
}

// figure_svg: a complete SVG document (the surface is finished).
TEST(FigureSvg, IsACompleteSvgDocument) {
  const RegionResult r = halves(kCubic, 60, 60, Direction::decreasing, Direction::none);
  RegionPicture p;
  p.spline = &kCubic;
  p.layers = {&r};
  Figure f;
  f.title = "svg";
  f.rows = {{{p, "(a)"}, {LambdaPlot{{1, -2, 0.5, 3}}, "(b)"}}};
  f.panel_size = 120;
  const std::string svg = figure_svg(f);
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("<image"), std::string::npos);
  const auto end = svg.find_last_not_of(" \n");
  ASSERT_NE(end, std::string::npos);
  EXPECT_EQ(svg.substr(end - 5, 6), "</svg>");
}

}  // namespace
}  // namespace cmr::draw
