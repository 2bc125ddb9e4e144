// The benchmark's baseline (tools/bench/published_method.hpp) is the published
// method, not a different one: its fixed-degree ξ equals cmr::lambda_bernstein
// to rounding, and its plain-double labels equal cmr's certified labels except
// where plain double may legitimately differ.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "bezierize/lambda.hpp"
#include "region/region.hpp"
#include "spline/errors.hpp"
#include "spline/spline_json.hpp"
#include "tools/bench/published_method.hpp"
#ifdef CMR_BENCH_VK
#include "tools/bench/published_method_vk.hpp"
#endif

namespace {

using cmr::Vec2;
using cmr::View;
using cmr::bench::published_lambda;
using cmr::bench::published_region;
using cmr::bench::PublishedRegion;

const std::string kSource = CMR_SOURCE_DIR;

/// Relative agreement of ξ: rounding of the ~n² terms per coefficient, each of
/// size at most max|ξ| times the binomial weights' spread; 1e-11 is far above
/// rounding and far below any wrong weight or index (an O(1) relative error).
constexpr double kXiRelativeTolerance = 1e-11;

TEST(PublishedMethod, LambdaAndItsEndsEqualCmrLambdaOnRandomCurves) {
  std::mt19937_64 rng(20241123);
  std::uniform_real_distribution<double> coord(-4, 4);
  for (int n = cmr::bench::kPublishedMinDegree; n <= cmr::bench::kPublishedMaxDegree; ++n) {
    for (int trial = 0; trial < 200; ++trial) {
      std::vector<Vec2> P(n + 1);
      for (Vec2& p : P) p = Vec2(coord(rng), coord(rng));
      const std::vector<double> ours = published_lambda(P);
      const std::array<double, 2> ends = cmr::bench::published_lambda_ends(P);
      const cmr::Bernstein<double> ref = cmr::lambda_bernstein<double>(P);
      ASSERT_EQ(ours.size(), ref.size()) << "degree " << n;
      double scale = 0;
      for (double v : ref) scale = std::max(scale, std::fabs(v));
      for (std::size_t k = 0; k < ref.size(); ++k)
        ASSERT_NEAR(ours[k], ref[k], kXiRelativeTolerance * scale) << "degree " << n << ", trial " << trial << ", xi_" << k;
      EXPECT_NEAR(ends[0], ref.front(), kXiRelativeTolerance * scale) << "degree " << n << ", trial " << trial << ", xi_0";
      EXPECT_NEAR(ends[1], ref.back(), kXiRelativeTolerance * scale) << "degree " << n << ", trial " << trial << ", xi_last";
    }
  }
}

TEST(PublishedMethod, RejectsWhatItHasNoCodeFor) {
  EXPECT_THROW((void)published_lambda({Vec2(0, 0), Vec2(1, 0), Vec2(1, 1)}), cmr::InputError);  // degree 2
  const cmr::BSpline c1 = cmr::BSpline::make(3, {0, 0, 0, 1, 1, 2, 2, 2},
                                             {Vec2(0, 0), Vec2(1, 1), Vec2(2, 0), Vec2(3, 1), Vec2(4, 0), Vec2(5, 1)});
  PublishedRegion r;
  r.width = r.height = 4;
  r.view = View{0, 0, 5, 1};
  EXPECT_THROW((void)published_region(c1, r), cmr::InputError);  // knot 1 twice: C1 only
  r.point = 6;
  EXPECT_THROW((void)published_region(cmr::read_spline_file(kSource + "/examples/figures/fig8.json"), r),
               cmr::InputError);
}

// cmr's certified labels and which pixels needed the exact path, through cmr's
// region API (the one place this test calls it).
struct Certified {
  std::vector<uint8_t> labels;
  std::vector<bool> exact;
  View view;
};
Certified certified_labels(const cmr::BSpline& spline, int point, int depth, int size, std::optional<View> view) {
  cmr::RegionRequest o;
  o.point = point;
  o.max_depth = depth;
  o.width = o.height = size;
  o.view = view;
  o.depth = false;
  const cmr::RegionProblem problem = cmr::RegionProblem::make(spline, o);
  Certified c{cmr::CpuRegionBackend().render(problem).codes(), std::vector<bool>(static_cast<std::size_t>(size) * size),
              problem.view()};
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i)
      c.exact[static_cast<std::size_t>(j) * size + i] =
          problem.classify(cmr::pixel_center(c.view, size, size, i, j)).exact;
  return c;
}

// Agreement criterion: the baseline is uncertified plain double, so it may
// differ from the certified label only at pixels where cmr needed the exact
// path (a sign too close to zero for a double bound) or within one pixel of a
// label change in cmr's map (some 8-neighbour has another label). Everywhere
// else the labels must be equal; and the exempt pixels must stay a small share
// of the image, or the criterion would excuse anything.
void expect_agreement(const cmr::BSpline& spline, int point, int depth, int size, std::optional<View> view,
                      const std::string& scene) {
  const Certified c = certified_labels(spline, point, depth, size, view);
  PublishedRegion r;
  r.point = point;
  r.max_depth = depth;
  r.width = r.height = size;
  r.view = c.view;
  const std::vector<uint8_t> ours = published_region(spline, r);
  const auto at = [&](int i, int j) { return c.labels[static_cast<std::size_t>(j) * size + i]; };
  int exempt = 0, distinct = 0;
  std::vector<bool> seen(256, false);
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) {
      const std::size_t idx = static_cast<std::size_t>(j) * size + i;
      if (!seen[c.labels[idx]]) ++distinct;
      seen[c.labels[idx]] = true;
      bool near_change = c.exact[idx];
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int ii = i + di, jj = j + dj;
          if (ii >= 0 && jj >= 0 && ii < size && jj < size && at(ii, jj) != at(i, j)) near_change = true;
        }
      exempt += near_change;
      if (!near_change) {
        ASSERT_EQ(int(ours[idx]), int(c.labels[idx])) << scene << ": pixel (" << i << ", " << j << ")";
      }
    }
  EXPECT_GE(distinct, 2) << scene << ": the view shows no region boundary, so the test proves little";
  EXPECT_LT(exempt, size * size / 10) << scene << ": too many pixels exempt from the comparison";
}

// A view `factor` times smaller than the default one, centred on the first
// label change along a row of the default view, rows taken from the middle out.
View zoom_on_boundary(const cmr::BSpline& spline, int point, int depth, int size, double factor) {
  const Certified c = certified_labels(spline, point, depth, size, std::nullopt);
  for (int step = 0; step < size; ++step) {
    const int j = size / 2 + (step % 2 ? -(step + 1) / 2 : step / 2);
    if (j < 0 || j >= size) continue;
    for (int i = 1; i < size; ++i)
      if (c.labels[static_cast<std::size_t>(j) * size + i] != c.labels[static_cast<std::size_t>(j) * size + i - 1]) {
        const Vec2 p = cmr::pixel_center(c.view, size, size, i, j);
        const double hx = (c.view.x1 - c.view.x0) / (2 * factor), hy = (c.view.y1 - c.view.y0) / (2 * factor);
        return View{p.x - hx, p.y - hy, p.x + hx, p.y + hy};
      }
  }
  ADD_FAILURE() << "no label change in the default view";
  return c.view;
}

TEST(PublishedMethod, LabelsAgreeWithCertifiedLabelsOnUniformCubic) {
  const cmr::BSpline s = cmr::read_spline_file(kSource + "/examples/figures/fig8.json");
  expect_agreement(s, 3, 12, 160, std::nullopt, "fig8 P3, default view");
  expect_agreement(s, 3, 16, 160, zoom_on_boundary(s, 3, 16, 160, 50), "fig8 P3, zoom on a boundary");
  expect_agreement(s, 1, 10, 96, std::nullopt, "fig8 P1, default view");
}

TEST(PublishedMethod, LabelsAgreeWithCertifiedLabelsOnDegree9Bezier) {
  const cmr::BSpline s = cmr::read_spline_file(kSource + "/examples/bezier9.json");
  expect_agreement(s, 4, 12, 128, std::nullopt, "bezier9 P4, default view");
  expect_agreement(s, 4, 16, 128, zoom_on_boundary(s, 4, 16, 128, 50), "bezier9 P4, zoom on a boundary");
}

// The vectorised baseline (published_region_lanes) and the shader baseline
// in both its forms (published_region_vulkan, fp64 on lavapipe, as
// fragments and as compute invocations) compute every pixel
// with the same operations in the same order as published_region: the label
// maps must be equal byte for byte, on views with region boundaries (default
// views, boundary zooms down to 4e-4 of the default view's width), on image
// widths that are not a multiple of the lane count, at several depths.
constexpr int kShaderWidth = 67;  ///< the zooms' image width in expect_lanes_equal_on_views

void expect_lanes_equal(const cmr::BSpline& spline, int point, int depth, int width, int height, const View& view,
                        const std::string& scene) {
  PublishedRegion r;
  r.point = point;
  r.max_depth = depth;
  r.width = width;
  r.height = height;
  r.view = view;
  const std::vector<uint8_t> scalar = published_region(spline, r);
  std::vector<int> count(4, 0);
  for (const uint8_t c : scalar) ++count[std::min<int>(c, 3)];
  for (const int form : {0, 1, 2, 3}) {
    const bool lockstep = form == 1;
    // The shader: at D = 16 on the zooms only (one pipeline per scene; lavapipe compiles each for seconds).
    if (form >= 2 && (depth != 16 || width != kShaderWidth)) continue;
#ifdef CMR_BENCH_VK
    using cmr::bench::ShaderStage;
    const std::vector<uint8_t> lanes =
        form >= 2 ? cmr::bench::published_region_vulkan(spline, r, form == 2 ? ShaderStage::fragment : ShaderStage::compute)
                  : cmr::bench::published_region_lanes(spline, r, lockstep);
#else
    if (form >= 2) continue;
    const std::vector<uint8_t> lanes = cmr::bench::published_region_lanes(spline, r, lockstep);
#endif
    ASSERT_EQ(scalar.size(), lanes.size()) << scene;
    int differ = 0, first = -1;
    for (std::size_t k = 0; k < scalar.size(); ++k) {
      if (scalar[k] != lanes[k] && first < 0) first = static_cast<int>(k);
      differ += scalar[k] != lanes[k];
    }
    const char* form_name = form == 3   ? ", compute shader"
                            : form == 2 ? ", fragment shader"
                            : lockstep  ? ", lock step"
                                        : ", level 0 vectorised";
    EXPECT_EQ(differ, 0) << scene << form_name << ": first differing pixel ("
                         << first % width << ", " << first / width << ")";
  }
  int labels_seen = 0;
  for (int c : count) labels_seen += c > 0;
  if (depth >= 3) {
    EXPECT_GE(labels_seen, 2) << scene << ": the view shows one label only, so the test proves little";
  }
}

// `view` shrunk `factor` times around the first label change of the scalar
// baseline's map of it (size x size pixels), rows from the middle out.
View zoom_in(const cmr::BSpline& spline, int point, int depth, int size, const View& view, double factor) {
  PublishedRegion r;
  r.point = point;
  r.max_depth = depth;
  r.width = r.height = size;
  r.view = view;
  const std::vector<uint8_t> labels = published_region(spline, r);
  for (int step = 0; step < size; ++step) {
    const int j = size / 2 + (step % 2 ? -(step + 1) / 2 : step / 2);
    for (int i = 1; i < size; ++i)
      if (labels[static_cast<std::size_t>(j) * size + i] != labels[static_cast<std::size_t>(j) * size + i - 1]) {
        const Vec2 a = cmr::pixel_center(view, size, size, i - 1, j), b = cmr::pixel_center(view, size, size, i, j);
        const Vec2 p = 0.5 * (a + b);
        const double hx = (view.x1 - view.x0) / (2 * factor), hy = (view.y1 - view.y0) / (2 * factor);
        return View{p.x - hx, p.y - hy, p.x + hx, p.y + hy};
      }
  }
  ADD_FAILURE() << "no label change in the view";
  return view;
}

void expect_lanes_equal_on_views(const cmr::BSpline& spline, int point, const std::string& name) {
  const Certified base = certified_labels(spline, point, 12, 96, std::nullopt);
  for (const int depth : {0, 3, 10, 16}) {
    expect_lanes_equal(spline, point, depth, 97, 61, base.view, name + ", default view, D = " + std::to_string(depth));
    View zoom = base.view;
    for (const int factor : {40, 1600, 64000}) {  // 1/64000 of the default view: about a 4e-4 zoom
      zoom = zoom_in(spline, point, depth >= 3 ? depth : 10, 96, zoom, 40);
      expect_lanes_equal(spline, point, depth, kShaderWidth, 45, zoom,
                         name + ", zoom 1/" + std::to_string(factor) + ", D = " + std::to_string(depth));
    }
  }
}

TEST(PublishedMethod, LanesEqualScalarOnCubicBezier) {
  expect_lanes_equal_on_views(cmr::read_spline_file(kSource + "/examples/figures/fig2.json"), 1, "fig2 P1");
}

TEST(PublishedMethod, LanesEqualScalarOnUniformCubic) {
  expect_lanes_equal_on_views(cmr::read_spline_file(kSource + "/examples/figures/fig8.json"), 3, "fig8 P3");
}

TEST(PublishedMethod, LanesEqualScalarOnDegree9Bezier) {
  expect_lanes_equal_on_views(cmr::read_spline_file(kSource + "/examples/bezier9.json"), 4, "bezier9 P4");
}

TEST(PublishedMethod, LanesRejectWhatTheScalarRejects) {
  PublishedRegion r;
  r.width = r.height = 4;
  r.view = View{0, 0, 5, 1};
  r.point = 6;
  EXPECT_THROW((void)cmr::bench::published_region_lanes(
                   cmr::read_spline_file(kSource + "/examples/figures/fig8.json"), r),
               cmr::InputError);
#ifdef CMR_BENCH_VK
  for (const auto stage : {cmr::bench::ShaderStage::fragment, cmr::bench::ShaderStage::compute})
    EXPECT_THROW((void)cmr::bench::published_region_vulkan(
                     cmr::read_spline_file(kSource + "/examples/figures/fig8.json"), r, stage),
                 cmr::InputError);
#endif
}

}  // namespace
