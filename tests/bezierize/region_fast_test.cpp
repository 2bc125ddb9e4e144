// The optimised region paths (block proofs with their adaptive piece budget,
// the per-pixel path that halves each deep piece once) against the exact
// path: on seeded zooms onto a region boundary (4e-4 and 1e-2 wide, the
// bench's views), every label of region_cpu and of classify_position must be
// what classify_position_exact gives the pixel's centre; and so must the
// labels of seeded points within 1e-9 of the boundary. Scenes: a cubic Bezier
// (fig2 P1), the uniform cubic B-spline (fig8 P3), the degree-9 Bezier (P4),
// at D = 10 and 16. Images are small so the exact path stays within seconds.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <sstream>
#include <string>

#include "bezierize/region.hpp"
#include "bezierize/region_setup.hpp"
#include "tests/bezierize/boundary_point.hpp"
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

}  // namespace
}  // namespace cmr
