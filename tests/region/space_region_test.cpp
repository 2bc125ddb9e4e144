// Regions of a point of a space curve moving in a plane
// (region/space_region.hpp, issue 25).
#include "region/space_region.hpp"

#include <gtest/gtest.h>

#include <random>

#include "bezierize/analyze.hpp"
#include "bezierize/space_classify.hpp"
#include "spline/errors.hpp"

namespace cmr {
namespace {

// examples/figures/fig8.json (the paper's Fig. 8), lifted off its plane by z.
const std::vector<Vec2> kFig8 = {{1.3, -1.43}, {1.05, -0.06}, {2.15, -1.31}, {1.97, -3.83}, {-2.23, -6.95}, {-6.78, -9.78}};
const std::vector<double> kFig8Knots = {0, 1, 2, 3, 4, 5, 6, 7};

SpaceSpline fig8_lifted(const std::vector<double>& z, const std::vector<double>& weights = {}) {
  std::vector<Vec3> p;
  for (std::size_t i = 0; i < kFig8.size(); ++i) p.emplace_back(kFig8[i].x, kFig8[i].y, z[i]);
  return SpaceSpline::make(3, kFig8Knots, p, "", weights);
}
const std::vector<double> kWeights = {1, 1.03125, 0.96875, 1.0625, 1, 1.03125};

void expect_same_labels(const RegionResult& a, const RegionResult& b, const std::string& what) {
  ASSERT_EQ(a.labels.size(), b.labels.size()) << what;
  int diff = 0;
  for (std::size_t i = 0; i < a.labels.size(); ++i) diff += a.labels[i] != b.labels[i];
  EXPECT_EQ(diff, 0) << what;
}

// Two neighbouring pixels with different labels, bisected along their row
// down to the boundary, as a tiny view around it (a near-boundary zoom);
// nullopt when the image has one label.
std::optional<View> boundary_zoom(const SpaceRegionProblem& problem, const RegionResult& img, double half_width) {
  for (int j = 0; j < img.height; ++j)
    for (int i = 0; i + 1 < img.width; ++i) {
      const std::size_t k = static_cast<std::size_t>(j) * img.width + i;
      if (img.labels[k] == img.labels[k + 1]) continue;
      Vec2 p = pixel_center(img.view, img.width, img.height, i, j);
      Vec2 q = pixel_center(img.view, img.width, img.height, i + 1, j);
      const Direction lp = img.labels[k];
      for (int it = 0; it < 60; ++it) {
        const Vec2 m = 0.5 * (p + q);
        (problem.classify(m.x, m.y).label == lp ? p : q) = m;
      }
      const Vec2 c = 0.5 * (p + q);
      return View{c.x - half_width, c.y - half_width, c.x + half_width, c.y + half_width};
    }
  return std::nullopt;
}

void labels_agree_with_exact_arithmetic(const std::vector<double>& weights, std::uint64_t seed, int size) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  int zooms = 0, mixed = 0;
  std::uint64_t exact = 0;
  for (int trial = 0; trial < 6; ++trial) {
    std::vector<double> z(6);
    for (double& x : z) x = trial == 0 ? 0.0 : u(rng);
    const SpaceSpline s = fig8_lifted(z, weights);
    SpaceRegionRequest r;
    r.point = 3;
    r.plane = SpacePlane{s.points()[3], {1, u(rng), u(rng)}, {u(rng), 1, u(rng)}};
    r.width = r.height = size;
    r.view = View{-0.5, -0.5, 0.5, 0.5};
    const RegionResult fast = SpaceRegionProblem::make(s, r).render(1);
    SpaceRegionRequest e = r;
    e.exact_only = true;
    expect_same_labels(fast, SpaceRegionProblem::make(s, e).render(1), "trial " + std::to_string(trial));
    bool several = false;
    for (Direction l : fast.labels) several = several || l != fast.labels[0];
    mixed += several;
    if (const auto zoom = boundary_zoom(SpaceRegionProblem::make(s, r), fast, 1e-12)) {
      r.view = e.view = zoom;
      r.width = r.height = e.width = e.height = 8;
      const RegionResult zf = SpaceRegionProblem::make(s, r).render(1);
      expect_same_labels(zf, SpaceRegionProblem::make(s, e).render(1), "zoom of trial " + std::to_string(trial));
      bool two = false;
      for (Direction l : zf.labels) two = two || l != zf.labels[0];
      zooms += two;
      exact += zf.exact_pixels;
    }
  }
  EXPECT_GE(mixed, 4);
  EXPECT_GE(zooms, 2);  // zooms that still straddle the boundary
  EXPECT_GT(exact, 0u);  // and there the exact fallback decided pixels
}

TEST(SpaceRegion, LabelsAgreeWithExactArithmeticOnSeededPlanesAndNearBoundaryZooms) {
  labels_agree_with_exact_arithmetic({}, 250, 20);
}

TEST(RationalSpaceRegion, LabelsAgreeWithExactArithmeticOnSeededPlanesAndNearBoundaryZooms) {
  // (Smaller images: the exact-only reference of a rational cubic works on
// lambda3r of degree 15 in GMP.)
  labels_agree_with_exact_arithmetic(kWeights, 251, 12);
}

void pixel_label_is_analyze_space(const std::vector<double>& weights) {
  // Dyadic plane and view: every pixel's point O + a U + b V is a double, so
  // the moved spline exists and analyze_space states the label.
  const SpaceSpline s = fig8_lifted({0, 0.125, -0.25, 0.25, 0.5, 0}, weights);
  SpaceRegionRequest r;
  r.point = 3;
  r.plane = SpacePlane{{2, -3.75, 0.25}, {1, 0, 0.125}, {0, 1, -0.0625}};
  r.width = r.height = 16;
  r.view = View{-0.5, -0.625, 0.5, 0.375};
  const SpaceRegionProblem p = SpaceRegionProblem::make(s, r);
  const RegionResult img = p.render(1);
  int monotone = 0;
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i) {
      const Vec2 c = pixel_center(*r.view, 16, 16, i, j);
      const Vec3 q = r.plane->origin + c.x * r.plane->u + c.y * r.plane->v;
      const SpaceAnalysis a = analyze_space(s.with_point(3, q));
      Direction want = Direction::undecided;
      if (a.curvature == Direction::increasing) want = Direction::increasing;
      if (a.curvature == Direction::decreasing) want = Direction::decreasing;
      if (a.curvature == Direction::none) want = Direction::none;
      EXPECT_EQ(img.labels[static_cast<std::size_t>(j) * 16 + i], want) << "pixel " << i << "," << j;
      monotone += want == Direction::increasing || want == Direction::decreasing;
    }
  EXPECT_GT(monotone, 5);
  EXPECT_LT(monotone, 256);
}

TEST(SpaceRegion, PixelLabelIsAnalyzeSpaceOfTheMovedSpline) { pixel_label_is_analyze_space({}); }

// The moved point keeps its weight: each pixel is analyze_space of the
// rational spline with point 3 at Q.
TEST(RationalSpaceRegion, PixelLabelIsAnalyzeSpaceOfTheMovedSpline) { pixel_label_is_analyze_space(kWeights); }

TEST(SpaceRegion, ClosedSplineMovesThePointAndItsTwin) {
  const SpaceSpline s = SpaceSpline::make_closed(3, {0, 1, 2, 3, 4, 5},
                                                 {{2, 0, 0}, {0.5, 1.5, 0.5}, {-1.5, 1, 1}, {-1.5, -1, 0.5}, {0.5, -1.5, 0}});
  SpaceRegionRequest r;
  r.point = 0;  // its twin in the unrolled form moves with it
  r.plane = SpacePlane{{2, 0, 0}, {1, 0, 0.5}, {0, 1, 0.25}};
  r.width = r.height = 8;
  r.view = View{-1, -1, 1, 1};
  const RegionResult img = SpaceRegionProblem::make(s, r).render(1);
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i) {
      const Vec2 c = pixel_center(*r.view, 8, 8, i, j);
      const SpaceAnalysis a = analyze_space(s.with_point(0, r.plane->origin + c.x * r.plane->u + c.y * r.plane->v));
      const Direction want = a.curvature == Direction::none        ? Direction::none
                               : a.curvature == Direction::undecided ? Direction::undecided
                               : a.curvature == Direction::increasing ? Direction::increasing
                                                                      : Direction::decreasing;
      EXPECT_EQ(img.labels[static_cast<std::size_t>(j) * 8 + i], want) << "pixel " << i << "," << j;
    }
}

// A planar spline in its own plane: the plane's region labels, read for |kappa|.
void planar_curve_gives_the_planes_labels(const BSpline& plane) {
  const SpaceSpline s = SpaceSpline::embed(plane);
  const int W = 24;
  SpaceRegionRequest r;
  r.point = 3;
  r.plane = SpacePlane{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  r.view = View{1.5, -4.3, 2.5, -3.3};
  r.width = r.height = W;
  r.max_depth = 10;
  const RegionResult img = SpaceRegionProblem::make(s, r).render(1);
  RegionRequest q;
  q.point = 3;
  q.width = q.height = W;
  q.view = img.view;
  q.max_depth = 10;
  CpuRegionBackend cpu(1);
  const RegionResult cmrwi = cpu.render(RegionProblem::make(plane, q));
  q.mode = Mode::cmr;
  const RegionResult cmr = cpu.render(RegionProblem::make(plane, q));
  int compared = 0, monotone = 0;
  for (int j = 0; j < W; ++j)
    for (int i = 0; i < W; ++i) {
      const std::size_t k = static_cast<std::size_t>(j) * W + i;
      const Direction got = img.labels[k];
      if (got == Direction::undecided || cmrwi.labels[k] == Direction::undecided ||
          cmr.labels[k] == Direction::undecided)
        continue;
      ++compared;
      if (cmrwi.labels[k] == Direction::none) {
        EXPECT_EQ(got, Direction::none) << "pixel " << i << "," << j;
      } else if (cmr.labels[k] == Direction::none) {
        EXPECT_EQ(got, Direction::none) << "pixel " << i << "," << j << " (an inflection: |kappa| has a minimum)";
      } else {
        const Vec2 c = pixel_center(img.view, W, W, i, j);
        const SplineAnalysis a = analyze(plane.with_point(3, c));
        const int sign = a.shapes[0].kappa_sign;
        Direction want = cmr.labels[k];
        if (sign < 0) want = want == Direction::increasing ? Direction::decreasing : Direction::increasing;
        EXPECT_EQ(got, want) << "pixel " << i << "," << j;
        ++monotone;
      }
    }
  EXPECT_GT(compared, W * W / 2);
  EXPECT_GT(monotone, 10);
}

TEST(SpaceRegion, PlanarCurveInItsOwnPlaneGivesThePlanesLabels) {
  planar_curve_gives_the_planes_labels(BSpline::make(3, kFig8Knots, kFig8));
}

TEST(RationalSpaceRegion, PlanarRationalCurveInItsOwnPlaneGivesThePlanesLabels) {
  planar_curve_gives_the_planes_labels(BSpline::make(3, kFig8Knots, kFig8, "", kWeights));
}

// rational_lambda3 (the Vulkan backend's input): each polynomial, at seeded
// offsets, is the exact lambda3 coefficient of the moved curve within the
// bound its rounded terms carry, and it has 21 terms (degree 5).
TEST(RationalSpaceRegion, Lambda3PolynomialsInThePlaneAreTheExactCoefficients) {
  const SpaceSpline s = fig8_lifted({0, 0.3, 0.8, 1.5, 2.4, 3.5}, {1, 1.5, 0.7, 1.2, 2, 1});
  SpaceRegionRequest r;
  r.point = 3;
  r.plane = SpacePlane{s.points()[3], {1, 0.25, 0}, {0, 1, -0.5}};
  r.width = r.height = 4;
  const SpaceRegionProblem p = SpaceRegionProblem::make(s, r);
  const double a0 = 0.375, b0 = -0.25;
  std::mt19937_64 rng(31);
  std::uniform_int_distribution<int> u(-64, 64);
  ASSERT_EQ(p.moved_segments().size(), 3u);
  for (const int seg : p.moved_segments()) {
    const auto polys = p.rational_lambda3(seg, a0, b0);
    ASSERT_EQ(polys.size(), 11u * 3 - 17) << seg;
    const SpaceWindow w = space_window(s, s.segments()[static_cast<std::size_t>(seg)]);
    for (int trial = 0; trial < 4; ++trial) {
      const Rational x(u(rng), 64), y(u(rng), 64);  // offsets from (a0, b0)
      const Rational a = Rational(a0) + x, b = Rational(b0) + y;
      const SpacePlane& pl = *r.plane;
      const auto c = [&](double o, double du, double dv) {
        return Rational(Rational(o) + a * Rational(du) + b * Rational(dv));
      };
      const Point3<Rational> q{c(pl.origin.x, pl.u.x, pl.v.x), c(pl.origin.y, pl.u.y, pl.v.y),
                               c(pl.origin.z, pl.u.z, pl.v.z)};
      std::vector<HPoint3<Rational>> H = space_window_hpoints<Rational>(s, w);
      for (int i = 0; i <= 3; ++i)
        if (w.first + i == 3) H[static_cast<std::size_t>(i)] = to_hpoint3<Rational>(q, s.weight(3));
      const Bernstein<Rational> exact = lambda3_bernstein<Rational>(space_window_bezier<Rational>(w, H));
      ASSERT_EQ(exact.size(), polys.size());
      for (std::size_t k = 0; k < exact.size(); ++k) {
        ASSERT_EQ(polys[k].degree, 5);
        ASSERT_EQ(polys[k].terms.size(), 21u);
        Rational v(0), bound(0);
        std::size_t t = 0;
        for (int i = 0; i <= 5; ++i)
          for (int j = 0; i + j <= 5; ++j, ++t) {
            Rational m(1);
            for (int e = 0; e < i; ++e) m *= x;
            for (int e = 0; e < j; ++e) m *= y;
            v += Rational(polys[k].terms[t][0]) * m;
            bound += Rational(polys[k].terms[t][1]) * abs(m);
          }
        EXPECT_LE(abs(Rational(v - exact[k])), bound) << "segment " << seg << " coefficient " << k;
        EXPECT_LE(bound, abs(exact[k]) * Rational(1, 1 << 20) + Rational(1, 1 << 30)) << "segment " << seg;
      }
    }
  }
}

TEST(SpaceRegion, BadPlanesAndRequestsAreInputErrors) {
  const SpaceSpline s = SpaceSpline::bezier({{0, 0, 0}, {1, 1, 0}, {2, 2, 0}, {3, 1, 1}});
  const auto message = [&](auto f) {
    try {
      f();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message([] { parse_space_plane("0,0,0,1,0,0,2,0,0", Vec3(0.0)); }),
            "plane: U and V are parallel (the plane is degenerate)");  // fields by name: spline/fields.hpp
  EXPECT_EQ(message([] { parse_space_plane("0,0,0,1,0,0", Vec3(0.0)); }),
            "plane: 6 numbers given, expected 9 (OX,OY,OZ,UX,UY,UZ,VX,VY,VZ), or xy, yz, zx");
  EXPECT_EQ(message([] { parse_space_plane("0,0,x,1,0,0,0,1,0", Vec3(0.0)); }),
            "plane: 'x' is not a number (expected xy, yz, zx or OX,OY,OZ,UX,UY,UZ,VX,VY,VZ)");
  EXPECT_EQ(parse_space_plane("yz", Vec3(1, 2, 3)).origin, Vec3(1, 2, 3));
  // Point 1's neighbours 0 and 2 are collinear with it.
  EXPECT_EQ(message([&] { default_space_plane(s, 1); }),
            "the default plane of point 1 is degenerate (its neighbours are collinear with it); give plane");
  SpaceRegionRequest r;
  r.point = 4;
  EXPECT_EQ(message([&] { SpaceRegionProblem::make(s, r); }), "point 4 is outside 0..3");
}

}  // namespace
}  // namespace cmr
