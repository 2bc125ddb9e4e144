// The Vulkan and CPU region backends give identical label maps (both are
// certified: every pixel the device cannot certify is recomputed exactly on
// the host), and the CPU labels are what `analyze` says of the moved spline.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "bezierize/analyze.hpp"
#include "region/region.hpp"
#include "tests/test_util.hpp"
#include "tests/vk/render_util.hpp"

namespace cmr {
namespace {

using namespace cmr::backend;

struct Scene {
  const char* name;
  BSpline spline;
  RegionRequest options;
};

BSpline random_spline(std::mt19937_64& rng, int degree, std::vector<double> knots) {
  const int m = static_cast<int>(knots.size()) - degree + 1;
  return BSpline::make(degree, std::move(knots), test::random_points(rng, m, 2.0));
}

RegionRequest opts(int point, Mode mode = Mode::cmrwi, std::optional<int> split = {}, std::vector<int> with = {}) {
  RegionRequest o;
  o.point = point;
  o.mode = mode;
  o.split = split;
  o.with = std::move(with);
  o.width = 48;
  o.height = 40;
  return o;
}

// Segment control: only `range` judged, and/or several cut joints; the view
// centred on the moved point so that both labels appear.
RegionRequest seg_opts(const BSpline& s, int point, std::optional<SegmentRange> range, std::optional<int> split,
                       std::vector<int> splits, Mode mode = Mode::cmrwi, double half = 0.5) {
  RegionRequest o = opts(point, mode, split);
  o.segments = range;
  o.splits = std::move(splits);
  const Vec2 c = s.points()[point];
  o.view = View{c.x - half, c.y - 0.8 * half, c.x + half, c.y + 0.8 * half};
  return o;
}

// Curvature increases on segments 0-1, decreases on 2, increases on 3
// (tests/bezierize/segments_test.cpp checks it by sampling).
BSpline wave(std::vector<double> knots = {0, 1, 2, 3, 4, 5, 6, 7, 8}) {
  return BSpline::make(3, std::move(knots),
                       {{0.058, 0.128}, {1.274, 0.936}, {2.065, -0.298}, {3.236, -0.998}, {3.765, 0.132},
                        {5.069, -0.719}, {6.078, 0.783}});
}

// Fig. 10's curve (examples/figures/fig10a.json) with knot 1 inserted once
// more (cmr knots insert 1): a maximum at joint 2, a C1 joint 1.
BSpline fig10_double_knot() {
  return BSpline::make(3, {0, 0, 0, 1, 1, 2, 3, 3, 3},
                       {{0, 0}, {0.33, 0}, {0.8, -0.135}, {2, -0.88}, {3.46, -2.1}, {5.45, -4.7}, {5.4, -5.8}});
}

std::vector<Scene> scenes() {
  std::mt19937_64 rng(71);
  const BSpline spiral = test::polynomial_as_bspline(test::class_a_bezier(3, -0.35, 1.25), {0, 1, 2, 3, 4, 5, 6, 7});
  const BSpline clamped = test::polynomial_as_bspline(test::class_a_bezier(3, -0.35, 1.25), {0, 0, 0, 1, 2, 3, 3, 3});
  std::vector<Scene> s = {
      {"uniform_cubic_P2", spiral, opts(2)},
      {"uniform_cubic_P3_cmr", spiral, opts(3, Mode::cmr)},
      {"clamped_cubic_P0", clamped, opts(0)},
      {"clamped_cubic_split2_P5", clamped, opts(5, Mode::cmr, 2)},
      {"clamped_rigid_P2_with_P3", clamped, opts(2, Mode::cmrwi, {}, {3})},
      {"bezier_quadratic", BSpline::bezier({{0, 0}, {1, 1}, {2, 0.2}}), opts(1)},
      {"bezier_quartic_cmr", test::class_a_bezier(4, -0.3, 1.2), opts(2, Mode::cmr)},
      {"bezier_degree9", test::class_a_bezier(9, -0.15, 1.08), opts(4)},
      {"nonuniform_quintic", random_spline(rng, 5, {0, 0.5, 1, 2.5, 3, 4, 4, 6, 7, 9}), opts(3)},
      {"quadratic_C1_joints", random_spline(rng, 2, {0, 1, 2, 3, 4, 5}), opts(2)},
      {"double_knot_cubic", random_spline(rng, 3, {0, 0, 0, 1.5, 1.5, 3, 3, 3}), opts(3)},
      {"wave_splits_2_3_P3", wave(), seg_opts(wave(), 3, {}, {}, {2, 3})},
      {"wave_segments_1_3_splits_2_3_P4", wave(), seg_opts(wave(), 4, SegmentRange{1, 3}, {}, {2, 3})},
      {"wave_segments_2_2_P3", wave(), seg_opts(wave(), 3, SegmentRange{2, 2}, {}, {})},
      {"wave_segments_1_2_split2_P2", wave(), seg_opts(wave(), 2, SegmentRange{1, 2}, 2, {})},
      {"wave_segments_1_1_P2_cmr", wave(), seg_opts(wave(), 2, SegmentRange{1, 1}, {}, {}, Mode::cmr)},
      // Fig. 10's curve with a double knot: joint 1 is C1, its jump varies
      // inside group 0 (and inside the range 0..1).
      {"fig10_double_knot_splits_2_P3", fig10_double_knot(), seg_opts(fig10_double_knot(), 3, {}, {}, {2}, Mode::cmrwi, 1.0)},
      {"fig10_double_knot_segments_0_1_P4", fig10_double_knot(), seg_opts(fig10_double_knot(), 4, SegmentRange{0, 1}, {}, {})},
  };
  // Each piece on its own (RegionRequest::each_piece): every joint a cut, or
  // chosen joints (a varying C1 jump inside group 0).
  const auto each = [](RegionRequest o, std::vector<int> cuts = {}) {
    o.each_piece = true;
    o.splits = std::move(cuts);
    return o;
  };
  s.push_back({"wave_each_piece_P3", wave(), each(seg_opts(wave(), 3, {}, {}, {}, Mode::cmrwi, 1.0))});
  s.push_back({"wave_each_piece_P4_cmrwi_2_3", wave(), each(seg_opts(wave(), 4, {}, {}, {}, Mode::cmrwi, 1.0), {2, 3})});
  s.push_back({"fig10_double_knot_each_piece_2_P3", fig10_double_knot(),
               each(seg_opts(fig10_double_knot(), 3, {}, {}, {}, Mode::cmrwi, 1.0), {2})});
  // Rational splines (weights fixed while the point moves): Fig. 9's polygon
  // with weights, seen around P3, on C2 knots and split at a C1 joint; and a
  // quadratic with C1 joints whose jumps vary (decided on the host).
  const std::vector<Vec2> fig9 = {{0, 0}, {0.33, 0}, {1.27, -0.27}, {3.46, -2.1}, {5.45, -4.7}, {6.57, -6.46}};
  const std::vector<double> w9 = {1, 1.03125, 1, 1, 0.96875, 1.0625};
  RegionRequest near_p3 = opts(3);
  near_p3.view = View{2.9, -2.6, 4.1, -1.4};
  RegionRequest near_p3_split = opts(3, Mode::cmr, 1);
  near_p3_split.view = near_p3.view;
  std::uniform_real_distribution<double> weight(0.5, 2);
  std::vector<double> wq;
  for (int i = 0; i < 5; ++i) wq.push_back(weight(rng));
  s.push_back({"rational_cubic_P3", BSpline::make(3, {0, 0, 0, 1, 2, 3, 3, 3}, fig9, "", w9), near_p3});
  s.push_back({"rational_cubic_C1_split1_P3_cmr", BSpline::make(3, {0, 0, 0, 1, 1, 2, 2, 2}, fig9, "", w9), near_p3_split});
  s.push_back({"rational_quadratic_C1_joints",
               BSpline::make(2, {0, 1, 2, 3, 4, 5}, random_spline(rng, 2, {0, 1, 2, 3, 4, 5}).points(), "", wq), opts(2)});
  // Poles (W = 0, spline/bspline.hpp): W(3) = 0 at the joint of segments 0
  // and 1; judged, every pixel is 0; outside the judged segment 2 it does not
  // matter. And W < 0 on every span (weights of mixed sign, no pole).
  const std::vector<Vec2> wave6 = {{0, 0}, {1, 1.2}, {2.2, 1.4}, {3.1, 0.3}, {4.4, -0.6}, {5.5, 0.2}};
  const BSpline knot_pole = BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7}, wave6, "", {1, 1, -0.5, 1, 1, 1});
  const BSpline negative_w = BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7}, wave6, "", {1, -1, -1, -1.5, -1, -1.25});
  s.push_back({"pole_judged_P3", knot_pole, opts(3)});
  s.push_back({"pole_outside_segments_2_2_P4", knot_pole, seg_opts(knot_pole, 4, SegmentRange{2, 2}, {}, {}, Mode::cmrwi, 1.0)});
  // Bezier weights 0.4, -0.2, 0.4 in the first span (W > 0, no pole) and a C1
  // joint: end_terms' division-free form on the host. (That span is the
  // complementary arc of a conic, never monotone: every label is 0 here, and
  // the scene checks that the backends and analyze agree on it.)
  const BSpline mixed = BSpline::make(2, {0, 1, 2, 3, 4}, {{0, 0}, {1, 1}, {2, -0.5}, {3, 0.5}}, "", {1, -0.2, 1, 1});
  s.push_back({"mixed_weights_quadratic_C1_P2", mixed, opts(2)});
  s.push_back({"negative_w_segments_1_1_P2_cmr", negative_w, seg_opts(negative_w, 2, SegmentRange{1, 1}, {}, {}, Mode::cmr, 1.0)});
  // Closed splines: the moved point's repeated copy moves too, and the seam
  // (segment N-1 against segment 0) is judged like every joint; P0 has a copy,
  // and the quadratic's C1 seam jump varies with it; the cubic has a double knot.
  const std::vector<Vec2> loop = {{1, 0}, {0.4, 0.9}, {-0.6, 0.8}, {-1.1, -0.1}, {-0.3, -1}, {0.7, -0.8}};
  RegionRequest near_p0 = opts(0);
  near_p0.view = View{0.4, -0.6, 1.6, 0.6};
  s.push_back({"closed_quadratic_P0", BSpline::make_closed(2, {0, 1, 2, 3, 4, 5, 6}, loop), near_p0});
  s.push_back({"closed_cubic_double_knot_P0_cmr", BSpline::make_closed(3, {0, 1, 2, 2, 3, 4, 5}, loop),
               [&] {
                 RegionRequest o = near_p0;
                 o.mode = Mode::cmr;
                 return o;
               }()});
  return s;
}

// DeviceShare::automatic: the host culls on a CPU device (lavapipe), the
// device shades every pixel on a GPU; an explicit share is kept.
TEST(RegionBackends, TheShareOfTheWorkFollowsTheDeviceType) {
  auto b = vk::VulkanRegionBackend::create({});
  ASSERT_TRUE(b) << b.error().message;
  const bool cpu_device = b.value().device().type == VK_PHYSICAL_DEVICE_TYPE_CPU;
  EXPECT_EQ(b.value().share(), cpu_device ? vk::DeviceShare::culled : vk::DeviceShare::whole);
  for (const vk::DeviceShare share : {vk::DeviceShare::culled, vk::DeviceShare::whole}) {
    vk::VulkanRegionOptions o;
    o.share = share;
    auto fixed = vk::VulkanRegionBackend::create(o);
    ASSERT_TRUE(fixed) << fixed.error().message;
    EXPECT_EQ(fixed.value().share(), share);
  }
}

// A frame split into several runs gives the labels and depths of one run,
// on both shares: culled, runs of at most pixels_per_run listed pixels (odd
// sizes, so that runs end inside rows and words); whole, runs of whole tile
// rows (one each here: 37 pixels are fewer than a tile row holds).
TEST(RegionBackends, AFrameSplitIntoRunsIsTheWholeFrame) {
  for (const Scene& sc : scenes()) {
    const RegionProblem problem = RegionProblem::make(sc.spline, sc.options);
    const RegionImage cpu = test::render(problem, {test::Backend::cpu});
    for (const vk::DeviceShare share : {vk::DeviceShare::culled, vk::DeviceShare::whole}) {
      vk::VulkanRegionOptions o;
      o.share = share;
      o.pixels_per_run = 37;
      auto b = vk::VulkanRegionBackend::create(o);
      ASSERT_TRUE(b) << b.error().message;
      const RegionResult r = b.value().render(problem);
      const std::string where = std::string(sc.name) + (share == vk::DeviceShare::whole ? " whole" : " culled");
      EXPECT_EQ(r.codes(), cpu.labels.codes()) << where;
      EXPECT_EQ(r.depth, cpu.depth) << where;
    }
  }
}

// DeviceShare::whole: without a depth map the tile pass proves whole tiles
// (8 x 8 pixels) over their boxes, and only the tiles it queues reach the
// pixel pass; with one it proves none (pixels of a tile may decide at
// different depths). Either way labels (and depths) are the CPU backend's,
// fp64 and fp32.
TEST(RegionBackends, TheDeviceProvesWholeTilesOfALabelMap) {
  for (const vk::RegionPrecision prec : {vk::RegionPrecision::fp64, vk::RegionPrecision::fp32}) {
    vk::VulkanRegionOptions o;
    o.share = vk::DeviceShare::whole;
    o.precision = prec;
    auto b = vk::VulkanRegionBackend::create(o);
    ASSERT_TRUE(b) << b.error().message;
    std::size_t tiles = 0, queued = 0;
    for (const Scene& sc : scenes()) {
      const std::string where = std::string(sc.name) + (prec == vk::RegionPrecision::fp32 ? " fp32" : " fp64");
      const std::size_t want_tiles =
          static_cast<std::size_t>((sc.options.width + 7) / 8) * static_cast<std::size_t>((sc.options.height + 7) / 8);
      RegionRequest labels_only = sc.options;
      labels_only.depth = false;
      const RegionProblem problem = RegionProblem::make(sc.spline, labels_only);
      EXPECT_EQ(b.value().render(problem).codes(), test::render(problem, {test::Backend::cpu}).labels.codes()) << where;
      const vk::VulkanRegionBackend::WholeFrame f = b.value().last_whole_frame();
      EXPECT_EQ(f.tiles, want_tiles) << where;
      tiles += f.tiles;
      queued += f.tiles_queued;
      const RegionProblem with_depth = RegionProblem::make(sc.spline, sc.options);
      const RegionResult r = b.value().render(with_depth);
      const RegionImage cpu = test::render(with_depth, {test::Backend::cpu});
      EXPECT_EQ(r.codes(), cpu.labels.codes()) << where << " with depths";
      EXPECT_EQ(r.depth, cpu.depth) << where;
      EXPECT_EQ(b.value().last_whole_frame().tiles_queued, want_tiles) << where << ": a tile proven with depths";
    }
    // The scenes are small views near region boundaries: over 40% proven.
    EXPECT_LT(queued, tiles * 6 / 10) << "the tile pass proved " << tiles - queued << " of " << tiles << " tiles";
    // A whole region at 256 x 256: most tiles lie inside or outside it.
    RegionRequest whole = opts(1);
    whole.width = whole.height = 256;
    whole.depth = false;
    const RegionProblem problem = RegionProblem::make(BSpline::bezier({{0, 0}, {1, 1}, {2, 0.2}}), whole);
    EXPECT_EQ(b.value().render(problem).codes(), test::render(problem, {test::Backend::cpu}).labels.codes());
    const vk::VulkanRegionBackend::WholeFrame f = b.value().last_whole_frame();
    EXPECT_LT(f.tiles_queued, f.tiles / 4) << "the tile pass proved " << f.tiles - f.tiles_queued << " of " << f.tiles;
  }
}

// An injected fault surfaces as its Vulkan error on both shares (the chain of
// the whole share included), so that make_region_backend's fallback (one
// note, the CPU's answer: backend_choice_test's Fault.*) sees it on a GPU as
// on lavapipe.
TEST(RegionBackends, AnInjectedFaultIsTheRendersErrorOnBothShares) {
  const std::vector<Scene> all = scenes();
  const RegionProblem problem = RegionProblem::make(all.front().spline, all.front().options);
  const std::pair<vk::InjectedFault, vk::Errc> faults[] = {{vk::InjectedFault::device_lost, vk::Errc::device_lost},
                                                           {vk::InjectedFault::out_of_memory, vk::Errc::out_of_memory},
                                                           {vk::InjectedFault::pipeline_rejected, vk::Errc::shader_invalid}};
  for (const vk::DeviceShare share : {vk::DeviceShare::culled, vk::DeviceShare::whole})
    for (const bool cascade : {false, true})
      for (const auto& [fault, code] : faults) {
        vk::VulkanRegionOptions o;
        o.share = share;
        o.cascade = cascade;
        o.fault = fault;
        auto b = vk::VulkanRegionBackend::create(o);
        ASSERT_TRUE(b) << b.error().message;
        auto r = b.value().try_render(problem);
        ASSERT_FALSE(r) << "share " << int(share) << " fault " << int(fault);
        EXPECT_EQ(r.error().code, code) << r.error().message;
        EXPECT_EQ(r.error().message.find('\n'), std::string::npos) << r.error().message;
      }
}

// Pixels the device flags for the host beyond the run's list are found in
// the label map: the same labels and depths as with the whole list.
TEST(RegionBackends, FlaggedPixelsBeyondTheListAreFoundInTheLabelMap) {
  const std::vector<Scene> all = scenes();
  const auto sc = std::find_if(all.begin(), all.end(), [](const Scene& s) {
    return std::string(s.name) == "mixed_weights_quadratic_C1_P2";  // its joints' jumps are the host's
  });
  ASSERT_NE(sc, all.end());
  const RegionProblem problem = RegionProblem::make(sc->spline, sc->options);
  const RegionImage cpu = test::render(problem, {test::Backend::cpu});
  for (const std::size_t listed : {std::size_t{0}, std::size_t{4}}) {
    vk::VulkanRegionOptions o;
    o.share = vk::DeviceShare::whole;
    o.flagged_per_run = listed;
    auto b = vk::VulkanRegionBackend::create(o);
    ASSERT_TRUE(b) << b.error().message;
    const RegionResult r = b.value().render(problem);
    EXPECT_GT(b.value().last_whole_frame().flagged, 4u);
    EXPECT_EQ(r.codes(), cpu.labels.codes()) << "list of " << listed;
    EXPECT_EQ(r.depth, cpu.depth) << "list of " << listed;
  }
}

TEST(RegionBackends, VulkanAndCpuLabelMapsAreIdentical) {
  for (const Scene& sc : scenes()) {
    const RegionProblem setup_problem = RegionProblem::make(sc.spline, sc.options);
  const RegionSetup& setup = setup_problem.setup();
    const RegionImage cpu = test::render(setup_problem, {test::Backend::cpu});
    for (vk::RegionPrecision prec : {vk::RegionPrecision::fp64, vk::RegionPrecision::fp32}) {
      test::BackendOptions bo;
      bo.precision = prec;
      bo.share = vk::DeviceShare::whole;  // the device shades every pixel, so the shader is what is compared
      const RegionImage gpu = test::render(setup_problem, bo);
      ASSERT_EQ(gpu.labels.size(), cpu.labels.size()) << sc.name;
      for (std::size_t at = 0; at < cpu.labels.size(); ++at) {
        ASSERT_EQ(int(gpu.labels[at]), int(cpu.labels[at]))
            << sc.name << (prec == vk::RegionPrecision::fp32 ? " fp32" : " fp64") << " pixel (" << at % sc.options.width
            << ", " << at / sc.options.width << ")";
        ASSERT_EQ(int(gpu.depth[at]), int(cpu.depth[at])) << sc.name << " depth at pixel " << at;
      }
    }
  }
}

// Coordinates scaled by 2^+-300 (points and view): the host hands the device
// the problem scaled back near 1 (RegionSetup::scale_exponent), so each
// open scene's labels and depths on the device, fp64 and fp32, are those of
// the unscaled scene on the CPU, and the device leaves the host no more
// pixels to decide exactly than unscaled (before, it left all of them).
TEST(RegionBackends, VulkanLabelsDoNotDependOnTheScale) {
  for (const Scene& sc : scenes()) {
    if (sc.spline.closed()) continue;
    const RegionProblem plain = RegionProblem::make(sc.spline, sc.options);
    const RegionImage cpu = test::render(plain, {test::Backend::cpu});
    for (const int e : {300, -300}) {
      BSpline big = sc.spline;
      for (int k = 0; k < big.point_count(); ++k)
        big = big.with_point(k, {std::ldexp(big.points()[k].x, e), std::ldexp(big.points()[k].y, e)});
      RegionRequest o = sc.options;
      const View& v = plain.view();
      o.view = View{std::ldexp(v.x0, e), std::ldexp(v.y0, e), std::ldexp(v.x1, e), std::ldexp(v.y1, e)};
      const RegionProblem scaled = RegionProblem::make(big, o);
      for (vk::RegionPrecision prec : {vk::RegionPrecision::fp64, vk::RegionPrecision::fp32}) {
        test::BackendOptions bo;
        bo.precision = prec;
        bo.share = vk::DeviceShare::whole;  // the device shades every pixel
        const std::string where = std::string(sc.name) + " at 2^" + std::to_string(e) +
                                  (prec == vk::RegionPrecision::fp32 ? " fp32" : " fp64");
        const RegionImage want = test::render(plain, bo);
        const RegionImage gpu = test::render(scaled, bo);
        EXPECT_EQ(gpu.labels, cpu.labels) << where;
        EXPECT_EQ(gpu.depth, cpu.depth) << where;
        EXPECT_EQ(gpu.exact_pixels, want.exact_pixels) << where;
      }
    }
  }
}

TEST(RegionBackends, BlockCullingGivesThePixelwiseLabels) {
  // The backends decide blocks over intervals of displacements; every pixel
  // must still get what classify_position gives it alone. With a depth map the
  // decision levels must match too; without one, blocks may be labelled by a
  // label-only proof, and every depth reads 0.
  for (const bool depth : {true, false}) {
    for (const Scene& sc : scenes()) {
      RegionRequest o = sc.options;
      o.width = 96;
      o.height = 80;
      o.depth = depth;
      const RegionProblem setup_problem = RegionProblem::make(sc.spline, o);
  const RegionSetup& setup = setup_problem.setup();
      const RegionImage img = region_cpu(setup);
      const RegionImage gpu = test::render(setup_problem, {});
      const std::string where = std::string(sc.name) + (depth ? " (depth map)" : " (labels only)");
      for (int j = 0; j < o.height; ++j)
        for (int i = 0; i < o.width; ++i) {
          const std::size_t at = static_cast<std::size_t>(j) * o.width + i;
          const PixelResult r = classify_position(setup, pixel_center(img.view, o.width, o.height, i, j));
          ASSERT_EQ(int(img.labels[at]), int(r.label)) << where << " pixel (" << i << ", " << j << ")";
          ASSERT_EQ(int(gpu.labels[at]), int(r.label)) << where << " vulkan pixel (" << i << ", " << j << ")";
          ASSERT_EQ(int(img.depth[at]), depth ? int(r.depth) : 0) << where << " pixel (" << i << ", " << j << ")";
        }
    }
  }
}

TEST(RegionBackends, CpuLabelsMatchAnalyzeOfTheMovedSpline) {
  std::mt19937_64 rng(72);
  for (const Scene& sc : scenes()) {
    const RegionProblem setup_problem = RegionProblem::make(sc.spline, sc.options);
  const RegionSetup& setup = setup_problem.setup();
    const RegionImage img = region_cpu(setup);
    std::uniform_int_distribution<int> ui(0, sc.options.width - 1), uj(0, sc.options.height - 1);
    for (int sample = 0; sample < 40; ++sample) {
      const int i = ui(rng), j = uj(rng);
      const Vec2 p = pixel_center(img.view, img.width, img.height, i, j);
      // The moved spline (with_point also moves a closed spline's repeated copies).
      const Vec2 delta = p - sc.spline.points()[sc.options.point];
      BSpline moved = sc.spline;
      for (int g : sc.options.with) moved = moved.with_point(g, sc.spline.points()[g] + delta);
      moved = moved.with_point(sc.options.point, p);
      AnalyzeOptions ao;
      ao.split = sc.options.split;
      ao.splits = sc.options.splits;
      ao.segments = sc.options.segments;
      ao.split_mode = sc.options.mode;
      const SplineAnalysis a = analyze(moved, ao);
      const uint8_t want = sc.options.each_piece ? region_label_code(analyze(moved, region_analyze_options(sc.options)), sc.options)
                           : !sc.options.splits.empty() ? code(*a.alternation)
                           : sc.options.split        ? code(*a.split)
                                                     : code(sc.options.mode == Mode::cmr ? a.cmr_algorithm2 : a.cmrwi);
      EXPECT_EQ(int(img.labels[j * img.width + i]), int(want)) << sc.name << " pixel (" << i << ", " << j << ")";
    }
  }
}

TEST(RegionBackends, ScenesHaveBothLabelsSomewhere) {
  // Guards the equality tests against trivial all-zero scenes.
  int scenes_with_regions = 0;
  for (const Scene& sc : scenes()) {
    const RegionImage img = region_cpu(prepare_region(sc.spline, sc.options));
    bool some = false;
    for (uint8_t l : img.labels) some = some || (l != 0);
    scenes_with_regions += some;
  }
  EXPECT_GE(scenes_with_regions, 6);
}

TEST(RegionBackends, SegmentControlScenesHavePassingAndFailingPixels) {
  // The segment-control scenes compare something: each has pixels that pass
  // (a non-zero label that is not "undecided") and pixels that fail.
  for (const Scene& sc : scenes()) {
    if (!sc.options.segments && sc.options.splits.empty() && !sc.options.each_piece) continue;
    const RegionSetup setup = prepare_region(sc.spline, sc.options);
    if (std::string(sc.name).find("double_knot") != std::string::npos)
      EXPECT_FALSE(setup.varying.empty()) << sc.name << ": a joint whose jump varies is what this scene checks";
    const RegionImage img = region_cpu(setup);
    const uint8_t undecided = sc.options.each_piece       ? code(EachPiece::undecided)
                              : !sc.options.splits.empty() ? code(Alternation::undecided)
                              : sc.options.split        ? code(Split::undecided)
                                                        : code(Direction::undecided);
    int pass = 0, fail = 0;
    for (uint8_t l : img.labels) {
      pass += l != 0 && l != undecided;
      fail += l == 0;
    }
    EXPECT_GT(pass, 0) << sc.name;
    EXPECT_GT(fail, 0) << sc.name;
  }
}

}  // namespace
}  // namespace cmr
