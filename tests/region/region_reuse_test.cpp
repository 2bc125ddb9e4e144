// Reuse of a failed block proof by its quarters and pixels (box_reuse.hpp,
// block.cpp: cull_block, classify_box_labels; region.cpp: classify_pixel_flat): label
// maps (no depth map) rendered with reuse must equal those rendered without
// it (set_block_reuse, the switch behind CMR_BLOCK_REUSE=0) and the exact
// path's, pixel by pixel, on seeded zooms onto a region boundary. Scenes: a
// cubic Bezier (fig2 P1), the uniform cubic B-spline (fig8 P3), the degree-9
// Bezier (P4) and a rational cubic B-spline (nurbs_cubic P3); modes CMRWI and
// CMR (where eta's traversal is reused too); D = 10 and 16. Each scene also
// checks that reuse happened, in the block proofs and at the pixels (and for
// nu in CMR mode where the scene has a CMR boundary: fig8 P3, nurbs_cubic
// P3), so that equal maps cannot come from reuse never taking place.
#include <gtest/gtest.h>

#include <random>
#include <sstream>
#include <string>

#include "region/box_reuse.hpp"
#include "region/region.hpp"
#include "region/region_setup.hpp"
#include "spline/spline_json.hpp"
#include "tests/region/boundary_point.hpp"

namespace cmr {
namespace {

using namespace cmr::backend;

const std::string kSource = CMR_SOURCE_DIR;

RegionRequest request(int point, int depth, int size, std::optional<View> view, Mode mode) {
  return test::region_request(point, depth, size, view, false, mode);  // labels only: reuse is for label maps
}

// Restores the switches' defaults whatever the test's outcome.
struct ReuseSwitch {
  ~ReuseSwitch() {
    set_block_reuse(-1);
    set_witness_search(-1);
  }
};

// Without the not-monotone witness (region_witness_test.cpp tests it with
// reuse): it decides many of the blocks whose quarters and pixels would
// take what they learned, and the cubic Bezier's pixels then reuse nothing
// in these views, which the checks below would not see tested.
RegionImage render(const RegionSetup& s, bool reuse) {
  set_block_reuse(reuse ? 1 : 0);
  set_witness_search(0);
  return region_cpu(s, 2);
}

void expect_reuse_exact(const BSpline& spline, int point, const std::string& name, int size, int exact_size,
                        unsigned seed, bool check_eta = true) {
  const ReuseSwitch restore;
  std::mt19937_64 rng(seed);
  const BlockReuseCounts before = block_reuse_counts();
  std::uint64_t eta = 0;  // reuse of nu's traversal (CMR mode only)
  for (const Mode mode : {Mode::cmrwi, Mode::cmr}) {
    const std::uint64_t eta_before = block_reuse_counts().eta;
    for (const int depth : {10, 16}) {
      // The default view at a size with many failed blocks (nu's reuse in CMR mode; see eta below).
      {
        const RegionProblem p = RegionProblem::make(spline, request(point, depth, 256, std::nullopt, mode));
        const RegionImage on = render(p.setup(), true), off = render(p.setup(), false);
        { int h[256] = {}; for (auto c : on.labels) h[c]++; for (int k = 0; k < 256; ++k) if (h[k]) fprintf(stderr, "label %d: %d\n", k, h[k]); }
    EXPECT_EQ(on.labels, off.labels) << name << ", default view 256^2, D = " << depth
                                         << (mode == Mode::cmr ? ", CMR" : ", CMRWI");
      }
      const RegionProblem whole = RegionProblem::make(spline, request(point, depth, 64, std::nullopt, mode));
      const auto edge = test::boundary_point(whole, 64);
      if (!edge) continue;  // one label in the default view
      std::uniform_real_distribution<double> log_width(std::log(1e-4), std::log(2e-1)), shift(-0.25, 0.25);
      for (int zoom = 0; zoom < 2; ++zoom) {
        const double w = std::exp(log_width(rng));
        const Vec2 c{edge->x + shift(rng) * w, edge->y + shift(rng) * w};
        const View v{c.x - w / 2, c.y - w / 2, c.x + w / 2, c.y + w / 2};
        std::ostringstream where;
        where.precision(17);
        where << name << (mode == Mode::cmr ? ", CMR" : ", CMRWI") << ", D = " << depth << ", seed " << seed
              << ", zoom " << zoom << " (width " << w << " at " << c.x << ", " << c.y << ")";
        // With and without reuse, at a size with several levels of quartering.
        {
          const RegionProblem p = RegionProblem::make(spline, request(point, depth, size, v, mode));
          const RegionImage on = render(p.setup(), true), off = render(p.setup(), false);
          int wrong = 0;
          std::ostringstream first;
          for (int j = 0; j < size; ++j)
            for (int i = 0; i < size; ++i) {
              const std::size_t at = static_cast<std::size_t>(j) * size + i;
              if (on.labels[at] != off.labels[at] && wrong++ < 3)
                first << "\n  pixel (" << i << ", " << j << "): code " << int(on.labels[at]) << " with reuse, "
                      << int(off.labels[at]) << " without";
            }
          EXPECT_EQ(wrong, 0) << where.str() << ", " << size << "^2" << first.str();
        }
        // With reuse against the exact path.
        {
          const RegionProblem p = RegionProblem::make(spline, request(point, depth, exact_size, v, mode));
          const RegionSetup& s = p.setup();
          const RegionImage on = render(s, true);
          std::ostringstream first;
          const int wrong = test::labels_not_exact(s, on, exact_size, first);
          EXPECT_EQ(wrong, 0) << where.str() << ", " << exact_size << "^2 against the exact path" << first.str();
        }
      }
    }
    const std::uint64_t eta_here = block_reuse_counts().eta - eta_before;
    if (mode == Mode::cmrwi) {
      EXPECT_EQ(eta_here, 0u) << name << ": nu reused without CMR mode";
    }
    eta += eta_here;
  }
  const BlockReuseCounts after = block_reuse_counts();
  const auto box = (after.box_nodes + after.box_segments + after.box_level0) -
                   (before.box_nodes + before.box_segments + before.box_level0);
  const auto pixel = (after.pixel_nodes + after.pixel_segments) - (before.pixel_nodes + before.pixel_segments);
  EXPECT_GT(box, 0u) << name << ": no block proof took anything from its parent";
  EXPECT_GT(pixel, 0u) << name << ": no pixel took anything from its block";
  if (check_eta) {
    EXPECT_GT(eta, 0u) << name << ": no reuse of nu's traversal in CMR mode";
  }
}

TEST(RegionReuse, CubicBezierLabelsUnchanged) {
  expect_reuse_exact(read_spline_file(kSource + "/examples/figures/fig2.json"), 1, "fig2 P1", 96, 32, 2311,
                     false);  // CMR: the inflection fails in the whole default view (no boundary to zoom onto)
}

TEST(RegionReuse, UniformCubicLabelsUnchanged) {
  expect_reuse_exact(read_spline_file(kSource + "/examples/figures/fig8.json"), 3, "fig8 P3", 96, 32, 2312);
}

TEST(RegionReuse, Degree9BezierLabelsUnchanged) {
  expect_reuse_exact(read_spline_file(kSource + "/examples/bezier9.json"), 4, "bezier9 P4", 64, 16, 2313,
                     false);  // CMR: as for fig2 P1
}

TEST(RegionReuse, RationalCubicLabelsUnchanged) {
  expect_reuse_exact(read_spline_file(kSource + "/examples/rational/nurbs_cubic.json"), 3, "nurbs_cubic P3", 96, 20,
                     2314);
}

// The switch itself: off means no reuse at all.
TEST(RegionReuse, SwitchOffReusesNothing) {
  const ReuseSwitch restore;
  const BSpline spline = read_spline_file(kSource + "/examples/figures/fig8.json");
  const RegionProblem p = RegionProblem::make(spline, request(3, 10, 128, std::nullopt, Mode::cmrwi));
  const BlockReuseCounts before = block_reuse_counts();
  render(p.setup(), false);
  const BlockReuseCounts after = block_reuse_counts();
  EXPECT_EQ(after.box_nodes + after.box_segments + after.box_level0 + after.pixel_nodes + after.pixel_segments,
            before.box_nodes + before.box_segments + before.box_level0 + before.pixel_nodes + before.pixel_segments);
}


// A block whose box cannot be scaled exactly (kernel_displacement: NaN, a
// displacement that would be subnormal) has no proof and learns nothing, so
// its quarters and pixels must not take the facts that the last block at the
// same quartering depth left (the blocks' knowledge is kept per thread, from
// one render to the next). The curve: fig2 scaled by 2^600 and moved so that
// its point 1, the one moved, is at the origin (the setup then scales by
// about 2^-600). In a view 2^-418 wide around it the pixel columns are
// 2^-425 apart, so a box with a column within 8 of the middle cannot be
// scaled and the others can: the whole image's top block cannot, its
// quarter at the top left can. Before it, on the same thread, the curve's
// mirror image is rendered in a view 2^-300 wide, where every box can be
// scaled and its one top block is proved of the other direction. (Before a
// block that cannot be scaled reset its knowledge, this test crashed: the
// quarters of such a block at a depth no block had reached on the thread
// read the records of no entries.)
TEST(RegionReuse, AnUnscalableBlockHandsOnNoFacts) {
  const ReuseSwitch restore;
  std::vector<Vec2> pts = read_spline_file(kSource + "/examples/figures/fig2.json").points();
  const Vec2 at = pts[1];
  for (Vec2& q : pts) q = std::ldexp(1.0, 600) * (q - at);
  std::vector<Vec2> mirrored = pts;
  for (Vec2& q : mirrored) q.x = -q.x;
  const double w = std::ldexp(1.0, -418), wide = std::ldexp(1.0, -300);
  const View tiny{-w / 2, -w / 2, w / 2, w / 2};
  for (const Mode mode : {Mode::cmrwi, Mode::cmr}) {
    const RegionProblem first = RegionProblem::make(
        BSpline::bezier(mirrored), request(1, 10, 64, View{-wide / 2, -wide / 2, wide / 2, wide / 2}, mode));
    const RegionProblem p = RegionProblem::make(BSpline::bezier(pts), request(1, 10, 128, tiny, mode));
    set_block_reuse(1);
    set_witness_search(0);
    const RegionImage before = region_cpu(first.setup(), 1);  // the facts of its top block, on this thread
    const RegionImage on = region_cpu(p.setup(), 1);
    set_block_reuse(0);
    const RegionImage off = region_cpu(p.setup(), 1);
    const char* m = mode == Mode::cmr ? "CMR" : "CMRWI";
    ASSERT_NE(before.labels[0], on.labels[0]) << m << ": the mirror image must have the other label";
    EXPECT_EQ(on.labels, off.labels) << m;
    int differ = 0;
    for (int j = 0; j < 128; j += 4)
      for (int i = 0; i < 128; i += 4) {
        const Vec2 c = pixel_center(tiny, 128, 128, i, j);
        differ += code(p.classify(c).label) != on.labels[static_cast<std::size_t>(j) * 128 + i];
      }
    EXPECT_EQ(differ, 0) << m << ": pixels unlike the exact label";
  }
}

}  // namespace
}  // namespace cmr
