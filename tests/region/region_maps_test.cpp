// The CPU render's label maps, codes and decision depths, against the exact
// path pixel by pixel on seeded zooms onto a region boundary: region_cpu
// (block proofs, the per-pixel kernel with its one bound per segment, the
// label-only shortcuts that stop at the first failing segment) must give
// every pixel the code and, with a depth map, the depth that
// classify_position_exact gives its centre; without a depth map every depth
// is 0. Scenes: a cubic Bezier (fig2 P1), the uniform cubic B-spline (fig8
// P3), the degree-9 Bezier (P4); D = 10 and 16; modes CMRWI and CMR; zoom
// widths and offsets drawn from a seeded generator, so a failure names a
// reproducible case.
#include <gtest/gtest.h>

#include <random>
#include <sstream>
#include <string>

#include "region/region.hpp"
#include "region/region_setup.hpp"
#include "tests/region/boundary_point.hpp"
#include "spline/spline_json.hpp"

namespace cmr {
namespace {

using namespace cmr::backend;

const std::string kSource = CMR_SOURCE_DIR;

RegionRequest request(int point, int depth, int size, std::optional<View> view, bool depth_map, Mode mode) {
  return test::region_request(point, depth, size, view, depth_map, mode);
}

// A label change between neighbouring pixels of a row of the default view
// (rows from the middle out), bisected 60 times on exact labels.
std::optional<Vec2> boundary_point(const BSpline& spline, int point, int depth, Mode mode) {
  const int size = 64;
  return test::boundary_point(RegionProblem::make(spline, request(point, depth, size, std::nullopt, false, mode)), size);
}

void expect_exact_maps(const BSpline& spline, int point, const std::string& name, int size, unsigned seed) {
  std::mt19937_64 rng(seed);
  for (const Mode mode : {Mode::cmrwi, Mode::cmr}) {
    for (const int depth : {10, 16}) {
      const auto edge = boundary_point(spline, point, depth, mode);
      if (!edge) continue;  // one label in the default view (CMR: the inflection fails everywhere)
      std::uniform_real_distribution<double> log_width(std::log(1e-4), std::log(2e-1)), shift(-0.25, 0.25);
      for (int zoom = 0; zoom < 2; ++zoom) {
        const double w = std::exp(log_width(rng));
        const Vec2 c{edge->x + shift(rng) * w, edge->y + shift(rng) * w};
        const View v{c.x - w / 2, c.y - w / 2, c.x + w / 2, c.y + w / 2};
        for (const bool depth_map : {false, true}) {
          const RegionProblem p = RegionProblem::make(spline, request(point, depth, size, v, depth_map, mode));
          const RegionSetup& s = p.setup();
          const RegionImage img = region_cpu(s, 2);
          int wrong = 0;
          std::ostringstream first;
          for (int j = 0; j < size; ++j)
            for (int i = 0; i < size; ++i) {
              const PixelResult exact = classify_position_exact(s, pixel_center(v, size, size, i, j));
              const std::size_t at = static_cast<std::size_t>(j) * size + i;
              const int want_depth = depth_map ? exact.depth : 0;
              if ((img.labels[at] != exact.label || img.depth[at] != want_depth) && wrong++ < 3)
                first << "\n  pixel (" << i << ", " << j << "): code " << int(img.labels[at]) << " depth "
                      << int(img.depth[at]) << ", exact code " << int(exact.label) << " depth " << want_depth;
            }
          std::ostringstream where;
          where.precision(17);
          where << name << (mode == Mode::cmr ? ", CMR" : ", CMRWI") << ", D = " << depth << ", seed " << seed
                << ", zoom " << zoom << " (width " << w << " at " << c.x << ", " << c.y << ")"
                << (depth_map ? ", depth map" : ", labels only");
          EXPECT_EQ(wrong, 0) << where.str() << first.str();
        }
      }
    }
  }
}

TEST(RegionMaps, CubicBezierCodesAndDepthsAreExact) {
  expect_exact_maps(read_spline_file(kSource + "/examples/figures/fig2.json"), 1, "fig2 P1", 20, 2301);
}

TEST(RegionMaps, UniformCubicCodesAndDepthsAreExact) {
  expect_exact_maps(read_spline_file(kSource + "/examples/figures/fig8.json"), 3, "fig8 P3", 20, 2302);
}

TEST(RegionMaps, Degree9BezierCodesAndDepthsAreExact) {
  expect_exact_maps(read_spline_file(kSource + "/examples/bezier9.json"), 4, "bezier9 P4", 12, 2303);
}

}  // namespace
}  // namespace cmr
