#include "bezierize/region.hpp"

#include <gtest/gtest.h>

#include <random>
#include <sstream>

#include "bezierize/analyze.hpp"
#include "bezierize/region_setup.hpp"
#include "spline/errors.hpp"
#include "tests/test_util.hpp"

namespace cmr {
namespace {

TEST(Region, PixelCentresFollowTheDocumentedFormula) {
  const View v{-1, 2, 3, 5};
  const Vec2 a = pixel_center(v, 4, 3, 0, 0);
  EXPECT_EQ(a.x, -1 + (4.0 * 0.5) / 4);
  EXPECT_EQ(a.y, 5 - (3.0 * 0.5) / 3);
  const Vec2 b = pixel_center(v, 4, 3, 3, 2);
  EXPECT_EQ(b.x, -1 + (4.0 * 3.5) / 4);
  EXPECT_EQ(b.y, 5 - (3.0 * 2.5) / 3);
}

TEST(Region, DefaultViewContainsThePolygonWithSquarePixels) {
  const BSpline s = BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7}, {{0, 0}, {1, 2}, {3, 3}, {5, 2.5}, {6.5, 1}, {7, -1}});
  const View v = default_view(s, 400, 200);
  for (const Vec2& p : s.points()) {
    EXPECT_GT(p.x, v.x0);
    EXPECT_LT(p.x, v.x1);
    EXPECT_GT(p.y, v.y0);
    EXPECT_LT(p.y, v.y1);
  }
  EXPECT_NEAR((v.x1 - v.x0) / 400, (v.y1 - v.y0) / 200, 1e-12);
}

TEST(Region, InvalidOptionsAreInputErrors) {
  const BSpline s = BSpline::bezier({{0, 0}, {1, 1}, {2, 0}, {3, 1}});
  auto bad = [&](auto tweak) {
    RegionRequest o;
    tweak(o);
    EXPECT_THROW(RegionProblem::make(s, o), InputError);
  };
  bad([](RegionRequest& o) { o.point = 4; });
  bad([](RegionRequest& o) { o.point = -1; });
  bad([](RegionRequest& o) { o.width = 0; });
  bad([](RegionRequest& o) { o.height = kMaxImageSize + 1; });
  bad([](RegionRequest& o) { o.split = 1; });  // one segment: no joint
  bad([](RegionRequest& o) { o.max_depth = 31; });
  bad([](RegionRequest& o) { o.with = {0}; });  // the moved point itself
  bad([](RegionRequest& o) { o.view = View{1, 0, 0, 1}; });
}

// The same curve at a higher degree has the same curvature, so for every
// position of the moved point the label agrees (or one of them is undecided:
// Algorithm 1's subdivision sees different coefficients).
TEST(Region, DegreeElevatedCurveKeepsItsRegion) {
  const BSpline cubic = test::class_a_bezier(3, -0.4, 1.3);
  RegionRequest o;
  o.point = 0;
  o.width = 40;
  o.height = 40;
  const RegionResult img = CpuRegionBackend().render(RegionProblem::make(cubic, o));
  int compared = 0, in_region = 0;
  for (int j = 0; j < o.height; j += 3)
    for (int i = 0; i < o.width; i += 3) {
      const Vec2 p = pixel_center(img.view, o.width, o.height, i, j);
      std::vector<Vec2> P = cubic.points();
      P[0] = p;
      // Exact elevation in rationals would change nothing; in double the
      // elevated points round, so compare only where both are decided.
      std::vector<Vec2> E(5);
      E[0] = P[0];
      E[4] = P[3];
      for (int k = 1; k <= 3; ++k) E[k] = (k / 4.0) * P[k - 1] + (1 - k / 4.0) * P[k];
      const SplineAnalysis a = analyze(BSpline::bezier(E));
      const int elevated = detail::label_of(a.cmrwi), original = code(img.labels[j * o.width + i]);
      if (elevated == 3 || original == 3) continue;
      EXPECT_EQ(elevated, original) << "pixel (" << i << ", " << j << ")";
      ++compared;
      in_region += original != 0;
    }
  EXPECT_GT(compared, 150);
  EXPECT_GT(in_region, 5) << "the scene must contain part of the region";
}

// fold_fixed_runs against part_verdict over the full lists: random classes,
// jumps, needed masks and splits (seeded); the needed segments and their
// joints are then re-filled at random as a position would, and the template
// must give the same verdict and the same deepest level in both modes.
TEST(Region, FoldedVerdictEqualsTheFullOne) {
  std::mt19937 rng(20241123);
  auto pick = [&](int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng); };
  const Curvature curvatures[] = {Curvature::increasing, Curvature::decreasing, Curvature::non_monotone,
                                  Curvature::undecided, Curvature::constant};
  const Inflection inflections[] = {Inflection::none, Inflection::none, Inflection::none, Inflection::present,
                                    Inflection::undecided};
  auto random_class = [&] {
    SegmentClass c;
    // Mostly monotone, so that most verdicts are not simply "none".
    c.monotonicity.curvature = pick(3) ? curvatures[pick(2)] : curvatures[pick(5)];
    c.monotonicity.depth = pick(6);
    c.inflection.inflection = pick(3) ? Inflection::none : inflections[pick(5)];
    c.inflection.depth = pick(6);
    c.inflection.kappa_sign = c.inflection.inflection == Inflection::none ? (pick(6) ? 1 : pick(3) - 1) : 0;
    return c;
  };
  auto random_jump = [&] { return pick(4) ? 0 : (pick(2) ? 1 : -1); };
  auto depth_of = [](const std::vector<SegmentClass>& v, Mode mode) {
    int d = 0;
    for (const SegmentClass& c : v)
      d = std::max({d, c.monotonicity.depth, mode == Mode::cmr ? c.inflection.depth : 0});
    return d;
  };
  int cases = 0, not_none = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const int N = 1 + pick(14);
    const Mode mode = pick(2) ? Mode::cmr : Mode::cmrwi;
    const int split = N > 1 && pick(2) ? 1 + pick(N - 1) : 0;
    std::vector<SegmentClass> classes(N);
    std::vector<Joint> joints(N - 1);
    std::vector<bool> needed(N);
    for (auto& c : classes) c = random_class();
    for (int j = 0; j < N - 1; ++j) joints[j].index = j + 1, joints[j].jump = random_jump();
    for (int i = 0; i < N; ++i) needed[i] = pick(4) == 0;
    const detail::VerdictTemplate t = detail::fold_fixed_runs(classes, joints, needed, split, mode);
    ASSERT_EQ(t.joints.size() + 1, t.classes.size());
    for (int fill = 0; fill < 8; ++fill) {
      std::vector<SegmentClass> full = classes, folded = t.classes;
      std::vector<Joint> full_joints = joints, folded_joints = t.joints;
      for (int i = 0; i < N; ++i) {
        if (!needed[i]) continue;
        full[i] = folded[t.slot[i]] = random_class();
        if (i > 0 && i != split) full_joints[i - 1].jump = folded_joints[t.slot[i] - 1].jump = random_jump();
      }
      std::ostringstream what;
      what << "trial " << trial << " fill " << fill << ": N " << N << ", split " << split << ", mode "
           << (mode == Mode::cmr ? "cmr" : "cmrwi") << ", needed";
      for (int i = 0; i < N; ++i) what << ' ' << needed[i];
      if (split) {
        const Split want = combine_split(part_verdict(full, full_joints, 0, split, mode),
                                         part_verdict(full, full_joints, split, N, mode));
        const Split got = combine_split(part_verdict(folded, folded_joints, 0, t.split, mode),
                                        part_verdict(folded, folded_joints, t.split, static_cast<int>(folded.size()), mode));
        ASSERT_EQ(to_string(got), std::string(to_string(want))) << what.str();
        not_none += want != Split::none;
      } else {
        const Direction want = part_verdict(full, full_joints, 0, N, mode);
        const Direction got = part_verdict(folded, folded_joints, 0, static_cast<int>(folded.size()), mode);
        ASSERT_EQ(to_string(got), std::string(to_string(want))) << what.str();
        not_none += want != Direction::none;
      }
      ASSERT_EQ(depth_of(folded, mode), depth_of(full, mode)) << what.str();
      ++cases;
    }
  }
  EXPECT_GT(not_none, cases / 10) << "the random cases must exercise monotone verdicts too";
}

// The problems of make_each (one analysis shared by all points, folded
// verdicts) label every position as analyze() labels the moved spline. The
// spline is Fig. 9(b) refined (`cmr knots examples/figures/fig9b.json
// refine`): six segments, increasing curvature, so every point's
// neighbourhood holds monotone positions; each view is a square around P_k.
TEST(Region, MakeEachAgreesWithAnalyzeOfTheMovedSpline) {
  const BSpline s = BSpline::make(3, {0, 0, 0, 0.5, 1, 1.5, 2, 2.5, 3, 3, 3},
                                  {{0.0, 0.0}, {0.165, 0.0}, {0.565, -0.0675}, {1.3675000000000002, -0.44812499999999994},
                                   {2.3649999999999998, -1.1849999999999996}, {3.559375, -2.3587499999999997},
                                   {4.952499999999999, -4.050000000000001}, {6.01, -5.58}, {6.57, -6.46}});
  std::vector<int> points(s.point_count());
  for (int k = 0; k < s.point_count(); ++k) points[k] = k;
  for (const std::optional<int> split : {std::optional<int>{}, std::optional<int>{3}}) {
    for (const Mode mode : {Mode::cmrwi, Mode::cmr}) {
      int monotone = 0;
      for (int k = 0; k < s.point_count(); ++k) {
        RegionRequest o;
        o.width = o.height = 8;
        o.mode = mode;
        o.split = split;
        const Vec2 c = s.points()[k];
        o.view = View{c.x - 0.3, c.y - 0.3, c.x + 0.3, c.y + 0.3};
        const std::vector<RegionProblem> problems = RegionProblem::make_each(s, o, points);
        ASSERT_EQ(problems.size(), points.size());
        EXPECT_EQ(problems[k].request().point, k);
        for (int j = 0; j < o.height; ++j)
          for (int i = 0; i < o.width; ++i) {
            const Vec2 p = pixel_center(*o.view, o.width, o.height, i, j);
            AnalyzeOptions ao;
            ao.split = split;
            ao.split_mode = mode;
            const SplineAnalysis a = analyze(s.with_point(k, p), ao);
            const RegionPixel px = problems[k].classify(p);
            if (split) {
              EXPECT_EQ(to_string(px.split_label), std::string(to_string(*a.split)))
                  << "P" << k << " pixel (" << i << ", " << j << ")";
              monotone += px.split_label != SplitLabel::none;
            } else {
              const Direction want = mode == Mode::cmr ? a.cmr : a.cmrwi;
              EXPECT_EQ(detail::label_of(want), code(px.label)) << "P" << k << " pixel (" << i << ", " << j << ")";
              monotone += px.label != RegionLabel::not_monotone;
            }
          }
      }
      EXPECT_GT(monotone, 10) << "the scenes must contain regions";
    }
  }
}
}  // namespace
}  // namespace cmr
