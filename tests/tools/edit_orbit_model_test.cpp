// The orbit view of a space curve without a window (tools/edit/orbit.hpp):
// the camera's projection and rays, a pointer drag that keeps the point in
// its plane, and the region's label at the dropped position against the
// certified label `cmr region SPACE.json --point K --plane ...` computes
// (SpaceRegionProblem, its CPU path) and against analyze_space of the moved
// curve.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "bezierize/space_analyze.hpp"
#include "region/space_region.hpp"
#include "spline/space.hpp"
#include "tools/edit/orbit.hpp"

namespace {

using namespace cmr;
using cmr::edit::OrbitPlane;
using cmr::edit::OrbitView;

const std::string kLifted = std::string(CMR_SOURCE_DIR) + "/examples/space/fig8b_lifted.json";

OrbitView make_view() {
  return OrbitView(read_space_spline_file(kLifted), kLifted, 1024, 768);
}

TEST(EditOrbit, ProjectionAndRayAgree) {
  OrbitView v(read_space_spline_file(kLifted), kLifted, 1024, 768);
  for (double yaw : {-120.0, 0.0, 35.0, 170.0})
    for (double pitch : {-60.0, 0.0, 30.0, 89.0}) {
      v.orbit(yaw, pitch);
      const edit::OrbitProjection p = v.projection();
      for (const Vec3& q : v.spline().points()) {
        Vec2 s;
        ASSERT_TRUE(p.to_screen(q, s));
        // q lies on the ray through its pixel.
        const Vec3 r = glm::normalize(p.ray(s));
        const Vec3 d = q - p.eye;
        EXPECT_LT(glm::length(d - glm::dot(d, r) * r), 1e-9 * glm::length(d)) << yaw << " " << pitch;
      }
    }
  // Rotating moves the picture; zoom divides the distance.
  v.orbit(0, 20);
  Vec2 a, b;
  ASSERT_TRUE(v.projection().to_screen(v.spline().points()[5], a));
  v.orbit(90, 20);
  ASSERT_TRUE(v.projection().to_screen(v.spline().points()[5], b));
  EXPECT_GT(std::hypot(a.x - b.x, a.y - b.y), 20);
  const double d = v.camera.distance;
  v.zoom(2);
  EXPECT_DOUBLE_EQ(v.camera.distance, d / 2);
}

/// Drags the selected point with the pointer, as the window does, to the
/// pixel where plane point (a, b) appears.
void pointer_drag(OrbitView& v, double a, double b) {
  const edit::OrbitProjection p = v.projection();
  Vec2 from, to;
  ASSERT_TRUE(p.to_screen(v.spline().points()[v.selected()], from));
  ASSERT_TRUE(p.to_screen(v.plane_point(a, b), to));
  v.mouse_move(from.x, from.y);
  v.mouse_button(edit::MouseButton::left, true);
  ASSERT_EQ(v.dragging(), v.selected());
  for (int i = 1; i <= 5; ++i)
    v.mouse_move(from.x + (to.x - from.x) * i / 5, from.y + (to.y - from.y) * i / 5);
  v.mouse_button(edit::MouseButton::left, false);
  EXPECT_EQ(v.dragging(), -1);
}

TEST(EditOrbit, DragStaysInThePlaneAndTheLabelThereIsCmrRegions) {
  for (OrbitPlane kind : {OrbitPlane::region, OrbitPlane::xy, OrbitPlane::screen, OrbitPlane::zx}) {
    OrbitView v = make_view();
    v.orbit(-60, 35);
    v.select(3);
    v.set_plane_kind(kind);
    ASSERT_TRUE(v.plane()) << v.message;
    v.settle();
    const edit::OrbitRegion region = *v.region();
    ASSERT_TRUE(region.full);
    const SpacePlane plane = *v.plane();
    const SpaceSpline before = v.spline();
    // cmr region's labels for this plane and view (the CPU path), pixel for pixel.
    SpaceRegionRequest req;
    req.point = 3;
    req.plane = plane;
    req.width = region.width;
    req.height = region.height;
    req.view = region.view;
    const SpaceRegionProblem problem = SpaceRegionProblem::make(before, req);
    EXPECT_EQ(problem.render(0).labels, region.labels) << edit::orbit_plane_name(kind);
    // Pixels inside a 5 x 5 block of one label: monotone ones and not monotone ones.
    const int w = region.width, h = region.height;
    std::vector<std::pair<int, int>> picks;
    int monotone = 0, other = 0;
    for (int j = 2; j + 2 < h; j += 3)
      for (int i = 2; i + 2 < w; i += 3) {
        const Direction l = region.labels[static_cast<std::size_t>(j) * w + i];
        bool uniform = true;
        for (int dj = -2; dj <= 2 && uniform; ++dj)
          for (int di = -2; di <= 2; ++di)
            if (region.labels[static_cast<std::size_t>(j + dj) * w + i + di] != l) uniform = false;
        if (!uniform) continue;
        const bool mono = l == Direction::increasing || l == Direction::decreasing;
        if (mono && monotone < 3) ++monotone, picks.push_back({i, j});
        if (!mono && other < 2) ++other, picks.push_back({i, j});
      }
    ASSERT_GT(monotone, 0) << edit::orbit_plane_name(kind) << ": no monotone block to drop the point in";
    const double size = glm::length(before.points()[5] - before.points()[0]);
    for (auto [i, j] : picks) {
      const Vec2 c = pixel_center(region.view, w, h, i, j);
      pointer_drag(v, c.x, c.y);
      const Vec3 q = v.spline().points()[3];
      // In the plane (to rounding), near the pixel's centre (to the pointer's precision).
      const Vec3 n = glm::normalize(glm::cross(plane.u, plane.v));
      EXPECT_LT(std::abs(glm::dot(q - plane.origin, n)), 1e-12 * size) << edit::orbit_plane_name(kind);
      const Vec2 ab = v.plane_coordinates(q);
      EXPECT_LT(std::hypot(ab.x - c.x, ab.y - c.y), 0.5 * (region.view.x1 - region.view.x0) / w) << i << "," << j << " c " << c.x << "," << c.y << " ab " << ab.x << "," << ab.y << " " << edit::orbit_plane_name(kind);
      // The label there: the region's pixel = cmr region's classify at (a, b) =
      // the editor's live label = analyze of the moved curve.
      const Direction want = region.labels[static_cast<std::size_t>(j) * w + i];
      EXPECT_EQ(problem.classify(ab.x, ab.y).label, want);
      EXPECT_EQ(v.label_here(), want);
      const Direction analysed = analyze_space(v.spline()).curvature;
      EXPECT_EQ(analysed == Direction::undecided ? Direction::none : analysed,
                want == Direction::undecided ? Direction::none : want);
      // The other points did not move.
      for (int k = 0; k < before.point_count(); ++k)
        if (k != 3) {
          EXPECT_EQ(v.spline().points()[k], before.points()[k]);
        }
      // The region did not change: K's region does not depend on where K is in its plane.
      // (Rendered again for the first drop only: each render is 25,600 certified pixels.)
      if (std::make_pair(i, j) == picks.front()) {
        EXPECT_EQ(SpaceRegionProblem::make(v.spline(), req).render(0).labels, region.labels);
      }
      EXPECT_EQ(v.region()->labels, region.labels);
    }
    // Undo puts the point back exactly.
    while (v.spline().points() != before.points()) v.undo();
    EXPECT_EQ(v.spline().points()[3], before.points()[3]);
  }
}

TEST(EditOrbit, LeftDragOffAPointOrbitsRightDragPans) {
  OrbitView v = make_view();
  v.orbit(0, 0);
  const double yaw = v.camera.yaw;
  const Vec3 target = v.camera.target;
  v.mouse_move(5, 5);  // no point there
  v.mouse_button(edit::MouseButton::left, true);
  v.mouse_move(105, 5);
  v.mouse_button(edit::MouseButton::left, false);
  EXPECT_NEAR(v.camera.yaw, yaw - 100 * 0.3 * M_PI / 180, 1e-12);
  EXPECT_EQ(v.camera.target, target);
  v.mouse_button(edit::MouseButton::right, true);
  v.mouse_move(125, 25);
  v.mouse_button(edit::MouseButton::right, false);
  EXPECT_GT(glm::length(v.camera.target - target), 0);
  const SpaceSpline s = v.spline();
  EXPECT_EQ(s.points(), make_view().spline().points());  // nothing moved
}

TEST(EditOrbit, ARayParallelToThePlaneLeavesThePointWhereItIs) {
  OrbitView v = make_view();
  v.select(3);
  v.set_plane_kind(OrbitPlane::xy);
  v.orbit(0, 0);  // looking horizontally: the xy plane is edge-on
  const Vec3 before = v.spline().points()[3];
  Vec2 s;
  ASSERT_TRUE(v.projection().to_screen(before, s));
  EXPECT_FALSE(v.move_to_screen({s.x, s.y - 40}));  // above the horizon: the ray meets the plane behind the eye
  EXPECT_EQ(v.spline().points()[3], before);
}

TEST(EditOrbit, OpensOnThePointAskedOrTheFirstWithARegion) {
  OrbitView v = make_view();
  v.open_on_region_point(4);
  EXPECT_EQ(v.selected(), 4);
  EXPECT_THROW(v.open_on_region_point(6), InputError);
  v.open_on_region_point(std::nullopt);
  v.settle();
  const auto& l = v.region()->labels;
  EXPECT_GT(std::count_if(l.begin(), l.end(), [](Direction d) { return d == Direction::increasing || d == Direction::decreasing; }), 0);
}

}  // namespace

namespace {

TEST(EditOrbit, OpensFacingThePlaneNotEdgeOn) {
  const std::string failing = std::string(CMR_SOURCE_DIR) + "/examples/space/fig8_lifted.json";
  OrbitView v(read_space_spline_file(failing), failing, 1024, 768);
  for (int k = 0; k < v.spline().unique_point_count(); ++k)
    for (OrbitPlane kind : {OrbitPlane::region, OrbitPlane::xy, OrbitPlane::yz, OrbitPlane::zx}) {
      v.select(k);
      v.set_plane_kind(kind);
      if (!v.plane()) continue;
      v.orbit(0, 0);
      v.face_plane();
      const Vec3 n = glm::normalize(glm::cross(v.plane()->u, v.plane()->v));
      // The view direction is at least 20 degrees off the plane: its region is not a line.
      EXPECT_GE(std::abs(glm::dot(v.projection().forward, n)), std::sin(20 * M_PI / 180) - 1e-12)
          << "P" << k << " " << edit::orbit_plane_name(kind);
      // Every control point is in front of the camera and inside the canvas beside the panel.
      for (const Vec3& q : v.spline().points()) {
        Vec2 s;
        ASSERT_TRUE(v.projection().to_screen(q, s));
        EXPECT_GE(s.x, 0);
        EXPECT_LE(s.x, v.width() - v.panel_width);
        EXPECT_GE(s.y, 0);
        EXPECT_LE(s.y, v.height());
      }
    }
}

}  // namespace

namespace {

TEST(EditOrbit, ARationalCurvesPointMovesInItsPlaneWithItsWeight) {
  const std::string rational = std::string(CMR_SOURCE_DIR) + "/examples/space/fig8b_lifted_rational.json";
  OrbitView v(read_space_spline_file(rational), rational, 1024, 768);
  const SpaceSpline before = v.spline();
  ASSERT_TRUE(before.is_rational());
  v.select(3);
  v.set_plane_kind(OrbitPlane::xy);
  v.orbit(-60, 35);
  SpaceRegionRequest req;
  req.point = 3;
  req.plane = *v.plane();
  const SpaceRegionProblem problem = SpaceRegionProblem::make(before, req);
  int monotone = 0;
  for (auto [a, b] : {std::pair{0.0, 0.0}, {-0.3, -0.2}, {0.2, 0.3}, {-0.6, 0.1}, {0.5, -0.5}}) {
    pointer_drag(v, a, b);
    const Vec3 q = v.spline().points()[3];
    EXPECT_EQ(q.z, before.points()[3].z);
    EXPECT_EQ(v.spline().weights(), before.weights());
    const Vec2 ab = v.plane_coordinates(q);
    const Direction here = problem.classify(ab.x, ab.y).label;
    EXPECT_EQ(v.label_here(), here);
    const Direction analysed = analyze_space(v.spline()).curvature;
    EXPECT_EQ(analysed == Direction::undecided ? Direction::none : analysed,
              here == Direction::undecided ? Direction::none : here);
    monotone += here == Direction::increasing || here == Direction::decreasing;
  }
  EXPECT_GT(monotone, 0);  // the test sees both kinds of label
  EXPECT_LT(monotone, 5);
}

}  // namespace
