#include "region/contour.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "spline/errors.hpp"

namespace cmr {
namespace {

constexpr double kTol = 1e-9;

RegionContours contours_of(const RegionProblem& problem) {
  CpuRegionBackend cpu(2);
  return region_contours(problem, cpu.render(problem));
}

// The coordinate a refined vertex was bisected along: the one that is not a
// sample's (a pixel centre's, or the view's edge on the ring of samples).
Vec2 bisection_step(Vec2 p, const View& v, int width, double delta) {
  const double cx = (p.x - v.x0) / (v.x1 - v.x0) * width - 0.5;
  const bool on_column = p.x == v.x0 || p.x == v.x1 || std::abs(cx - std::round(cx)) <= 1e-6;
  return on_column ? Vec2{0, delta} : Vec2{delta, 0};
}

// The labels and the band tile the view: their areas sum to its area.
void expect_areas_sum_to_the_view(const RegionContours& rc) {
  const View& v = rc.view;
  double total = rc.band.area;
  for (const LabelContours& lc : rc.labels) total += lc.area;
  const double view_area = (v.x1 - v.x0) * (v.y1 - v.y0);
  EXPECT_NEAR(total, view_area, 1e-9 * view_area) << "band " << rc.band.area;
}

// Every piece is a convex counter-clockwise polygon, the fans of the pieces
// cover exactly the area the outlines enclose, and every outline vertex is an
// edge vertex (refined or on the view's edge).
void expect_consistent(const RegionContours& rc) {
  for (const LabelContours& lc : rc.labels) {
    double fans = 0;
    for (const std::vector<int>& piece : lc.pieces) {
      ASSERT_GE(piece.size(), 3u);
      for (std::size_t k = 1; k + 1 < piece.size(); ++k) {
        const double a = polygon_area(lc.vertices, {piece[0], piece[k], piece[k + 1]});
        EXPECT_GE(a, 0) << "label " << int(lc.label);
        fans += a;
      }
    }
    EXPECT_NEAR(fans, lc.area, 1e-9 * std::abs(lc.area) + 1e-12) << "label " << int(lc.label);
    for (const std::vector<int>& loop : lc.outlines) EXPECT_GE(loop.size(), 3u);
  }
  expect_areas_sum_to_the_view(rc);
}

// A quadratic Bezier P0 = (0,0), P1 = p, P2 = (4,0): P' = 2((1-t)a + tb) with
// a = p - P0, b = P2 - p, and P'' constant, so |kappa| has its one extremum
// where P'.P'' = 0, at t* = a.(a-b) / |a-b|^2. The curvature is monotone iff
// t* is not inside (0, 1): t* <= 0 iff (p - P0).(p - M) <= 0 (M = (P0+P2)/2),
// the disk with diameter P0 M; t* >= 1 iff (p - P2).(p - M) <= 0, the disk
// with diameter M P2. The region's boundary is the two unit circles around
// (1, 0) and (3, 0), and the line y = 0 where the sign of the curvature (and
// with it the direction) flips. Every refined vertex must lie within the
// tolerance of one of them.
TEST(Contour, QuadraticBoundaryVerticesLieOnTheCirclesInClosedForm) {
  const BSpline s = BSpline::bezier({{0, 0}, {2, 1}, {4, 0}});
  RegionRequest rq;
  rq.point = 1;
  rq.width = 97;
  rq.height = 61;
  rq.view = View{-0.53, -1.47, 4.61, 1.71};  // no pixel centre on y = 0
  const RegionProblem problem = RegionProblem::make(s, rq);
  const RegionContours rc = contours_of(problem);
  expect_consistent(rc);
  const double w = std::min(rq.view->x1 - rq.view->x0, rq.view->y1 - rq.view->y0);
  int refined = 0;
  double monotone_area = 0;
  for (const LabelContours& lc : rc.labels) {
    if (lc.label == code(Direction::increasing) || lc.label == code(Direction::decreasing))
      monotone_area += lc.area;
    for (std::size_t i = 0; i < lc.vertices.size(); ++i) {
      if (!lc.refined[i]) continue;
      ++refined;
      const Vec2 p = lc.vertices[i];
      const double d = std::min({std::abs(std::hypot(p.x - 1, p.y) - 1), std::abs(std::hypot(p.x - 3, p.y) - 1),
                                 std::abs(p.y)});
      EXPECT_LE(d, kTol * w) << "label " << int(lc.label) << " vertex (" << p.x << ", " << p.y << ")";
    }
  }
  EXPECT_GT(refined, 200);
  // Two unit disks; the pixel sampling misses at most a band of one pixel
  // diagonal along the boundary (length 4 pi + the diameters on y = 0).
  const double pixel = std::hypot((rq.view->x1 - rq.view->x0) / rq.width, (rq.view->y1 - rq.view->y0) / rq.height);
  EXPECT_NEAR(monotone_area, 2 * std::numbers::pi, pixel * (4 * std::numbers::pi + 4));
}

// On a cubic B-spline (the paper's Fig. 8, P3), the certified classifier on
// both sides of every refined vertex, 1e-9 of the view's side away along the
// pixel edge the vertex lies on, gives the label on one side and another on
// the other: the vertex is on the exact boundary to that accuracy.
TEST(Contour, CubicVerticesSeparateTheirLabelOnTheExactPath) {
  const BSpline s = BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7},
                                  {{1.3, -1.43}, {1.05, -0.06}, {2.15, -1.31}, {1.97, -3.83}, {-2.23, -6.95}, {-6.78, -9.78}});
  RegionRequest rq;
  rq.point = 3;
  rq.width = rq.height = 96;
  const RegionProblem problem = RegionProblem::make(s, rq);
  const RegionContours rc = contours_of(problem);
  expect_consistent(rc);
  const View& v = problem.view();
  const double delta = kTol * std::min(v.x1 - v.x0, v.y1 - v.y0);
  int checked = 0;
  for (const LabelContours& lc : rc.labels) {
    for (std::size_t i = 0; i < lc.vertices.size(); ++i) {
      if (!lc.refined[i]) continue;
      const Vec2 p = lc.vertices[i];
      // The sample grid's edge is horizontal or vertical: the coordinate
      // that is not a sample's is the one that was bisected.
      const Vec2 d = bisection_step(p, v, rq.width, delta);
      const std::uint8_t lo = code(problem.classify(p - d).label), hi = code(problem.classify(p + d).label);
      EXPECT_NE(lo, hi) << "(" << p.x << ", " << p.y << ")";
      EXPECT_TRUE(lo == lc.label || hi == lc.label) << "(" << p.x << ", " << p.y << ")";
      ++checked;
    }
  }
  EXPECT_GT(checked, 50);
  // The region is not empty and lies inside the view.
  double total = 0;
  for (const LabelContours& lc : rc.labels) total += lc.area;
  EXPECT_LE(total, (v.x1 - v.x0) * (v.y1 - v.y0) * (1 + 1e-12));
}

// With a split (Fig. 10(a)'s curve, P5, joint 2: three split labels meet),
// the vertices separate their labels on the exact path in the same way.
TEST(Contour, SplitLabelVerticesSeparateTheirLabelOnTheExactPath) {
  const BSpline s = BSpline::make(3, {0, 0, 0, 1, 2, 3, 3, 3},
                                  {{0, 0}, {0.33, 0}, {1.27, -0.27}, {3.46, -2.1}, {5.45, -4.7}, {5.4, -5.8}});
  RegionRequest rq;
  rq.point = 5;
  rq.split = 2;
  rq.width = rq.height = 64;
  const RegionProblem problem = RegionProblem::make(s, rq);
  const RegionContours rc = contours_of(problem);
  ASSERT_TRUE(rc.split);
  expect_consistent(rc);
  const View& v = problem.view();
  const double delta = kTol * std::min(v.x1 - v.x0, v.y1 - v.y0);
  int checked = 0;
  std::size_t monotone_labels = 0;
  for (const LabelContours& lc : rc.labels) {
    monotone_labels += lc.label >= 1 && lc.label <= 4;
    for (std::size_t i = 0; i < lc.vertices.size(); ++i) {
      if (!lc.refined[i]) continue;
      const Vec2 p = lc.vertices[i];
      const Vec2 d = bisection_step(p, v, rq.width, delta);
      const std::uint8_t lo = code(problem.classify(p - d).split_label), hi = code(problem.classify(p + d).split_label);
      EXPECT_NE(lo, hi) << "(" << p.x << ", " << p.y << ")";
      EXPECT_TRUE(lo == lc.label || hi == lc.label) << "(" << p.x << ", " << p.y << ")";
      ++checked;
    }
  }
  EXPECT_EQ(monotone_labels, 2u);  // inc-inc and inc-dec
  EXPECT_GT(checked, 20);
  expect_areas_sum_to_the_view(rc);
}

// A label map with holes: outlines of a ring come as one counter-clockwise
// loop and one clockwise loop, and the area is the difference.
TEST(Contour, HolesAreClockwiseLoops) {
  const BSpline s = BSpline::bezier({{0, 0}, {2, 1}, {4, 0}});
  RegionRequest rq;
  rq.point = 1;
  rq.width = rq.height = 40;
  rq.view = View{-0.5, -2.3, 4.5, 2.7};
  const RegionProblem problem = RegionProblem::make(s, rq);
  const RegionContours rc = contours_of(problem);
  // Not monotone (label 0) is the view minus the two disks: one outer loop
  // (the view's edge) and holes around the disks.
  const LabelContours* none = nullptr;
  for (const LabelContours& lc : rc.labels)
    if (lc.label == 0) none = &lc;
  ASSERT_NE(none, nullptr);
  int ccw = 0, cw = 0;
  for (const std::vector<int>& loop : none->outlines) (polygon_area(none->vertices, loop) > 0 ? ccw : cw)++;
  EXPECT_EQ(ccw, 1);
  EXPECT_GE(cw, 1);
  EXPECT_NEAR(none->area, 25 - 2 * std::numbers::pi, 1.0);
}

// The reproducer (fig8, P3, 40x40, view -0.1,-5.4,3.0,-2.3): every
// refined vertex is held to the promise contour.hpp states, at its stated
// distance: the certified label (the exact classifier, depth 12) differs
// tolerance/2 of the view's smaller side either side of the vertex along
// its pixel edge, and one side is the vertex's own label (the band's
// vertices: one side undecided). The band undecided at depth 12 between
// increasing and not monotone is an outline and an area of its own.
TEST(Contour, Fig8VerticesKeepThePromisedDistanceAndTheBandIsItsOwnOutline) {
  const BSpline s = BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7},
                                  {{1.3, -1.43}, {1.05, -0.06}, {2.15, -1.31}, {1.97, -3.83}, {-2.23, -6.95}, {-6.78, -9.78}});
  RegionRequest rq;
  rq.point = 3;
  rq.width = rq.height = 40;
  rq.view = View{-0.1, -5.4, 3.0, -2.3};
  const RegionProblem problem = RegionProblem::make(s, rq);
  const RegionContours rc = contours_of(problem);
  expect_consistent(rc);
  const View& v = problem.view();
  // The promise: within tolerance / 2 of the smaller side (1.55e-9 here);
  // the bracket's ends are at most that far, up to the rounding of along().
  const double promised = ContourOptions{}.tolerance / 2 * std::min(v.x1 - v.x0, v.y1 - v.y0);
  const double delta = promised * (1 + 1e-6);
  const std::uint8_t undecided = code(Direction::undecided);
  int checked = 0;
  std::vector<const LabelContours*> all;
  for (const LabelContours& lc : rc.labels) all.push_back(&lc);
  all.push_back(&rc.band);
  for (const LabelContours* lc : all)
    for (std::size_t i = 0; i < lc->vertices.size(); ++i) {
      if (!lc->refined[i]) continue;
      const Vec2 p = lc->vertices[i];
      const Vec2 d = bisection_step(p, v, rq.width, delta);
      const std::uint8_t lo = code(problem.classify(p - d).label), hi = code(problem.classify(p + d).label);
      EXPECT_NE(lo, hi) << "label " << int(lc->label) << " vertex (" << p.x << ", " << p.y << ")";
      // A band vertex is some label's vertex: undecided on one side, or a
      // decided label each side where the band's cell meets no undecided
      // stretch on that edge.
      if (lc == &rc.band) {
        ++checked;
        continue;
      }
      const std::uint8_t own = lc->label;
      EXPECT_TRUE(lo == own || hi == own) << "label " << int(lc->label) << " vertex (" << p.x << ", " << p.y
                                          << "): " << int(lo) << " | " << int(hi);
      ++checked;
    }
  EXPECT_GT(checked, 90);
  // No pixel centre is undecided, yet the band is there: outlines and area.
  for (const LabelContours& lc : rc.labels) EXPECT_NE(lc.label, undecided);
  ASSERT_FALSE(rc.band.outlines.empty());
  EXPECT_EQ(rc.band.label, kUndecidedBandLabel);
  EXPECT_GT(rc.band.area, 0);
  double fans = 0;
  for (const std::vector<int>& piece : rc.band.pieces) fans += polygon_area(rc.band.vertices, piece);
  // The band is thin (about 1e-8 here): compare to the rounding of
  // coordinates of the view's size, not to its own area.
  EXPECT_NEAR(fans, rc.band.area, 1e-12 * (v.x1 - v.x0) * (v.y1 - v.y0));
  // The labels and the band tile the view, corners and junctions included.
  expect_areas_sum_to_the_view(rc);
}

// The each-piece and alternating (--split S1,S2) maps: their contours are
// refined with the map's own kind of label (the reproducer: fig8, P3,
// 40x40, view -0.1,-5.4,3.0,-2.3, --each-piece), so every refined vertex
// separates two labels of that kind on the exact path, one of them its own,
// and the areas sum to the view. The label names are the map's own.
void expect_vertices_keep_the_promise_in_the_maps_kind(const RegionRequest& rq, const std::vector<const char*>& names) {
  const BSpline s = BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7},
                                  {{1.3, -1.43}, {1.05, -0.06}, {2.15, -1.31}, {1.97, -3.83}, {-2.23, -6.95}, {-6.78, -9.78}});
  const RegionProblem problem = RegionProblem::make(s, rq);
  CpuRegionBackend cpu(2);
  const RegionResult map = cpu.render(problem);
  const RegionContours rc = region_contours(problem, map);
  expect_consistent(rc);
  const View& v = problem.view();
  const double delta = ContourOptions{}.tolerance / 2 * std::min(v.x1 - v.x0, v.y1 - v.y0) * (1 + 1e-6);
  int checked = 0;
  for (const LabelContours& lc : rc.labels) {
    EXPECT_STREQ(rc.label_name(lc.label), map.label_name(lc.label));
    for (std::size_t i = 0; i < lc.vertices.size(); ++i) {
      if (!lc.refined[i]) continue;
      const Vec2 p = lc.vertices[i], d = bisection_step(p, v, rq.width, delta);
      const std::uint8_t lo = label_code(problem.classify(p - d), rq), hi = label_code(problem.classify(p + d), rq);
      EXPECT_NE(lo, hi) << "label " << int(lc.label) << " vertex (" << p.x << ", " << p.y << ")";
      EXPECT_TRUE(lo == lc.label || hi == lc.label) << "label " << int(lc.label) << " vertex (" << p.x << ", " << p.y
                                                    << "): " << int(lo) << " | " << int(hi);
      ++checked;
    }
  }
  EXPECT_GT(checked, 20);
  std::vector<const char*> got;
  for (const LabelContours& lc : rc.labels) got.push_back(rc.label_name(lc.label));
  ASSERT_EQ(got.size(), names.size());
  for (std::size_t k = 0; k < names.size(); ++k) EXPECT_STREQ(got[k], names[k]);
}

TEST(Contour, EachPieceOutlinesUseTheEachPieceClassifier) {
  RegionRequest rq;
  rq.point = 3;
  rq.each_piece = true;
  rq.width = rq.height = 40;
  rq.view = View{-0.1, -5.4, 3.0, -2.3};
  expect_vertices_keep_the_promise_in_the_maps_kind(rq, {"fail", "each-monotone"});
}

TEST(Contour, AlternatingOutlinesUseTheAlternatingClassifier) {
  RegionRequest rq;
  rq.point = 3;
  rq.splits = {1, 2};
  rq.width = rq.height = 40;  // the default view: 16 pixels inc-first
  expect_vertices_keep_the_promise_in_the_maps_kind(rq, {"fail", "inc-first"});
}

TEST(Contour, MismatchedRegionIsAnInputError) {
  const BSpline s = BSpline::bezier({{0, 0}, {2, 1}, {4, 0}});
  RegionRequest rq;
  rq.point = 1;
  rq.width = rq.height = 8;
  const RegionProblem problem = RegionProblem::make(s, rq);
  RegionRequest other = rq;
  other.width = 9;
  CpuRegionBackend cpu(1);
  EXPECT_THROW(region_contours(problem, cpu.render(RegionProblem::make(s, other))), InputError);
}

}  // namespace
}  // namespace cmr

// fuzz_region_classify found it: a NaN or infinite position reached GMP's
// mpq_set_d, which raises SIGFPE. It is bad input, an InputError.
namespace cmr {
TEST(Contour, NonFinitePositionIsAnInputErrorNotACrash) {
  const BSpline s = BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7},
                                  {{1.3, -1.43}, {1.05, -0.06}, {2.15, -1.31}, {1.97, -3.83}, {-2.23, -6.95}, {-6.78, -9.78}});
  RegionRequest rq;
  rq.point = 2;
  rq.width = rq.height = 4;
  const RegionProblem problem = RegionProblem::make(s, rq);
  for (const Vec2 p : {Vec2(std::nan(""), 0.0), Vec2(0.0, INFINITY), Vec2(-INFINITY, std::nan(""))})
    EXPECT_THROW((void)problem.classify(p), InputError) << p.x << ", " << p.y;
  EXPECT_NO_THROW((void)problem.classify(s.points()[2]));
}
}  // namespace cmr
