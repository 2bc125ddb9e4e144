// The editor's window-free logic: Bezier-chain G1 moves, viewport mapping
// against cmr::pixel_center, undo merging.
#include <gtest/gtest.h>

#include <cmath>

#include "tools/edit/engine.hpp"
#include "tools/edit/model.hpp"

namespace {

using namespace cmr;
using namespace cmr::edit;

// Two cubic Bezier pieces joined at P3 (knot 1 of multiplicity 3): a chain.
BSpline chain_spline() {
  return BSpline::make(3, {0, 0, 0, 1, 1, 1, 2, 2, 2},
                       {{0, 0}, {1, 1}, {2, 1}, {3, 0}, {4, -1}, {5, -1}, {6, 0}});
}

Document doc_of(BSpline s, bool chain) {
  return Document{std::move(s), 0, {}, false, Mode::cmrwi, kDefaultDepth, false, std::nullopt, chain, std::nullopt, std::nullopt};
}

TEST(EditModel, ChainAnchorsAreTheJointPoints) {
  EXPECT_EQ(chain_anchors(chain_spline()), std::vector<int>{3});
  EXPECT_TRUE(chain_anchors(BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7}, {{0, 0}, {1, 1}, {2, 1}, {3, 0}, {4, 1}, {5, 0}}))
                  .empty());
}

TEST(EditModel, AnchorCarriesItsHandles) {
  const Document d = doc_of(chain_spline(), true);
  const BSpline s = move_point(d, 3, {3.5, 0.5});
  for (int i : {2, 3, 4}) {
    const Vec2 moved = s.points()[i] - d.spline.points()[i];
    EXPECT_DOUBLE_EQ(moved.x, 0.5) << "point " << i;
    EXPECT_DOUBLE_EQ(moved.y, 0.5) << "point " << i;
  }
  EXPECT_EQ(s.points()[1], d.spline.points()[1]);
}

TEST(EditModel, HandleTurnsTheOppositeHandleCollinear) {
  const Document d = doc_of(chain_spline(), true);
  const BSpline s = move_point(d, 2, {1.0, 2.0});
  const Vec2 a = s.points()[3], h1 = s.points()[2], h2 = s.points()[4];
  EXPECT_NEAR(det(h1 - a, h2 - a), 0.0, 1e-12) << "G1: handles and anchor collinear";
  EXPECT_LT(dot(h1 - a, h2 - a), 0) << "handles on opposite sides";
  EXPECT_NEAR(std::hypot(h2.x - a.x, h2.y - a.y), std::sqrt(2.0), 1e-12) << "opposite handle keeps its length";
  const BSpline off = move_point(doc_of(chain_spline(), false), 2, {1.0, 2.0});
  EXPECT_EQ(off.points()[4], chain_spline().points()[4]) << "without chain mode only the point moves";
}

TEST(EditModel, ViewportMapsPixelCentresLikeCmrRegion) {
  const Viewport v{{-1, -7, 5, -2.5}, 320, 240};
  for (int j : {0, 17, 239})
    for (int i : {0, 100, 319}) {
      const Vec2 c = pixel_center(v.view, 320, 240, i, j);
      const Vec2 s = v.to_screen(c);
      EXPECT_NEAR(s.x, i + 0.5, 1e-9) << i << "," << j;
      EXPECT_NEAR(s.y, j + 0.5, 1e-9) << i << "," << j;
    }
  const Viewport z = v.zoomed(2.0, 160, 120);
  EXPECT_NEAR(z.to_screen(v.to_world(160, 120)).x, 160, 1e-9) << "zoom keeps the cursor's point";
}

TEST(EditModel, DragCommitsMergeIntoOneUndoStep) {
  History h(doc_of(chain_spline(), false));
  for (int i = 1; i <= 3; ++i) {
    Document d = h.current();
    d.spline = d.spline.with_point(0, {0.1 * i, 0});
    h.commit(std::move(d), "drag1");
  }
  h.seal();
  EXPECT_TRUE(h.undo());
  EXPECT_EQ(h.current().spline.points()[0], Vec2(0, 0));
  EXPECT_FALSE(h.undo());
  EXPECT_TRUE(h.redo());
  EXPECT_DOUBLE_EQ(h.current().spline.points()[0].x, 0.3);
}

TEST(EditModel, KnotInsertionKeepsARationalCurve) {
  const BSpline s = BSpline::make(3, {0, 0, 0, 1, 2, 2, 2}, {{0, 0}, {1, 2}, {3, 3}, {4, 1}, {5, 0}}, "", {1, 2, 0.5, 1.5, 1});
  const KnotResult r = knot_operation(s, "insert", 0.5, 2);
  ASSERT_TRUE(r.spline.is_rational());
  EXPECT_EQ(r.spline.point_count(), 7);
  for (double t = 0; t <= 2; t += 0.125) {
    const Vec2 a = evaluate(s, t), b = evaluate(r.spline, t);
    EXPECT_NEAR(a.x, b.x, 1e-12) << "t=" << t;
    EXPECT_NEAR(a.y, b.y, 1e-12) << "t=" << t;
  }
}

}  // namespace
