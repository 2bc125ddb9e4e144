// Space curves from Wavefront OBJ (io/obj.hpp, issue 25).
#include "io/obj.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>

#include "spline/errors.hpp"
#include "spline/spline_json.hpp"

namespace cmr::import {
namespace {

const std::string kVertices = R"(# a helix-like polygon
v 1 0 0
v 1 1 0.25
v 0 1.5 0.5
v -1 1 0.75
v -1.5 0 1
v -1 -1 1.25
)";

TEST(ObjCurves, FreeFormBSplineReadsKnotsAndPoints) {
  const auto curves = parse_obj_curves(kVertices + R"(o helix
cstype bspline
deg 3
curv 0 3 1 2 3 4 5 6
parm u 0 0 0 0 1 2 3 3 3 3
end
)",
                                       "t.obj");
  ASSERT_EQ(curves.size(), 1u);
  const SpaceSpline& s = curves[0].spline;
  EXPECT_EQ(curves[0].kind, "curv");
  EXPECT_EQ(curves[0].line, 11);
  EXPECT_EQ(s.name(), "helix");
  EXPECT_EQ(s.degree(), 3);
  EXPECT_EQ(s.knots(), (std::vector<double>{0, 0, 0, 1, 2, 3, 3, 3}));
  EXPECT_EQ(s.points()[2], Vec3(0, 1.5, 0.5));
  EXPECT_EQ(s.segment_count(), 3);
  EXPECT_LT(glm::length(evaluate(s, 0) - Vec3(1, 0, 0)), 1e-15);  // clamped: starts at the first point
}

TEST(ObjCurves, RationalWithEqualWeightsBezierPiecesNegativeIndicesAndPolylines) {
  // A rat curve's vertices carry w (`v x y z w`); equal weights are the
  // polynomial curve, read without weights.
  const auto curves = parse_obj_curves(kVertices + R"(v -1 1 0.75 2
v -1.5 0 1 2
v -1 -1 1.25 2
v 2 2 2 2
cstype rat bspline
deg 2
curv 0 2 -4 -3 -2 -1
parm u 0 0 0 1 2 2 2
end
cstype bezier
deg 2
curv 0 2 1 2 3 4 5
parm u 0 1 2
end
l 1 2 3 4/1 5
)",
                                       "t.obj");
  ASSERT_EQ(curves.size(), 3u);
  EXPECT_EQ(curves[0].spline.points()[3], Vec3(2, 2, 2));  // -1: the last vertex so far
  EXPECT_FALSE(curves[0].spline.is_rational());
  EXPECT_TRUE(curves[0].spline.weights().empty());
  EXPECT_EQ(curves[1].spline.knots(), (std::vector<double>{0, 0, 1, 1, 2, 2}));
  EXPECT_EQ(curves[1].spline.segment_count(), 2);
  EXPECT_EQ(curves[2].kind, "l");
  EXPECT_EQ(curves[2].spline.degree(), 3);
  EXPECT_EQ(curves[2].spline.point_count(), 5);
}

// examples/space/rational.obj holds fig8b_lifted_rational.json as a rat
// bspline: the same points, weights and knots, exactly.
TEST(ObjCurves, RationalWithUnequalWeightsEqualsTheSplineFile) {
  const std::string dir = std::string(CMR_SOURCE_DIR) + "/examples/";
  const auto curves = read_obj_curves(dir + "space/rational.obj");
  ASSERT_EQ(curves.size(), 2u);
  const SpaceSpline want = read_space_spline_file(dir + "space/fig8b_lifted_rational.json");
  const SpaceSpline& got = curves[0].spline;
  EXPECT_EQ(got.name(), want.name());
  EXPECT_TRUE(got.is_rational());
  EXPECT_EQ(got.degree(), want.degree());
  EXPECT_EQ(got.knots(), want.knots());
  EXPECT_EQ(got.points(), want.points());
  EXPECT_EQ(got.weights(), want.weights());
  EXPECT_EQ(got.weights(), (std::vector<double>{1, 1.05, 0.95, 1.1, 1, 1.2}));
  EXPECT_EQ(got.closed(), want.closed());
  for (double t : {2.0, 2.5, 3.25, 4.0, 4.9, 5.0}) EXPECT_EQ(evaluate(got, t), evaluate(want, t)) << t;
}

// The quarter circle (weights 1, sqrt(2)/2, 1 as the decimal a file holds)
// in the plane z = 0: its planar shadow is examples/rational/quarter_circle.json.
TEST(ObjCurves, RationalQuarterCircleIsThePlanarRationalFile) {
  const std::string dir = std::string(CMR_SOURCE_DIR) + "/examples/";
  const auto curves = read_obj_curves(dir + "space/rational.obj");
  ASSERT_EQ(curves.size(), 2u);
  const SpaceSpline& got = curves[1].spline;
  EXPECT_EQ(got.name(), "quarter-circle");
  EXPECT_EQ(got.weights(), (std::vector<double>{1, 0.7071067811865476, 1}));
  EXPECT_EQ(got.weights()[1], std::sqrt(2.0) / 2);  // the decimal is the double nearest sqrt(2)/2
  const BSpline want = read_spline_file(dir + "rational/quarter_circle.json");
  EXPECT_EQ(got.shadow().degree(), want.degree());
  EXPECT_EQ(got.shadow().knots(), want.knots());
  EXPECT_EQ(got.shadow().points(), want.points());
  EXPECT_EQ(got.shadow().weights(), want.weights());
  for (const Vec3& p : got.points()) EXPECT_EQ(p.z, 0.0);
}

void expect_error(const std::string& body, const std::string& want) {
  try {
    parse_obj_curves(kVertices + body, "t.obj");
    ADD_FAILURE() << "no error for " << body;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), want) << body;
  }
}

// The spec: a vertex's w defaults to 1.0, also for the vertices of a rat curve.
TEST(ObjCurves, RatVertexWithoutWHasWeightOne) {
  const auto curves = parse_obj_curves(
      "v 3 3 3\nv 4 3 3 2\nv 5 4 3 1\ncstype rat bspline\ndeg 2\ncurv 0 1 1 2 3\nparm u 0 0 0 1 1 1\nend\n", "t.obj");
  ASSERT_EQ(curves.size(), 1u);
  EXPECT_EQ(curves[0].spline.weights(), (std::vector<double>{1, 2, 1}));
  const auto equal = parse_obj_curves(
      "v 3 3 3\nv 4 3 3\nv 5 4 3 1\ncstype rat bspline\ndeg 2\ncurv 0 1 1 2 3\nparm u 0 0 0 1 1 1\nend\n", "t.obj");
  ASSERT_EQ(equal.size(), 1u);
  EXPECT_TRUE(equal[0].spline.weights().empty()) << "weights 1, 1, 1 are the polynomial curve";
}

TEST(ObjCurves, BadInputNamesFileAndLine) {
  expect_error("", "t.obj: no curves (cstype/curv or l elements)");
  expect_error("cstype bspline\ndeg 3\ncurv 0 3 1 2 3 4 5 9\nparm u 0 0 0 0 1 2 3 3 3 3\nend\n",
               "t.obj:10: curv: vertex 9 is outside 1..6 (or -1..-6)");
  expect_error("cstype bspline\ndeg 3\ncurv 0 3 1 2 3 4 5 6\nparm u 0 0 0 1 2 3 3 3\nend\n",
               "t.obj:10: parm u: 8 knots for 6 control points of degree 3 (expected points + degree + 1 = 10)");
  expect_error("cstype bspline\ndeg 3\ncurv 0 2 1 2 3 4 5 6\nparm u 0 0 0 0 1 2 3 3 3 3\nend\n",
               "t.obj:10: curv: the range [0, 2] is not the curve's domain [0, 3] (trimmed curves are not supported)");
  expect_error("cstype rat bspline\ndeg 2\ncurv 0 1 1 2 7\nparm u 0 0 0 1 1 1\nend\nv 0 0 0\n",
               "t.obj:10: curv: vertex 7 is outside 1..6 (or -1..-6)");
  // rat curves: every vertex's w must be positive (the error names the curv line and the vertex's line)
  expect_error("v 3 3 3 2\nv 4 3 3 0\nv 5 3 3 1\ncstype rat bspline\ndeg 2\ncurv 0 1 7 8 9\nparm u 0 0 0 1 1 1\nend\n",
               "t.obj:13: curv: vertex 8 (line 9) has weight 0: rational curves need positive weights");
  expect_error("v 3 3 3 2\nv 4 3 3 -0.5\nv 5 3 3 1\ncstype rat bezier\ndeg 2\ncurv 0 1 7 8 9\nend\n",
               "t.obj:13: curv: vertex 8 (line 9) has weight -0.5: rational curves need positive weights");
  expect_error("cstype taylor\n", "t.obj:8: cstype taylor: only bspline and bezier curves are read (not taylor)");
  expect_error("l 1 2\n", "t.obj:8: l: a polyline needs at least 3 vertices to be a control polygon (got 2)");
  expect_error("v 1 x 2\n", "t.obj:8: v: 'x' is not a finite number");
  expect_error("cstype bspline\ndeg 3\ncurv 0 3 1 2 3 4 5 6\n", "t.obj:10: curv: no 'end' statement");
  // A name that is not UTF-8 cannot go into JSON (fuzz_obj's finding: exit 3, "unexpected error").
  expect_error("o bad\xffname\n", "t.obj:8: o: the name is not UTF-8");
  expect_error("g \xc3\n", "t.obj:8: g: the name is not UTF-8");
}

}  // namespace
}  // namespace cmr::import
