// The optimised region paths (block proofs with their adaptive piece budget,
// the per-pixel path that halves each deep piece once) against the exact
// path: on seeded zooms onto a region boundary (4e-4 and 1e-2 wide, the
// bench's views), every label of region_cpu and of classify_position must be
// what classify_position_exact gives the pixel's centre; and so must the
// labels of seeded points within 1e-9 of the boundary. Scenes: a cubic Bezier
// (fig2 P1), the uniform cubic B-spline (fig8 P3), the degree-9 Bezier (P4),
// at D = 10 and 16. Images are small so the exact path stays within seconds.
// And the scale: with coordinates multiplied by 2^300 or 2^-300 the labels,
// depths and exact-path pixels are those of the unscaled spline.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>

#include "region/region.hpp"
#include "region/region_setup.hpp"
#include "spline/errors.hpp"
#include "tests/region/boundary_point.hpp"
#include "spline/spline_json.hpp"

namespace cmr {
namespace {

using namespace cmr::backend;

const std::string kSource = CMR_SOURCE_DIR;

RegionRequest request(int point, int depth, int size, std::optional<View> view) {
  return test::region_request(point, depth, size, view, false);  // label maps: the block proofs run
}

// A point on a region boundary: a label change between neighbouring pixels of
// a row of the default view at size x size (rows from the middle out, labels
// of region_cpu), bisected 60 times on exact labels; the bench's way.
Vec2 boundary_point(const BSpline& spline, int point, int depth, int size = 64) {
  const std::optional<Vec2> edge =
      test::boundary_point(RegionProblem::make(spline, request(point, depth, size, std::nullopt)), size);
  if (!edge) ADD_FAILURE() << "no boundary in the default view";
  return edge.value_or(Vec2{0, 0});
}

void expect_exact_labels(const BSpline& spline, int point, const std::string& name, int size) {
  for (const int depth : {10, 16}) {
    const Vec2 edge = boundary_point(spline, point, depth);
    for (const double width : {4e-4, 1e-2}) {
      const View v{edge.x - width / 2, edge.y - width / 2, edge.x + width / 2, edge.y + width / 2};
      const RegionProblem p = RegionProblem::make(spline, request(point, depth, size, v));
      const RegionSetup& s = p.setup();
      const RegionImage img = region_cpu(s, 1);
      std::map<int, int> seen;
      int wrong = 0;
      std::ostringstream first;
      first.precision(17);
      for (int j = 0; j < size; ++j)
        for (int i = 0; i < size; ++i) {
          const Vec2 c = pixel_center(v, size, size, i, j);
          const uint8_t exact = classify_position_exact(s, c).label;
          ++seen[exact];
          const uint8_t block = img.labels[static_cast<std::size_t>(j) * size + i];
          const uint8_t pixel = classify_position(s, c).label;
          if ((block != exact || pixel != exact) && wrong++ < 3)
            first << "\n  pixel (" << i << ", " << j << "): region_cpu " << int(block) << ", classify_position "
                  << int(pixel) << ", exact " << int(exact);
        }
      const std::string where = name + ", D = " + std::to_string(depth) + ", zoom " + std::to_string(width);
      EXPECT_EQ(wrong, 0) << where << first.str();
      EXPECT_GE(seen.size(), 2u) << where << ": the zoom shows one label only";
      // Seeded points next to the boundary: the fast path must still agree.
      std::mt19937_64 rng(23 + depth);
      std::uniform_real_distribution<double> off(-1e-9, 1e-9);
      for (int k = 0; k < 40; ++k) {
        const Vec2 q{edge.x + off(rng), edge.y + off(rng)};
        EXPECT_EQ(int(classify_position(s, q).label), int(classify_position_exact(s, q).label))
            << where << ", point near the boundary #" << k;
      }
    }
  }
}

TEST(RegionFast, CubicBezierZoomLabelsAreExact) {
  expect_exact_labels(read_spline_file(kSource + "/examples/figures/fig2.json"), 1, "fig2 P1", 24);
}

TEST(RegionFast, UniformCubicZoomLabelsAreExact) {
  expect_exact_labels(read_spline_file(kSource + "/examples/figures/fig8.json"), 3, "fig8 P3", 24);
}

TEST(RegionFast, Degree9BezierZoomLabelsAreExact) {
  expect_exact_labels(read_spline_file(kSource + "/examples/bezier9.json"), 4, "bezier9 P4", 16);
}

// Block proofs reach the pixels' depth: in the bench's 4e-4 zoom onto a
// boundary of the uniform cubic at D = 16 (boundary found in the 1024^2
// default view), where a budget of 6 pieces per proof decided almost no
// block, most 8x8 blocks of a 512^2 image are proved whole (tested on a 64^2
// window of it), and every proved block's label is the exact label of each
// of its corners.
TEST(RegionFast, BlockProofsDecideMostOfABoundaryZoom) {
  const BSpline spline = read_spline_file(kSource + "/examples/figures/fig8.json");
  const Vec2 edge = boundary_point(spline, 3, 12, 1024);
  const double w = 4e-4 / 8;  // the central 64x64 pixels of the 512^2 zoom
  const View v{edge.x - w / 2, edge.y - w / 2, edge.x + w / 2, edge.y + w / 2};
  const int size = 64, block = 8;
  const RegionProblem p = RegionProblem::make(spline, request(3, 16, size, v));
  const RegionSetup& s = p.setup();
  int proved = 0, blocks = 0;
  for (int j0 = 0; j0 < size; j0 += block)
    for (int i0 = 0; i0 < size; i0 += block) {
      ++blocks;
      const auto r = classify_block(s, i0, j0, i0 + block - 1, j0 + block - 1);
      if (!r) continue;
      ++proved;
      for (const auto& [i, j] : {std::pair{i0, j0}, {i0 + block - 1, j0}, {i0, j0 + block - 1},
                                 {i0 + block - 1, j0 + block - 1}})
        EXPECT_EQ(int(r->label), int(classify_position_exact(s, pixel_center(v, size, size, i, j)).label))
            << "block at (" << i0 << ", " << j0 << "), corner (" << i << ", " << j << ")";
    }
  EXPECT_GE(proved, blocks / 2) << proved << " of " << blocks << " blocks proved";
}

BSpline scaled_spline(BSpline s, int e) {
  for (int k = 0; k < s.point_count(); ++k)
    s = s.with_point(k, {std::ldexp(s.points()[k].x, e), std::ldexp(s.points()[k].y, e)});
  return s;
}

// Coordinates scaled by 2^+-300: the kernel works on the problem scaled back
// near 1 (RegionSetup::scale_exponent), so every pixel's label and depth are
// those of the unscaled spline and no more pixels take the exact path (all of
// them did before: the polynomials' values left the double range). A sample
// of pixels is checked against the analysis of the moved, scaled spline.
TEST(RegionFast, LabelsAndExactPixelsDoNotDependOnTheScale) {
  struct Scene {
    std::string file;
    int point;
    Mode mode;
    bool depth_map;
    std::optional<int> split;
  };
  const std::vector<Scene> scenes = {{"figures/fig2.json", 1, Mode::cmrwi, true, std::nullopt},
                                     {"figures/fig8.json", 3, Mode::cmr, false, std::nullopt},
                                     {"figures/fig8.json", 3, Mode::cmrwi, true, 2},
                                     {"rational/nurbs_cubic.json", 4, Mode::cmrwi, true, std::nullopt}};
  const int size = 40;
  for (const Scene& sc : scenes) {
    const BSpline spline = read_spline_file(kSource + "/examples/" + sc.file);
    RegionRequest o = test::region_request(sc.point, 10, size, std::nullopt, sc.depth_map, sc.mode);
    o.split = sc.split;
    const RegionProblem plain = RegionProblem::make(spline, o);
    const RegionImage want = region_cpu(plain.setup(), 1);
    EXPECT_EQ(plain.setup().scale_exponent, 0) << sc.file;
    for (const int e : {300, -300}) {
      const std::string where = sc.file + " P" + std::to_string(sc.point) + " at 2^" + std::to_string(e);
      const BSpline big = scaled_spline(spline, e);
      const View v = plain.view();
      RegionRequest ob = o;
      ob.view = View{std::ldexp(v.x0, e), std::ldexp(v.y0, e), std::ldexp(v.x1, e), std::ldexp(v.y1, e)};
      const RegionProblem scaled = RegionProblem::make(big, ob);
      EXPECT_NE(scaled.setup().scale_exponent, 0) << where;
      const RegionImage got = region_cpu(scaled.setup(), 1);
      EXPECT_EQ(got.labels, want.labels) << where;
      EXPECT_EQ(got.depth, want.depth) << where;
      EXPECT_EQ(got.exact_pixels, want.exact_pixels) << where << " (" << size * size << " pixels)";
      EXPECT_LT(got.exact_pixels, static_cast<std::uint64_t>(size * size / 10)) << where;
      // The sample: every 53rd pixel and the first pixel of each label.
      std::map<int, int> first;
      for (int at = 0; at < size * size; ++at) first.emplace(got.labels[at], at);
      EXPECT_GE(first.size(), 2u) << where << ": the image shows one label only";
      std::vector<int> sample;
      for (int at = 0; at < size * size; at += 53) sample.push_back(at);
      for (const auto& [label, at] : first) sample.push_back(at);
      for (const int at : sample) {
        const Vec2 c = pixel_center(*ob.view, size, size, at % size, at / size);
        const SplineAnalysis a = analyze(big.with_point(sc.point, c), region_analyze_options(ob));
        EXPECT_EQ(int(region_label_code(a, ob)), int(got.labels[at])) << where << ", pixel " << at;
      }
    }
  }
}

// A render's codes go to RegionResult without a copy (LabelCodes keeps them
// in the vector of their kind): a copied image owns its own codes, a moved
// one hands them over, and to_result fills the vector of the codes' kind
// only. A device's code beyond its kind's count is an internal error.
TEST(LabelCodes, CopiesOwnTheirCodesAndResultsTakeThemOfTheirKind) {
  const std::pair<Labels, std::uint8_t> kinds[] = {{Labels::plain, kRegionLabelCodes},
                                                   {Labels::split, kSplitLabelCodes},
                                                   {Labels::alternating, kAlternatingLabelCodes},
                                                   {Labels::each_piece, kPieceLabelCodes}};
  for (const auto& [kind, count] : kinds) {
    LabelCodes a(kind, 5);
    EXPECT_EQ(a.codes(), std::vector<std::uint8_t>(5, 0));
    a[2] = 1;
    LabelCodes b = a;
    b[2] = 0;
    EXPECT_EQ(a[2], 1);
    EXPECT_FALSE(a == b);
    RegionImage img;
    img.width = 5;
    img.height = 1;
    img.labels = std::move(a);
    EXPECT_EQ(a.size(), 0u);
    img.depth.assign(5, 0);
    const std::uint8_t* kept = img.labels.data();
    img.labels[4] = static_cast<std::uint8_t>(count - 1);
    check_codes(img.labels);
    const RegionResult r = to_result(std::move(img));
    EXPECT_EQ(r.split, kind == Labels::split);
    EXPECT_EQ(r.alternating, kind == Labels::alternating);
    EXPECT_EQ(r.each_piece, kind == Labels::each_piece);
    EXPECT_EQ(r.labels.size(), kind == Labels::plain ? 5u : 0u);
    EXPECT_EQ(r.split_labels.size(), kind == Labels::split ? 5u : 0u);
    EXPECT_EQ(r.alternating_labels.size(), kind == Labels::alternating ? 5u : 0u);
    EXPECT_EQ(r.piece_labels.size(), kind == Labels::each_piece ? 5u : 0u);
    EXPECT_EQ(r.codes(), (std::vector<std::uint8_t>{0, 0, 1, 0, static_cast<std::uint8_t>(count - 1)}));
    const void* taken = kind == Labels::plain ? static_cast<const void*>(r.labels.data())
                        : kind == Labels::split ? static_cast<const void*>(r.split_labels.data())
                        : kind == Labels::alternating ? static_cast<const void*>(r.alternating_labels.data())
                                                      : static_cast<const void*>(r.piece_labels.data());
    EXPECT_EQ(taken, kept) << "the codes were copied, not moved";
    LabelCodes bad(kind, 3);
    bad[1] = count;
    EXPECT_DEATH(check_codes(bad), "internal error");
  }
}

// The host's cull for a device (region_cull with min_block 2, the Vulkan
// backend's culled share) proves blocks of 2 x 2 pixels too, where the CPU
// render hands such blocks to its pixel kernel unproved: it lists fewer
// pixels than a cull that stops at 4 x 4 blocks (which listed as many as one
// stopping at 2 x 2 before, since no 2 x 2 block got a proof), and every
// pixel it decides has region_cpu's label.
TEST(RegionCull, ADeviceCullProvesBlocksOfTwoByTwo) {
  for (const auto& [file, point] : {std::pair<const char*, int>{"/examples/figures/fig8.json", 3},
                                    std::pair<const char*, int>{"/examples/figures/fig2.json", 1}}) {
    const BSpline spline = read_spline_file(kSource + file);
    const RegionProblem p = RegionProblem::make(spline, test::region_request(point, 10, 256, std::nullopt, false));
    const RegionSetup& s = p.setup();
    const RegionImage cpu = region_cpu(s, 2);
    RegionImage two = blank_image(s), four = blank_image(s);
    const std::vector<std::array<int, 2>> listed_two = region_cull(s, two, 2, 2);
    const std::vector<std::array<int, 2>> listed_four = region_cull(s, four, 4, 2);
    EXPECT_GT(listed_two.size(), 0u) << file;
    EXPECT_LT(listed_two.size() * 3, listed_four.size() * 2) << file << ": 2 x 2 blocks were not proved";
    std::vector<char> is_listed(cpu.labels.size(), 0);
    for (const auto& [i, j] : listed_two) is_listed[static_cast<std::size_t>(j) * 256 + i] = 1;
    int wrong = 0;
    for (std::size_t at = 0; at < cpu.labels.size(); ++at)
      wrong += !is_listed[at] && two.labels[at] != cpu.labels[at];
    EXPECT_EQ(wrong, 0) << file << ": decided pixels whose label is not region_cpu's";
  }
}

// The exact path converts a position to GMP rationals, which raises SIGFPE
// on NaN or an infinity. RegionProblem::classify refuses such a position; a
// caller inside the library (a search whose arithmetic overflowed) gets
// label 0, no region's, from the exact path and from the reference that
// falls back on it.
TEST(RegionFast, TheExactPathGivesANonFinitePositionNoRegion) {
  const BSpline spline = read_spline_file(kSource + "/examples/figures/fig8.json");
  RegionRequest o;
  o.point = 3;
  o.width = o.height = 8;
  const RegionProblem p = RegionProblem::make(spline, o);
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  for (const Vec2 at : {Vec2{inf, 0}, Vec2{0, -inf}, Vec2{nan, 1}, Vec2{1, nan}}) {
    EXPECT_EQ(backend::classify_position_exact(p.setup(), at).label, 0);
    EXPECT_EQ(backend::classify_position(p.setup(), at).label, 0);
    EXPECT_THROW((void)p.classify(at), InputError);
  }
  // A finite position still gets its label: where `cmr fix` moves P3, the curve passes.
  EXPECT_NE(backend::classify_position_exact(p.setup(), {1.9241387367787128, -3.861045755889574}).label, 0);
}

}  // namespace
}  // namespace cmr
