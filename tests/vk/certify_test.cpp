// Certification of the region backends against the exact rational path.
//
// Every label of every region backend, on every backend (CPU; Vulkan fp64 and
// fp32 with host culling; Vulkan fp64 and fp32 shading every pixel), must be
// what classify_position_exact gives the pixel's centre: the certified paths
// may only answer where their signs are certain. The scenes are the hard ones
// for floating point:
//  * structural zeros: designs where a Bernstein coefficient of xi (or nu) is
//    exactly zero for every position of the moved point (collinear or
//    coincident leading control points, a degree-elevated parabola starting at
//    its vertex), which must also stay cheap: the zero is known on the host;
//  * exact zeros along a line of pixels (a mirror-symmetric design moved along
//    its axis, a straight control polygon);
//  * zoomed views 1e-4 (and 1e-7) wide centred on a region boundary found by
//    bisection, and on the extreme point of a region, where the boundary is
//    tangent to a pixel row.
// Images are small (at most 48x48) so that the exact path over every pixel
// stays within seconds per scene.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "region/region.hpp"
#include "tests/test_util.hpp"
#include "tests/vk/render_util.hpp"

namespace cmr {
namespace {

using namespace cmr::backend;

struct Scene {
  BSpline spline;
  RegionRequest options;
};

RegionRequest opts(int point, Mode mode = Mode::cmrwi, int size = 48, std::optional<int> split = {},
                   std::vector<int> with = {}) {
  RegionRequest o;
  o.point = point;
  o.mode = mode;
  o.split = split;
  o.with = std::move(with);
  o.width = size;
  o.height = size;
  return o;
}

std::vector<double> iota_knots(int count) {
  std::vector<double> k(count);
  for (int i = 0; i < count; ++i) k[i] = i;
  return k;
}

// ------------------------------------------------------------------ designs

// Quartic whose first four points are a degree-elevated parabola at its vertex
// (differences (1,0),(1,1),(1,2): P'.P'' = 0 and P''' = 0 at t = 0), so
// lambda(0) = xi_0 = 0 whatever P4 is.
BSpline parabola_vertex_quartic() { return BSpline::bezier({{0, 0}, {1, 0}, {2, 1}, {3, 3}, {4, 6}}); }

// Quartic with P0..P3 collinear and equally spaced: xi_0 = 0 for every P4
// (lambda(0) depends on P0..P3 only), and nu_0 = nu_1 = 0.
BSpline collinear_start_quartic() { return BSpline::bezier({{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 1.5}}); }

// Quintic with P0..P3 collinear: xi_0 = 0 for every P5.
BSpline collinear_start_quintic() { return BSpline::bezier({{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 1}, {5, 3}}); }

// Cubic with P0, P1, P2 collinear: nu_0 = det(P', P'')(0) = 0 for every P3.
BSpline collinear_start_cubic() { return BSpline::bezier({{0, 0}, {1, 0}, {2, 0}, {3, 1}}); }

// Cubic with P0 = P1 (a vanishing first leg): P'(0) = 0, so lambda and its
// derivative vanish at 0 (xi_0 = xi_1 = 0) for every P3.
BSpline double_start_cubic() { return BSpline::bezier({{0, 0}, {0, 0}, {1, 1}, {3, 0.5}}); }

// Clamped cubic with P0..P3 collinear and equally spaced: segment 1's first
// three Bezier points lie on that line whatever P4 is, so its nu_0 = 0.
BSpline collinear_clamped_cubic() {
  return BSpline::make(3, {0, 0, 0, 1, 2, 3, 3, 3}, {{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 1}, {5, 3}});
}

// Uniform cubic on seven collinear, equally spaced points: moving P3 leaves
// the ends of segments 0 and 3 on the line (nu_0 of segment 0, nu_last of
// segment 3 are zero).
BSpline straight_uniform_cubic() {
  std::vector<Vec2> p;
  for (int i = 0; i < 7; ++i) p.push_back({i, 0});
  return BSpline::make(3, iota_knots(9), std::move(p));
}

// Quartic B-spline on a straight control polygon but for its last point:
// segments 0 and 1 are straight (fixed), segment 2's first four Bezier points
// lie on the line whatever P6 is, so its xi_0 = 0.
BSpline straight_tail_quartic_bspline() {
  return BSpline::make(4, {0, 0, 0, 0, 1, 2, 3, 3, 3, 3}, {{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 0}, {5, 0}, {6, 1.5}});
}

// As above with P0, P1 off the line: the fixed segments 0 and 1 are not
// monotone (decided at level 1), so every position is label 0.
BSpline collinear_tail_quartic_bspline() {
  return BSpline::make(4, {0, 0, 0, 0, 1, 2, 3, 3, 3, 3},
                       {{-2, 2}, {-1, 0.5}, {1, 0}, {2, 0}, {3, 0}, {4, 0}, {5, 1.5}});
}

// The arch of examples/report/arch.json: symmetric about x = 0, its joint at
// the curvature minimum. Moving P2 along the axis (or P1 and P3 together
// vertically) keeps the symmetry, so the split verdict dec-inc holds on that
// line only.
BSpline symmetric_arch() {
  return BSpline::make(3, {0, 0, 0, 1, 2, 2, 2}, {{-1, 0}, {-0.75, 0.5}, {0, 1}, {0.75, 0.5}, {1, 0}});
}

// Mirror-symmetric quartic about x = 0; P2 sits on the axis.
BSpline symmetric_quartic() { return BSpline::bezier({{-2, 0}, {-1, 1}, {0, 1.5}, {1, 1}, {2, 0}}); }

// A straight cubic: every coefficient is zero where P1 is on the line.
BSpline straight_cubic() { return BSpline::bezier({{0, 0}, {1, 0}, {2, 0}, {3, 0}}); }

BSpline spiral_clamped() {
  return test::polynomial_as_bspline(test::class_a_bezier(3, -0.35, 1.25), {0, 0, 0, 1, 2, 3, 3, 3});
}

BSpline random_quintic_spline(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  return BSpline::make(5, {0, 0.5, 1, 2.5, 3, 4, 4, 6, 7, 9}, test::random_points(rng, 6, 2.0));
}

// ---------------------------------------------------------------- zooming

// A square view `width` wide centred on c.
View square(Vec2 c, double width) { return {c.x - 0.5 * width, c.y - 0.5 * width, c.x + 0.5 * width, c.y + 0.5 * width}; }

// Bisects the segment a-b (whose ends have different labels) down to a
// length well below `width`, and returns its midpoint: a point of a region
// boundary.
Vec2 bisect_boundary(const RegionSetup& setup, Vec2 a, Vec2 b, double width) {
  const uint8_t la = classify_position(setup, a).label;
  while (std::hypot(b.x - a.x, b.y - a.y) > 1e-3 * width) {
    const Vec2 m = 0.5 * (a + b);
    if (classify_position(setup, m).label == la) a = m;
    else b = m;
  }
  return 0.5 * (a + b);
}

enum class Zoom { none, boundary, extreme };

// How a case's scene is made: a base design, and optionally a zoom onto one of
// its boundaries found on a coarse map.
struct Case {
  std::string name;
  std::function<Scene()> base;
  bool structural = false;  ///< a xi (cmrwi) or xi/nu (cmr) coefficient is zero for every position
  Zoom zoom = Zoom::none;
  double zoom_width = 1e-4;
  std::uint64_t seed = 0;   ///< picks the boundary pair
  int size = 32;            ///< zoomed image side
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

// The scene of a case: the base, or a view zoom_width wide on a boundary of
// the base's coarse map.
Scene make_scene(const Case& c) {
  Scene s = c.base();
  if (c.zoom == Zoom::none) return s;
  RegionRequest coarse = s.options;
  coarse.width = coarse.height = 64;
  const RegionProblem setup_problem = RegionProblem::make(s.spline, coarse);
  const RegionSetup& setup = setup_problem.setup();
  const RegionImage img = region_cpu(setup);
  auto at = [&](int i, int j) { return img.labels[static_cast<std::size_t>(j) * img.width + i]; };
  auto centre = [&](int i, int j) { return pixel_center(img.view, img.width, img.height, i, j); };
  std::vector<std::array<int, 4>> pairs;  // (i, j) and a neighbour with another label
  if (c.zoom == Zoom::boundary) {
    for (int j = 0; j < img.height; ++j)
      for (int i = 0; i < img.width; ++i) {
        if (i + 1 < img.width && at(i, j) != at(i + 1, j)) pairs.push_back({i, j, i + 1, j});
        if (j + 1 < img.height && at(i, j) != at(i, j + 1)) pairs.push_back({i, j, i, j + 1});
      }
  } else {
    // The top pixel of the smallest non-zero region and the pixel above it:
    // there the boundary runs along the pixel row.
    std::map<int, int> count;
    for (uint8_t l : img.labels)
      if (l != 0) ++count[l];
    int label = -1;
    for (const auto& [l, n] : count)
      if (label < 0 || n < count[label]) label = l;
    for (int j = 1; j < img.height && pairs.empty(); ++j)
      for (int i = 0; i < img.width && pairs.empty(); ++i)
        if (at(i, j) == label && at(i, j - 1) != label) pairs.push_back({i, j, i, j - 1});
  }
  if (pairs.empty()) {
    ADD_FAILURE() << c.name << ": the coarse 64x64 map has no boundary to zoom onto";
    return s;
  }
  std::mt19937_64 rng(c.seed);
  const auto p = pairs[std::uniform_int_distribution<std::size_t>(0, pairs.size() - 1)(rng)];
  const Vec2 b = bisect_boundary(setup, centre(p[0], p[1]), centre(p[2], p[3]), c.zoom_width);
  s.options.view = square(b, c.zoom_width);
  s.options.width = s.options.height = c.size;
  return s;
}

// ------------------------------------------------------------------- cases

std::function<Scene()> design(BSpline (*spline)(), RegionRequest o, std::optional<View> view = {}) {
  return [=] {
    RegionRequest oo = o;
    oo.view = view;
    return Scene{spline(), oo};
  };
}

std::vector<Case> cases() {
  std::vector<Case> c;
  auto add = [&](std::string name, std::function<Scene()> base, bool structural, Zoom zoom = Zoom::none,
                 double width = 1e-4, std::uint64_t seed = 0) {
    c.push_back({std::move(name), std::move(base), structural, zoom, width, seed});
  };
  // Structural zeros, default views.
  add("parabola_vertex_quartic_P4", design(parabola_vertex_quartic, opts(4)), true);
  add("parabola_vertex_quartic_P4_cmr", design(parabola_vertex_quartic, opts(4, Mode::cmr)), true);
  add("collinear_start_quartic_P4", design(collinear_start_quartic, opts(4)), true);
  add("collinear_start_quintic_P5", design(collinear_start_quintic, opts(5)), true);
  add("collinear_start_cubic_P3_cmr", design(collinear_start_cubic, opts(3, Mode::cmr)), true);
  add("double_start_cubic_P3", design(double_start_cubic, opts(3)), true);
  add("double_start_cubic_P2", design(double_start_cubic, opts(2)), true);
  add("collinear_clamped_cubic_P4_cmr", design(collinear_clamped_cubic, opts(4, Mode::cmr)), true);
  add("straight_uniform_cubic_P3_cmr", design(straight_uniform_cubic, opts(3, Mode::cmr)), true);
  add("straight_tail_quartic_bspline_P6", design(straight_tail_quartic_bspline, opts(6)), true);
  add("collinear_tail_quartic_bspline_P6", design(collinear_tail_quartic_bspline, opts(6)), true);
  // Exact zeros along a pixel column (an axis at a pixel centre: odd width,
  // view symmetric about it) or row (y = 0).
  add("symmetric_quartic_P2_axis", design(symmetric_quartic, opts(2, Mode::cmrwi, 33), View{-1, 0, 1, 3}), false);
  add("symmetric_arch_P2_split1_axis", design(symmetric_arch, opts(2, Mode::cmrwi, 33, 1), View{-1, 0, 1, 2}), false);
  add("symmetric_arch_P2_split1_axis_cmr", design(symmetric_arch, opts(2, Mode::cmr, 33, 1), View{-1, 0, 1, 2}),
      false);
  add("symmetric_arch_P1_with_P3_split1_axis",
      design(symmetric_arch, opts(1, Mode::cmrwi, 33, 1, {3}), View{-1.75, -0.5, 0.25, 1.5}), false);
  add("straight_cubic_P1_line", design(straight_cubic, opts(1, Mode::cmrwi, 33), View{-1, -2, 3, 2}), false);
  add("straight_cubic_P1_line_cmr", design(straight_cubic, opts(1, Mode::cmr, 33), View{-1, -2, 3, 2}), false);
  // Zoomed boundaries of structural-zero designs.
  add("parabola_vertex_quartic_P4_zoom1e-4_seed1", design(parabola_vertex_quartic, opts(4)), true, Zoom::boundary,
      1e-4, 1);
  add("collinear_start_quartic_P4_zoom1e-4_seed2", design(collinear_start_quartic, opts(4)), true, Zoom::boundary,
      1e-4, 2);
  add("double_start_cubic_P3_zoom1e-4_seed3", design(double_start_cubic, opts(3)), true, Zoom::boundary, 1e-4, 3);
  add("straight_tail_quartic_bspline_P6_zoom1e-4_seed11", design(straight_tail_quartic_bspline, opts(6)), true,
      Zoom::boundary, 1e-4, 11);
  // Zoomed boundaries of generic designs.
  add("spiral_clamped_P0_zoom1e-4_seed4", design(spiral_clamped, opts(0)), false, Zoom::boundary, 1e-4, 4);
  // Point 3's region is a small island round P3 itself: the coarse map looks 0.2 wide round it.
  const auto spiral_p3 = [] {
    Scene s{spiral_clamped(), opts(3)};
    s.options.view = square(s.spline.points()[3], 0.2);
    return s;
  };
  add("spiral_clamped_P3_near_zoom1e-4_seed5", spiral_p3, false, Zoom::boundary, 1e-4, 5);
  add("spiral_clamped_P5_split2_cmr_zoom1e-4_seed6", design(spiral_clamped, opts(5, Mode::cmr, 48, 2)), false,
      Zoom::boundary, 1e-4, 6);
  add("spiral_clamped_P2_with_P3_zoom1e-4_seed7", design(spiral_clamped, opts(2, Mode::cmrwi, 48, {}, {3})), false,
      Zoom::boundary, 1e-4, 7);
  add("spiral_clamped_P0_extreme_zoom1e-4", design(spiral_clamped, opts(0)), false, Zoom::extreme, 1e-4);
  add("spiral_clamped_P3_near_zoom1e-7_seed8", spiral_p3, false, Zoom::boundary, 1e-7, 8);
  add("class_a_quartic_P2_cmr_zoom1e-4_seed9",
      [] { return Scene{test::class_a_bezier(4, -0.3, 1.2), opts(2, Mode::cmr)}; }, false, Zoom::boundary, 1e-4, 9);
  add("class_a_quartic_P2_cmr_extreme_zoom1e-4",
      [] { return Scene{test::class_a_bezier(4, -0.3, 1.2), opts(2, Mode::cmr)}; }, false, Zoom::extreme, 1e-4);
  add("random_quintic_seed73_P3_zoom1e-4_seed10", [] { return Scene{random_quintic_spline(73), opts(3)}; }, false,
      Zoom::boundary, 1e-4, 10);
  // A rational cubic B-spline (examples/rational/nurbs_cubic.json), zoomed onto
  // boundaries of P3's region (cmrwi) and of P5's (cmr).
  const auto nurbs = [](int k, Mode mode, std::optional<View> view) {
    return [=] {
      Scene s{BSpline::make(3, {0, 0, 0, 1, 2, 3, 3, 3},
                            {{0, 0}, {0.33, 0}, {1.27, -0.27}, {3.46, -2.1}, {5.45, -4.7}, {6.57, -6.46}}, "nurbs",
                            {1, 1.03125, 1, 1, 0.96875, 1.0625}),
              opts(k, mode)};
      s.options.view = view;
      return s;
    };
  };
  add("nurbs_cubic_P3_zoom1e-4_seed12", nurbs(3, Mode::cmrwi, View{2.9, -2.6, 4.1, -1.4}), false, Zoom::boundary, 1e-4,
      12);
  add("nurbs_cubic_P5_cmr_zoom1e-4_seed13", nurbs(5, Mode::cmr, std::nullopt), false, Zoom::boundary, 1e-4, 13);
  return c;
}

std::string case_name(const ::testing::TestParamInfo<Case>& p) {
  std::string n = p.param.name;
  for (char& ch : n)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return n;
}

// ------------------------------------------------------------------- tests

struct BackendUnderTest {
  const char* name;
  test::BackendOptions options;
};

std::vector<BackendUnderTest> backends() {
  std::vector<BackendUnderTest> b;
  test::BackendOptions cpu;
  cpu.backend = test::Backend::cpu;
  b.push_back({"cpu", cpu});
  // Both shares of the work on whatever device runs the tests (vk::DeviceShare):
  // the host culling blocks with the device's pixels down to the precomputed
  // pieces, and the device shading every pixel and halving deeper pieces itself.
  for (const vk::DeviceShare share : {vk::DeviceShare::culled, vk::DeviceShare::whole})
    for (const vk::RegionPrecision p : {vk::RegionPrecision::fp64, vk::RegionPrecision::fp32}) {
      test::BackendOptions o;
      o.precision = p;
      o.share = share;
      const bool f64 = p == vk::RegionPrecision::fp64, culled = share == vk::DeviceShare::culled;
      b.push_back({culled ? (f64 ? "vulkan_fp64" : "vulkan_fp32") : (f64 ? "vulkan_fp64_whole" : "vulkan_fp32_whole"), o});
    }
  // The whole share as a cascade: fp32 passes, then fp64 for what they flag.
  test::BackendOptions cascade;
  cascade.share = vk::DeviceShare::whole;
  cascade.cascade = true;
  b.push_back({"vulkan_cascade_whole", cascade});
  return b;
}

std::string describe(const Scene& s) {
  std::ostringstream o;
  o.precision(17);
  const View& v = *s.options.view;
  o << "point " << s.options.point << ", view [" << v.x0 << ", " << v.y0 << ", " << v.x1 << ", " << v.y1 << "], "
    << s.options.width << "x" << s.options.height;
  return o.str();
}

class Certify : public ::testing::TestWithParam<Case> {};

TEST_P(Certify, EveryBackendLabelIsTheExactLabel) {
  const Case& c = GetParam();
  const Scene scene = make_scene(c);
  const RegionProblem setup_problem = RegionProblem::make(scene.spline, scene.options);
  const RegionSetup& setup = setup_problem.setup();
  const RegionRequest& o = setup.options;
  const Scene shown{scene.spline, o};
  std::vector<uint8_t> exact(static_cast<std::size_t>(o.width) * o.height), exact_depth(exact.size());
  std::map<int, int> histogram;
  for (int j = 0; j < o.height; ++j)
    for (int i = 0; i < o.width; ++i) {
      const PixelResult r = classify_position_exact(setup, pixel_center(*o.view, o.width, o.height, i, j));
      exact[static_cast<std::size_t>(j) * o.width + i] = r.label;
      exact_depth[static_cast<std::size_t>(j) * o.width + i] = r.depth;
      ++histogram[r.label];
    }
  std::ostringstream hist;
  for (const auto& [l, n] : histogram) hist << " " << l << ":" << n;
  if (c.zoom != Zoom::none) {
    ASSERT_GE(histogram.size(), 2u) << c.name << " (" << describe(shown)
                                    << "): the zoomed view has one label only:" << hist.str();
  }
  for (const BackendUnderTest& b : backends()) {
    const RegionImage img = test::render(setup_problem, b.options);
    ASSERT_EQ(img.labels.size(), exact.size()) << c.name << " " << b.name;
    int wrong = 0, wrong_depth = 0;
    std::ostringstream first, first_depth;
    for (int j = 0; j < o.height; ++j)
      for (int i = 0; i < o.width; ++i) {
        const std::size_t at = static_cast<std::size_t>(j) * o.width + i;
        if (img.depth[at] != exact_depth[at] && wrong_depth++ < 5)
          first_depth << "\n  pixel (" << i << ", " << j << "): " << b.name << " depth " << int(img.depth[at])
                      << ", exact " << int(exact_depth[at]) << " (label " << int(exact[at]) << ")";
        if (img.labels[at] == exact[at]) continue;
        if (wrong++ < 5) {
          const Vec2 p = pixel_center(*o.view, o.width, o.height, i, j);
          first.precision(17);
          first << "\n  pixel (" << i << ", " << j << ") at (" << p.x << ", " << p.y << "): " << b.name << " says "
                << int(img.labels[at]) << ", exact " << int(exact[at]);
        }
      }
    EXPECT_EQ(wrong, 0) << c.name << " (" << describe(shown) << ") on " << b.name << ": " << wrong
                        << " pixel(s) differ from the exact path; exact labels" << hist.str() << first.str();
    EXPECT_EQ(wrong_depth, 0) << c.name << " (" << describe(shown) << ") on " << b.name << ": " << wrong_depth
                              << " pixel(s) have another decision level than the exact path" << first_depth.str();
  }
  // Label maps without a depth map (what `cmr region` computes unless asked
  // for --depth-map) may decide blocks by a label-only proof: same labels.
  RegionRequest labels_only = scene.options;
  labels_only.depth = false;
  const RegionProblem label_problem = RegionProblem::make(scene.spline, labels_only);
  for (const BackendUnderTest& b : backends()) {
    const RegionImage img = test::render(label_problem, b.options);
    int wrong = 0;
    std::ostringstream first;
    for (std::size_t at = 0; at < exact.size(); ++at)
      if (img.labels[at] != exact[at] && wrong++ < 5)
        first << "\n  pixel (" << at % o.width << ", " << at / o.width << "): " << b.name << " says "
              << int(img.labels[at]) << ", exact " << int(exact[at]);
    EXPECT_EQ(wrong, 0) << c.name << " (" << describe(shown) << ") labels only, on " << b.name << ": " << wrong
                        << " pixel(s) differ from the exact path" << first.str();
  }
}

// The structural zero is really there: some coefficient of the unsubdivided
// xi (or, in CMR mode, nu) is the zero polynomial in (dx, dy). The host's
// rounded coefficients are all zero exactly when the rational ones are.
std::vector<std::string> structural_zeros(const RegionSetup& s) {
  std::vector<std::string> found;
  for (const RegionEntry& e : s.entries) {
    if (!e.classify) continue;
    for (int k = 0; k < e.n_xi; ++k)
      if (std::all_of(e.xi[k].begin(), e.xi[k].end(), [](double v) { return v == 0; }))
        found.push_back("segment " + std::to_string(e.segment) + " xi_" + std::to_string(k));
    if (s.options.mode != Mode::cmr) continue;
    for (int k = 0; k < e.n_nu; ++k)
      if (std::all_of(e.nu[k].begin(), e.nu[k].end(), [](double v) { return v == 0; }))
        found.push_back("segment " + std::to_string(e.segment) + " nu_" + std::to_string(k));
  }
  return found;
}

class CertifyStructuralZeros : public ::testing::TestWithParam<Case> {};

TEST_P(CertifyStructuralZeros, FewPixelsTakeTheExactPath) {
  // Requirement: a coefficient that is zero for every pixel is known on the
  // host once, so it must not send every pixel to the exact path.
  constexpr double kMaxExactShare = 0.05;
  const Case& c = GetParam();
  const Scene scene = make_scene(c);
  const RegionProblem setup_problem = RegionProblem::make(scene.spline, scene.options);
  const RegionSetup& setup = setup_problem.setup();
  const std::vector<std::string> zeros = structural_zeros(setup);
  ASSERT_FALSE(zeros.empty()) << c.name << ": no coefficient is zero for every position";
  std::string list;
  for (const std::string& z : zeros) list += (list.empty() ? "" : ", ") + z;
  test::BackendOptions cpu;
  cpu.backend = test::Backend::cpu;
  const RegionImage img = test::render(setup_problem, cpu);
  const double share = static_cast<double>(img.exact_pixels) / static_cast<double>(img.labels.size());
  EXPECT_LE(share, kMaxExactShare) << c.name << " (" << describe({scene.spline, setup.options}) << "): "
                                   << img.exact_pixels << " of " << img.labels.size()
                                   << " pixels took the exact path; zero for every position: " << list;
}

std::vector<Case> structural_cases() {
  std::vector<Case> s;
  for (const Case& c : cases())
    if (c.structural) s.push_back(c);
  return s;
}

// The cascade's fp64 pass is not idle: over the boundary zooms the fp32
// passes flag pixels, and the fp64 pass decides most of them, so that the
// host decides fewer than fp32 alone would leave it (labels: Certify.*).
TEST(CertifyCascade, TheFp64PassDecidesMostOfWhatTheFp32PassesFlag) {
  vk::VulkanRegionOptions o;
  o.share = vk::DeviceShare::whole;
  o.cascade = true;
  auto b = vk::VulkanRegionBackend::create(o);
  ASSERT_TRUE(b) << b.error().message;
  if (!b.value().device().float64) GTEST_SKIP() << "no shaderFloat64: the cascade is fp32 alone";
  std::size_t second = 0, flagged = 0;
  for (const Case& c : cases()) {
    if (c.zoom == Zoom::none) continue;
    const Scene scene = make_scene(c);
    (void)b.value().render(RegionProblem::make(scene.spline, scene.options));
    second += b.value().last_whole_frame().second;
    flagged += b.value().last_whole_frame().flagged;
  }
  EXPECT_GT(second, 0u) << "the fp32 passes flagged no pixel: the fp64 pass was not exercised";
  EXPECT_LT(2 * flagged, second) << "of " << second << " pixels the fp32 passes flagged, the fp64 pass left "
                                 << flagged << " to the host";
}

// The tests above can see a bound that is too small: with the shader's
// polynomial error bound divided by 2^24 (about what fp32 would claim if its
// rounding were ignored), the device, shading every pixel of the boundary
// zooms in fp32, certifies signs that are wrong, and some label differs from
// the exact path's. With the true bound none does (Certify.*).
TEST(CertifyBound, AWeakenedFp32BoundGivesLabelsTheExactPathRefutes) {
  vk::VulkanRegionOptions o;
  o.precision = vk::RegionPrecision::fp32;
  o.share = vk::DeviceShare::whole;
  o.weaken_bound_bits = 24;
  auto weakened = vk::VulkanRegionBackend::create(o);
  ASSERT_TRUE(weakened) << weakened.error().message;
  int wrong = 0, zooms = 0;
  for (const Case& c : cases()) {
    if (c.zoom == Zoom::none || wrong > 0) continue;  // one refuted zoom is enough
    ++zooms;
    const Scene scene = make_scene(c);
    const RegionProblem problem = RegionProblem::make(scene.spline, scene.options);
    const RegionSetup& setup = problem.setup();
    const RegionRequest& r = setup.options;
    const std::vector<uint8_t> labels = weakened.value().render(problem).codes();
    for (int j = 0; j < r.height; ++j)
      for (int i = 0; i < r.width; ++i)
        wrong += labels[static_cast<std::size_t>(j) * r.width + i] !=
                 classify_position_exact(setup, pixel_center(*r.view, r.width, r.height, i, j)).label;
  }
  EXPECT_GT(zooms, 0);
  EXPECT_GT(wrong, 0) << "a bound 2^24 times too small went unnoticed on " << zooms << " boundary zooms";
  std::printf("a bound 2^24 times too small: %d wrong labels on the first %d boundary zoom(s)\n", wrong, zooms);
}

INSTANTIATE_TEST_SUITE_P(Scenes, Certify, ::testing::ValuesIn(cases()), case_name);
INSTANTIATE_TEST_SUITE_P(Scenes, CertifyStructuralZeros, ::testing::ValuesIn(structural_cases()), case_name);

}  // namespace
}  // namespace cmr
