// Space curves below the CLI (spline/space.hpp, issue 25).
#include "spline/space.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "spline/errors.hpp"

namespace cmr {
namespace {

using nlohmann::json;

std::vector<Vec3> random_points3(std::mt19937_64& rng, int count) {
  std::uniform_real_distribution<double> u(-2, 2);
  std::vector<Vec3> p(count);
  for (Vec3& q : p) q = Vec3(u(rng), u(rng), u(rng));
  return p;
}

TEST(SpaceSpline, PlanarEmbeddingEvaluatesLikeThePlanarSpline) {
  const BSpline s = BSpline::make(3, {0, 0, 0, 1, 2.5, 3, 3, 3}, {{0, 0}, {1, 2}, {3, 3}, {5, 2.5}, {6.5, 1}, {7, -1}});
  const SpaceSpline e = SpaceSpline::embed(s);
  ASSERT_EQ(e.segment_count(), s.segment_count());
  for (double t = 0; t <= 3; t += 0.125) {
    for (int r = 0; r <= 3; ++r) {
      const Vec2 a = derivative(s, t, r);
      const Vec3 b = derivative(e, t, r);
      EXPECT_NEAR(b.x, a.x, 1e-12 * (1 + std::fabs(a.x))) << "t=" << t << " r=" << r;
      EXPECT_NEAR(b.y, a.y, 1e-12 * (1 + std::fabs(a.y))) << "t=" << t << " r=" << r;
      EXPECT_EQ(b.z, 0.0);
    }
  }
}

TEST(SpaceSpline, DerivativesMatchFiniteDifferencesAndBezierPointsInterpolate) {
  std::mt19937_64 rng(3);
  for (int d = 2; d <= 5; ++d) {
    std::vector<double> knots;
    for (int i = 0; i < 7 + d - 1; ++i) knots.push_back(i);
    const SpaceSpline s = SpaceSpline::make(d, knots, random_points3(rng, 7));
    for (const Segment& seg : s.segments()) {
      const std::vector<Vec3> B = bezier_points(s, seg);
      EXPECT_LT(glm::length(B.front() - evaluate(s, seg.a)), 1e-12) << "d=" << d;
      EXPECT_LT(glm::length(B.back() - evaluate(s, std::nextafter(seg.b, seg.a))), 1e-9) << "d=" << d;
      const double t = 0.5 * (seg.a + seg.b), h = 1e-6;
      for (int r = 1; r <= std::min(d, 3); ++r) {
        const Vec3 fd = (derivative(s, t + h, r - 1) - derivative(s, t - h, r - 1)) / (2 * h);
        EXPECT_LT(glm::length(fd - derivative(s, t, r)), 1e-5 * (1 + glm::length(fd))) << "d=" << d << " r=" << r;
      }
    }
  }
}

TEST(SpaceSpline, HelixLikeCubicHasPositiveCurvatureAndTorsion) {
  const SpaceSpline s = SpaceSpline::bezier({{1, 0, 0}, {1, 1, 0.3}, {0, 1.5, 0.6}, {-1, 1, 0.9}});
  for (double t = 0; t <= 1; t += 0.25) {
    EXPECT_GT(space_curvature(s, t), 0) << t;
    EXPECT_GT(space_torsion(s, t), 0) << t;
  }
}

TEST(SpaceSpline, ClosedSplineEndsWhereItStartsAndMovesTwins) {
  const SpaceSpline s = SpaceSpline::make_closed(3, {0, 1, 2, 3, 4}, {{1, 0, 0}, {0, 1, 1}, {-1, 0, 0}, {0, -1, -1}});
  EXPECT_TRUE(s.closed());
  EXPECT_EQ(s.point_count(), 7);
  EXPECT_LT(glm::length(evaluate(s, 0) - evaluate(s, std::nextafter(4.0, 0.0))), 1e-12);
  const SpaceSpline m = s.with_point(1, {0, 2, 3});
  EXPECT_EQ(m.points()[1], Vec3(0, 2, 3));
  EXPECT_EQ(m.points()[5], Vec3(0, 2, 3));  // the twin of point 1 in the unrolled form
}

TEST(SpaceSplineJson, ReadsAndRoundTrips) {
  const json doc = json::parse(R"({"name":"h","degree":3,"knots":[0,0,0,1,2,3,3,3],
      "points":[[0,0,0],[1,2,0.5],[3,3,1],[5,2.5,1.5],[6.5,1,2],[7,-1,2.5]]})");
  EXPECT_EQ(spline_dimension(doc), 3);
  const SpaceSpline s = space_spline_from_json(doc);
  EXPECT_EQ(s.name(), "h");
  EXPECT_EQ(s.points()[3], Vec3(5, 2.5, 1.5));
  const SpaceSpline t = space_spline_from_json(space_spline_to_json(s));
  EXPECT_EQ(t.knots(), s.knots());
  EXPECT_EQ(t.points(), s.points());
}

TEST(SpaceSplineJson, PlanarFilesAreDimensionTwo) {
  EXPECT_EQ(spline_dimension(json::parse(R"({"points":[[0,0],[1,1],[2,0]]})")), 2);
  EXPECT_EQ(spline_dimension(json::parse(R"({"points":[]})")), 2);
  EXPECT_EQ(spline_dimension(json::parse(R"([1,2])")), 2);
}

void expect_error(const std::string& text, const std::string& want, bool dimension = false) {
  try {
    if (dimension) spline_dimension(json::parse(text));
    else space_spline_from_json(json::parse(text));
    ADD_FAILURE() << "no error for " << text;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), want) << text;
  }
}

TEST(SpaceSplineJson, BadInputNamesTheField) {
  expect_error(R"({"points":[[0,0,0],[1,1],[2,0,0]]})",
               "points[1] has 2 coordinates but points[0] has 3 (all points must be [x, y], or all [x, y, z])", true);
  expect_error(R"({"points":[[0,0],[1,1,1]]})",
               "points[1] has 3 coordinates but points[0] has 2 (all points must be [x, y], or all [x, y, z])", true);
  expect_error(R"({"points":[[0,0,0],[1,1,"a"],[2,0,0]]})", "points[1][2] is not a number");
  expect_error(R"({"points":[[0,0,0],[1,1,1],[2,0,0]],"weights":[1,2]})",
               "weights: one weight per control point is needed: 3 points, 2 weights");
  expect_error(R"({"points":[[0,0,0],[1,1,1],[2,0,0]],"weights":[1,0,1]})",
               "weights[1] is 0: rational space curves need positive weights");
  expect_error(R"({"points":[[0,0,0],[1,1,1],[2,0,0]],"weights":[-1,-2,-1]})",
               "weights[0] is -1: rational space curves need positive weights");
  expect_error(R"({"points":[[0,0,0],[1,1,1],[2,0,0]],"weights":[1,"a",1]})", "weights[1] is not a number");
  expect_error(R"({"points":[[0,0,0],["x",1,1],[2,0,0]]})", "points[1][0] is not a number");
  expect_error(R"({"degree":3,"knots":[0,1,2,3],"points":[[0,0,0],[1,1,1],[2,0,0],[3,1,1]]})",
               "knots: polar form needs points + degree - 1 = 6 knots (got 4)");
}

// A rational space curve: evaluation is the projected homogeneous blossom,
// derivatives (Leibniz on H = W C) match finite differences, the Bezier
// points interpolate, and the file round-trips with its weights.
TEST(SpaceSpline, RationalCurveEvaluatesDerivesAndRoundTrips) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> uw(0.25, 4);
  for (int d = 2; d <= 5; ++d) {
    std::vector<double> knots, w;
    for (int i = 0; i < 7 + d - 1; ++i) knots.push_back(i);
    for (int i = 0; i < 7; ++i) w.push_back(uw(rng));
    const std::vector<Vec3> P = random_points3(rng, 7);
    const SpaceSpline s = SpaceSpline::make(d, knots, P, "r", w);
    ASSERT_TRUE(s.is_rational());
    for (const Segment& seg : s.segments()) {
      const std::vector<Vec3> B = bezier_points(s, seg);
      EXPECT_LT(glm::length(B.front() - evaluate(s, seg.a)), 1e-12) << "d=" << d;
      const double t = 0.5 * (seg.a + seg.b), h = 1e-6;
      // C(t) = sum N_i w_i P_i / sum N_i w_i, from the homogeneous blossom.
      const Vec4 H = homogeneous_blossom(s, seg, std::vector<double>(d, t).data());
      EXPECT_LT(glm::length(Vec3(H.x, H.y, H.z) / H.w - evaluate(s, t)), 1e-12) << "d=" << d;
      for (int r = 1; r <= std::min(d, 3); ++r) {
        const Vec3 fd = (derivative(s, t + h, r - 1) - derivative(s, t - h, r - 1)) / (2 * h);
        EXPECT_LT(glm::length(fd - derivative(s, t, r)), 1e-5 * (1 + glm::length(fd))) << "d=" << d << " r=" << r;
      }
    }
    const SpaceSpline back = space_spline_from_json(space_spline_to_json(s));
    ASSERT_EQ(back.weights().size(), s.weights().size());
    for (std::size_t i = 0; i < w.size(); ++i) EXPECT_EQ(back.weights()[i], w[i]) << "d=" << d << " i=" << i;
    // Scaling every weight by the same factor is the same curve.
    std::vector<double> w3 = w;
    for (double& x : w3) x *= 3;
    const SpaceSpline s3 = SpaceSpline::make(d, knots, P, "r3", w3);
    for (double t = knots[d - 1]; t < knots[knots.size() - d]; t += 0.37)
      EXPECT_LT(glm::length(evaluate(s3, t) - evaluate(s, t)), 1e-12) << "d=" << d << " t=" << t;
  }
  // Equal weights are the polynomial curve.
  EXPECT_FALSE(SpaceSpline::bezier({{0, 0, 0}, {1, 1, 1}, {2, 0, 0}}, "", {2, 2, 2}).is_rational());
}

}  // namespace
}  // namespace cmr
