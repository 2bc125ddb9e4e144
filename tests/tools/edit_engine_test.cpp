// The editor's engine doorway without a window: the region cache (keys that
// ignore exactly what a region does not depend on), the coarse region while
// dragging and the full one after, knot operations and their refusals. Labels
// are checked against RegionProblem::classify at pixel centres (the
// engine's own single-position answer, independent of the block renderer
// and of the cache).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "bezierize/analyze.hpp"
#include "bezierize/knot_ops.hpp"
#include "region/region_reason.hpp"
#include "spline/curvature.hpp"
#include "spline/errors.hpp"
#include "tools/edit/editor.hpp"
#include "tools/field_flags.hpp"
#include "region/weight_region.hpp"
#include "vk/presenter.hpp"

namespace {

using namespace cmr;
using namespace cmr::edit;

// The Fig. 8 spline (examples/figures/fig8.json): a cubic with three segments
// whose points have monotone regions.
BSpline spline6() {
  return BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7},
                       {{1.3, -1.43}, {1.05, -0.06}, {2.15, -1.31}, {1.97, -3.83}, {-2.23, -6.95}, {-6.78, -9.78}});
}

constexpr int kW = 96, kH = 72;

Editor small_editor(BSpline s) {
  Editor e(std::move(s), "t.json", kW, kH);
  e.show_ui = false;  // the canvas is the whole window
  e.fit_view();
  return e;
}

/// Every pixel of a layer against classify at its centre.
void expect_layer_is_classify(const BSpline& s, const RegionRequest& r, const RegionResult& layer) {
  const RegionProblem p = RegionProblem::make(s, r);
  ASSERT_EQ(layer.width, r.width);
  ASSERT_EQ(layer.height, r.height);
  int wrong = 0;
  for (int j = 0; j < r.height; ++j)
    for (int i = 0; i < r.width; ++i) {
      const RegionPixel want = p.classify(pixel_center(*r.view, r.width, r.height, i, j));
      const std::size_t at = static_cast<std::size_t>(j) * r.width + i;
      const uint8_t code_wanted = r.split ? code(want.split_label) : code(want.label);
      if (layer.code_at(at) != code_wanted && ++wrong <= 3) ADD_FAILURE() << "pixel " << i << "," << j;
    }
  EXPECT_EQ(wrong, 0);
}

int count_label(const RegionResult& r, Direction l) { return static_cast<int>(std::count(r.labels.begin(), r.labels.end(), l)); }

// Weights shape every region of a rational spline: a weight change (the
// moved point's own included) gives another key; the same weights the same key.
TEST(EditEngine, RegionKeyHoldsTheWeights) {
  const BSpline s = spline6();
  RegionRequest r;
  r.point = 2;
  r.view = View{-1, -2, 6, 3};
  const auto key = region_key(s, r);
  const BSpline heavy = with_weight(s, 4, 1.5);
  EXPECT_NE(region_key(heavy, r), key);
  EXPECT_NE(region_key(with_weight(s, 2, 1.5), r), key) << "the moved point's weight counts";
  EXPECT_EQ(region_key(with_weight(s, 4, 1.5), r), region_key(heavy, r));
  EXPECT_NE(region_key(with_weight(heavy, 4, 1.25), r), region_key(heavy, r));
  EXPECT_EQ(region_key(with_weight(heavy, 4, 1.0), r), key) << "weights all 1 are the polynomial spline";
}

// The panel's region of the selected weight: off by default; on, it answers
// [w/4, 4w] of the selected point's weight in the view's labels, every
// interval's ends carry its label (the certified label of the spline with
// that weight), and a weight or mode change recomputes it.
TEST(EditEngine, WeightRegionViewFollowsTheSelectedWeight) {
  Editor e = small_editor(spline6());
  EXPECT_EQ(e.weight_region_view(), nullptr) << "off by default";
  e.show_weight_region = true;
  e.select(2);
  const auto check = [&](const WeightRegion* r, const WeightRegionRequest& q) {
    ASSERT_NE(r, nullptr);
    EXPECT_EQ(q.point, 2);
    EXPECT_EQ(q.labels.mode, e.doc().mode);
    EXPECT_EQ(r->intervals.front().from, q.from);
    EXPECT_EQ(r->intervals.back().to, q.to);
    for (const WeightInterval& iv : r->intervals)
      for (const double w : {iv.from, iv.to}) EXPECT_EQ(weight_label(e.doc().spline, q, w), iv.label) << "w = " << w;
  };
  WeightRegionRequest q;
  const WeightRegion* r = e.weight_region_view(&q);
  check(r, q);
  EXPECT_EQ(q.from, 0.25);
  EXPECT_EQ(q.to, 4.0);
  bool increasing = false;  // Fig. 8's P2: increasing for w2 in about [1.134, 1.257]
  for (const WeightInterval& iv : r->intervals)
    increasing = increasing || (iv.label == code(Direction::increasing) && iv.from < 1.2 && iv.to > 1.2);
  EXPECT_TRUE(increasing);
  e.set_weight(2, 1.2);
  e.set_mode(Mode::cmr);
  r = e.weight_region_view(&q);
  check(r, q);
  EXPECT_DOUBLE_EQ(q.from, 0.3);
  EXPECT_DOUBLE_EQ(q.to, 4.8);
  EXPECT_EQ(q.labels.mode, Mode::cmr);
}

// Weights of any sign: a negative weight that makes W vanish is a pole, the
// status line says so exactly when analyze finds one, the region is all 0,
// and the weight view spans [4w, w/4] (or [-1, 1] at w = 0) with its pole
// stretch marked as analyze finds it; every weight 0 is refused.
TEST(EditEngine, SignedWeightsAndPoles) {
  Editor e = small_editor(spline6());
  e.show_weight_region = true;
  e.select(2);
  for (const double w : {-2.0, -0.01, 0.0, 0.5}) {
    e.set_weight(2, w);
    EXPECT_EQ(e.doc().spline.weight(2), w);
    const bool pole = analyze(e.doc().spline).pole;
    EXPECT_EQ(e.message.find("pole") != std::string::npos, pole) << "w = " << w << ": " << e.message;
    WeightRegionRequest q;
    const WeightRegion* r = e.weight_region_view(&q);
    ASSERT_NE(r, nullptr);
    EXPECT_LT(q.from, q.to);
    EXPECT_LE(q.from, w);
    EXPECT_GE(q.to, w);
    for (const WeightInterval& iv : r->intervals)
      for (const double x : {iv.from, iv.to}) {
        const SplineAnalysis a = analyze(with_weight(e.doc().spline, 2, x));
        EXPECT_EQ(iv.pole, a.pole) << "w = " << x;
        if (iv.pole) {
          EXPECT_EQ(iv.label, 0);
        }
      }
  }
  EXPECT_TRUE(analyze(with_weight(e.doc().spline, 2, -2.0)).pole) << "the test should meet a pole";
  const BSpline lone = BSpline::bezier({{0, 0}, {1, 1}, {2, 0}}, "", {0, 1, 0});
  Editor f = small_editor(lone);
  EXPECT_THROW(f.set_weight(1, 0.0), InputError);
}

TEST(EditEngine, RegionKeyIgnoresOnlyWhereTheMovedGroupStands) {
  const BSpline s = spline6();
  RegionRequest r;
  r.point = 2;
  r.with = {3};
  r.view = View{-1, -2, 6, 3};
  const auto key = region_key(s, r);
  // The group moved by one vector (2^-7 each way: every sum here is exact,
  // so the offsets are unchanged): same key.
  const Vec2 d{0.0078125, -0.0078125};
  const BSpline moved = s.with_point(2, s.points()[2] + d).with_point(3, s.points()[3] + d);
  EXPECT_EQ(region_key(moved, r), key);
  // A companion moved alone, a fixed point moved, the request changed: other keys.
  EXPECT_NE(region_key(s.with_point(3, s.points()[3] + d), r), key);
  EXPECT_NE(region_key(s.with_point(0, {0, 1e-300}), r), key);
  RegionRequest r2 = r;
  r2.mode = Mode::cmr;
  EXPECT_NE(region_key(s, r2), key);
  r2 = r;
  r2.with.clear();
  EXPECT_NE(region_key(s, r2), key);
  // Offsets kept exactly: 1e16 + 2 - 0.5 and 1e16 + 2 - 0.25 round to the
  // same double, yet they are two problems.
  const BSpline far = s.with_point(2, {0.5, 2}).with_point(3, {1e16 + 2, 1.5});
  const BSpline far2 = s.with_point(2, {0.25, 2}).with_point(3, {1e16 + 2, 1.5});
  ASSERT_EQ((1e16 + 2) - 0.5, (1e16 + 2) - 0.25);
  EXPECT_NE(region_key(far, r), region_key(far2, r));
}

TEST(EditEngine, RegionCacheFindsEqualKeysOnly) {
  // Keys are compared with == (through their hash first): -0.0 and 0.0 are
  // one key, the smallest difference another.
  const BSpline s = spline6().with_point(4, {0.0, -6.95});
  RegionRequest r;
  r.point = 2;
  r.width = r.height = 8;
  RegionCache cache;
  const RegionResult& a = cache.get(s, r);
  EXPECT_EQ(cache.find(region_key(s.with_point(4, {-0.0, -6.95}), r)), &a) << "-0.0 == 0.0: the same key";
  EXPECT_EQ(cache.find(region_key(s.with_point(4, {1e-300, -6.95}), r)), nullptr);
  EXPECT_EQ(&cache.get(s, r), &a);
  EXPECT_EQ(cache.size(), 1u);
}

TEST(EditEngine, RegionCacheRemembersWhyALayerIsEmpty) {
  // The status line's reason is worked out once per remembered layer: a frame
  // served by the cache does not prepare the request again (issue 23: a
  // 10,000-point spline's remembered frame). P5 of Fig. 8 acts on segment 2
  // only; segments 0..1 fail whatever it does.
  const BSpline s = spline6();
  RegionRequest r;
  r.point = 5;
  r.width = r.height = 8;
  r.depth = false;
  RegionCache cache;
  const auto key = region_key(s, r);
  EXPECT_FALSE(cache.reason(s, r, key).has_value()) << "not remembered yet";
  EXPECT_EQ(cache.reasons_worked_out(), 0);
  const RegionResult& layer = cache.get(s, r, key);
  const auto direct = region_reason(RegionProblem::make(s, r), layer);
  ASSERT_TRUE(direct.has_value());
  EXPECT_EQ(cache.reason(s, r, key), direct);
  EXPECT_EQ(cache.reason(s, r, key), direct);
  EXPECT_EQ(cache.reasons_worked_out(), 1) << "the second call is served from the cache";
  // Another layer in between: the first one's reason is still remembered.
  RegionRequest r3 = r;
  r3.point = 3;
  const auto key3 = region_key(s, r3);
  const RegionResult& layer3 = cache.get(s, r3, key3);
  // The editor shows the reason's fields as the command's flags (tools/field_flags.hpp).
  const auto direct3 = region_reason(RegionProblem::make(s, r3), layer3);
  ASSERT_TRUE(direct3.has_value());
  EXPECT_EQ(cache.reason(s, r3, key3), cli::show_fields(*direct3));
  EXPECT_EQ(cache.reason(s, r, key), direct);
  EXPECT_EQ(cache.reasons_worked_out(), 2);
}

TEST(EditEngine, CachedRegionOfADraggedPointIsItsCertifiedRegion) {
  // The layer the cache returns while P2 is dragged is what classify gives
  // for the spline with P2 where the drag left it.
  Editor e = small_editor(spline6());
  e.select(2);
  e.region();
  const Vec2 from = e.viewport().to_screen(e.doc().spline.points()[2]);
  e.mouse_move(from.x, from.y);
  e.mouse_button(MouseButton::left, true, false);
  ASSERT_EQ(e.dragging(), 2);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> step(-6, 6);
  Vec2 at = from;
  for (int i = 0; i < 5; ++i) {
    at = at + Vec2{step(rng), step(rng)};
    e.mouse_move(at.x, at.y);
    bool changed = true;
    const auto& layers = e.region(&changed);
    EXPECT_FALSE(changed) << "P2's own region does not depend on where P2 is";
    EXPECT_EQ(e.region_coarse(), 1) << "a remembered region is shown at full resolution";
    ASSERT_EQ(layers.size(), 1u);
    const RegionRequest r = e.region_requests().front();
    expect_layer_is_classify(e.doc().spline, r, *layers.front());
    EXPECT_GT(kW * kH - count_label(*layers.front(), Direction::none), 0) << "region pixels in view";
  }
  e.mouse_button(MouseButton::left, false, false);
}

TEST(EditEngine, OverlappedRegionsAreCoarseWhileDraggingAndFullAfter) {
  Editor e = small_editor(spline6());
  e.set_all_points(true);
  e.region();
  const Vec2 from = e.viewport().to_screen(e.doc().spline.points()[3]);
  e.mouse_move(from.x, from.y);
  e.mouse_button(MouseButton::left, true, false);
  e.mouse_move(from.x + 7, from.y - 5);
  bool changed = false;
  const auto& coarse = e.region(&changed);
  EXPECT_TRUE(changed);
  ASSERT_EQ(e.region_coarse(), Editor::kDragCoarse);
  const std::vector<RegionRequest> rc = e.region_requests(false, Editor::kDragCoarse);
  ASSERT_EQ(coarse.size(), rc.size());
  EXPECT_EQ(rc.front().width, (kW + 1) / 2);
  EXPECT_EQ(rc.front().height, (kH + 1) / 2);
  // Coarse pixel (i, j) covers window pixels 2i, 2i+1: its centre is theirs.
  const View& v = *rc.front().view;
  const View full = e.viewport().view;
  EXPECT_DOUBLE_EQ(v.x0, full.x0);
  EXPECT_DOUBLE_EQ(v.y1, full.y1);
  EXPECT_NEAR((v.x1 - v.x0) / rc.front().width, 2 * (full.x1 - full.x0) / kW, 1e-12);
  for (std::size_t k = 0; k < rc.size(); ++k) expect_layer_is_classify(e.doc().spline, rc[k], *coarse[k]);
  // The window's colours replicate each coarse pixel into its 2x2 block.
  const std::vector<uint8_t>& rgba = e.region_rgba();
  for (int j : {0, 1, 30, 31})
    for (int i : {10, 11})
      EXPECT_EQ(std::vector<uint8_t>(&rgba[4 * (j * kW + i)], &rgba[4 * (j * kW + i) + 4]),
                std::vector<uint8_t>(&rgba[4 * ((j / 2 * 2) * kW + i / 2 * 2)],
                                     &rgba[4 * ((j / 2 * 2) * kW + i / 2 * 2) + 4]));
  e.mouse_button(MouseButton::left, false, false);
  const auto& after = e.region(&changed);
  EXPECT_TRUE(changed);
  EXPECT_EQ(e.region_coarse(), 1);
  const std::vector<RegionRequest> rf = e.region_requests();
  ASSERT_EQ(after.size(), rf.size());
  EXPECT_EQ(rf.front().width, kW);
  int monotone = 0;
  for (std::size_t k = 0; k < rf.size(); ++k) {
    expect_layer_is_classify(e.doc().spline, rf[k], *after[k]);
    monotone += kW * kH - count_label(*after[k], Direction::none);
  }
  EXPECT_GT(monotone, 0) << "the test should see region pixels";
}

TEST(EditEngine, KnotOperationsKeepOrChangeTheCurveAsKnotOpsSays) {
  Editor e = small_editor(spline6());
  const BSpline before = e.doc().spline;
  ASSERT_TRUE(e.knot_operation("insert", 3.5, 1));
  EXPECT_EQ(e.doc().spline.point_count(), before.point_count() + 1);
  for (double t : {2.3, 3.5, 4.7}) {
    const Vec2 a = evaluate(before, t), b = evaluate(e.doc().spline, t);
    EXPECT_NEAR(a.x, b.x, 1e-12);
    EXPECT_NEAR(a.y, b.y, 1e-12);
  }
  ASSERT_TRUE(e.knot_operation("remove", 3.5, 0)) << e.message;  // removable: it was just inserted
  EXPECT_EQ(e.doc().spline.point_count(), before.point_count());
  // Knot 3 of the original is not removable within 1e-9 of the size: refused, nothing changes.
  const BSpline kept = e.doc().spline;
  EXPECT_FALSE(e.knot_operation("remove", 3, 0));
  EXPECT_NE(e.message.find("refused"), std::string::npos) << e.message;
  EXPECT_NE(e.message.find("more than the tolerance"), std::string::npos) << e.message;
  EXPECT_EQ(e.doc().spline.points(), kept.points());
  ASSERT_TRUE(e.knot_operation("elevate", 0, 0));
  EXPECT_EQ(e.doc().spline.degree(), 4);
  EXPECT_EQ(e.doc().spline.points(), elevate_degree(kept).points());
  ASSERT_TRUE(e.knot_operation("uniform", 0, 0));
  EXPECT_EQ(e.doc().spline.knots(), make_uniform(elevate_degree(kept)).knots());
  ASSERT_TRUE(e.knot_operation("clamp", 0, 0));
  EXPECT_EQ(e.doc().spline.knots(), clamp(make_uniform(elevate_degree(kept))).knots());
  EXPECT_FALSE(e.knot_operation("insert", 99, 1)) << "outside the domain";
  EXPECT_FALSE(e.knot_operation("twist", 0, 0));
  // Each operation was one undo step.
  for (int i = 0; i < 5; ++i) EXPECT_TRUE(e.undo());
  EXPECT_EQ(e.doc().spline.points(), before.points());
  EXPECT_EQ(e.doc().spline.knots(), before.knots());
}

TEST(EditEngine, SegmentRangeReachesTheRequestsAndDropsAnOutsideSplit) {
  Editor e = small_editor(spline6());
  e.select(3);
  e.set_split(1);
  e.set_segments(SegmentRange{1, 2});
  EXPECT_FALSE(e.doc().split.has_value()) << "joint 1 is not inside 1..2";
  const RegionRequest r = e.region_requests().front();
  ASSERT_TRUE(r.segments.has_value());
  EXPECT_EQ(*r.segments, (SegmentRange{1, 2}));
  EXPECT_NE(region_key(e.doc().spline, r), region_key(e.doc().spline, [&] {
              RegionRequest all = r;
              all.segments.reset();
              return all;
            }()));
  EXPECT_THROW(e.set_split(1), InputError);
  e.set_split(2);
  EXPECT_THROW(e.set_segments(SegmentRange{0, 3}), InputError);
  expect_layer_is_classify(e.doc().spline, e.region_requests().front(), *e.region().front());
  e.set_segments(std::nullopt);
  EXPECT_FALSE(e.region_requests().front().segments.has_value());
}

TEST(EditEngine, KnotMoveIsSetKnot) {
  Editor e = small_editor(spline6());
  e.move_knot(4, 4.25);
  EXPECT_EQ(e.doc().spline.knots(), set_knot(spline6(), 4, 4.25).knots());
  EXPECT_THROW(e.move_knot(4, 2.5), InputError) << "knots stay in order";
  EXPECT_THROW(e.move_knot(99, 0.5), InputError);
  // A ruler drag (consecutive moves of one knot) is one undo step.
  e.move_knot(4, 4.5);
  e.move_knot(4, 4.75);
  ASSERT_TRUE(e.undo());
  EXPECT_EQ(e.doc().spline.knots(), spline6().knots());
  e.move_knot(4, 4.5);
  e.move_knot(3, 3.25);  // another knot: a new step
  ASSERT_TRUE(e.undo());
  EXPECT_EQ(e.doc().spline.knots()[4], 4.5);
}

}  // namespace

namespace {

// The window's swapchain choices (vk/presenter.hpp): no upper image limit is
// written maxImageCount == 0; a currentExtent of 0xFFFFFFFF means the
// swapchain decides the size.
TEST(EditPresenter, ImageCountHonoursAMissingUpperLimit) {
  VkSurfaceCapabilitiesKHR caps{};
  caps.minImageCount = 2;
  caps.maxImageCount = 0;
  EXPECT_EQ(cmr::vk::choose_image_count(caps), 3u);
  caps.maxImageCount = 2;
  EXPECT_EQ(cmr::vk::choose_image_count(caps), 2u);
  caps.maxImageCount = 8;
  EXPECT_EQ(cmr::vk::choose_image_count(caps), 3u);
}

TEST(EditPresenter, ExtentFollowsTheWindowOnlyWhenTheSurfaceLetsIt) {
  VkSurfaceCapabilitiesKHR caps{};
  caps.currentExtent = {640, 480};
  caps.minImageExtent = {1, 1};
  caps.maxImageExtent = {4096, 4096};
  EXPECT_EQ(cmr::vk::choose_extent(caps, 800, 600).width, 640u);
  caps.currentExtent = {0xFFFFFFFFu, 0xFFFFFFFFu};
  const VkExtent2D e = cmr::vk::choose_extent(caps, 800, 9000);
  EXPECT_EQ(e.width, 800u);
  EXPECT_EQ(e.height, 4096u) << "clamped to the surface's limit";
}

}  // namespace
