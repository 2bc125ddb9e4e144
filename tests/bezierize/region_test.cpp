#include "bezierize/region.hpp"

#include <gtest/gtest.h>

#include <random>

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
  bad([](RegionRequest& o) { o.segments = SegmentRange{0, 1}; });  // one segment: 0..0
  bad([](RegionRequest& o) { o.splits = {1}; });
}

// Segment control (RegionRequest::segments / splits) on a wave whose
// curvature increases on segments 0-1, decreases on 2, increases on 3
// (tests/bezierize/segments_test.cpp checks it by sampling).
BSpline wave() {
  return BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7, 8},
                       {{0.058, 0.128}, {1.274, 0.936}, {2.065, -0.298}, {3.236, -0.998}, {3.765, 0.132},
                        {5.069, -0.719}, {6.078, 0.783}});
}

TEST(Region, SegmentRangesAndSplitsAreValidated) {
  const BSpline s = wave();  // 4 segments
  auto bad = [&](auto tweak, const char* why) {
    RegionRequest o;
    o.point = 3;
    tweak(o);
    EXPECT_THROW(RegionProblem::make(s, o), InputError) << why;
  };
  bad([](RegionRequest& o) { o.segments = SegmentRange{2, 1}; }, "reversed range");
  bad([](RegionRequest& o) { o.segments = SegmentRange{1, 4}; }, "past the last segment");
  bad([](RegionRequest& o) { o.segments = SegmentRange{1, 3}, o.split = 1; }, "split at the range's start");
  bad([](RegionRequest& o) { o.segments = SegmentRange{0, 2}, o.splits = {1, 3}; }, "split past the range");
  bad([](RegionRequest& o) { o.splits = {3, 2}; }, "splits not increasing");
  bad([](RegionRequest& o) { o.split = 2, o.splits = {3}; }, "split and splits together");
  RegionRequest ok;
  ok.point = 3;
  ok.segments = SegmentRange{1, 3};
  ok.splits = {2, 3};
  EXPECT_NO_THROW(RegionProblem::make(s, ok));
}

TEST(Region, OnlyTheJudgedSegmentsArePrepared) {
  const BSpline s = wave();
  RegionRequest o;
  o.point = 3;  // touches segments 0..3
  o.segments = SegmentRange{1, 2};
  const RegionProblem p = RegionProblem::make(s, o);
  ASSERT_FALSE(p.setup().entries.empty());
  for (const detail::RegionEntry& e : p.setup().entries) {
    EXPECT_GE(e.segment, 1);
    EXPECT_LE(e.segment, 2);
  }
  o.point = 0;  // touches segment 0 only: nothing to prepare
  EXPECT_TRUE(RegionProblem::make(s, o).setup().entries.empty());
}

// Moving a point that only touches ignored segments changes no label: every
// position gets analyze's verdict of the judged range.
TEST(Region, IgnoredSegmentsDoNotChangeTheLabel) {
  const BSpline s = wave();
  for (const auto& [range, want] : {std::pair{SegmentRange{1, 2}, RegionLabel::not_monotone},
                                    std::pair{SegmentRange{2, 2}, RegionLabel::decreasing},
                                    std::pair{SegmentRange{3, 3}, RegionLabel::increasing}}) {
    AnalyzeOptions ao;
    ao.segments = range;
    ASSERT_EQ(code(want), detail::label_of(analyze(s, ao).cmrwi));
    RegionRequest o;
    o.point = 0;
    o.segments = range;
    o.width = o.height = 24;
    const RegionResult r = CpuRegionBackend(1).render(RegionProblem::make(s, o));
    for (std::size_t i = 0; i < r.size(); ++i)
      ASSERT_EQ(r.labels[i], want) << "segments " << range.first << ".." << range.last << " pixel " << i;
  }
}

// The single-position classifier against analyze of the moved spline, for
// ranges, one split in a range, and several joints.
TEST(Region, SegmentControlMatchesAnalyzeOfTheMovedSpline) {
  const BSpline s = wave();
  std::mt19937_64 rng(1102);
  std::uniform_real_distribution<double> off(-0.5, 0.5);
  struct Case {
    int point;
    std::optional<SegmentRange> range;
    std::optional<int> split;
    std::vector<int> splits;
    Mode mode;
  };
  const Case cases[] = {{3, SegmentRange{1, 3}, {}, {}, Mode::cmrwi},   {2, SegmentRange{0, 1}, {}, {}, Mode::cmr},
                        {2, SegmentRange{1, 3}, 2, {}, Mode::cmrwi},     {3, {}, {}, {2, 3}, Mode::cmrwi},
                        {4, SegmentRange{1, 3}, {}, {2, 3}, Mode::cmrwi}, {3, {}, {}, {2}, Mode::cmr}};
  int passing = 0;
  for (const Case& c : cases) {
    RegionRequest o;
    o.point = c.point;
    o.segments = c.range;
    o.split = c.split;
    o.splits = c.splits;
    o.mode = c.mode;
    const RegionProblem problem = RegionProblem::make(s, o);
    for (int sample = 0; sample < 60; ++sample) {
      const Vec2 p = s.points()[c.point] + Vec2(off(rng), off(rng));
      AnalyzeOptions ao;
      ao.segments = c.range;
      ao.split = c.split;
      ao.splits = c.splits;
      ao.split_mode = c.mode;
      const SplineAnalysis a = analyze(s.with_point(c.point, p), ao);
      const RegionPixel px = problem.classify(p);
      const std::string where = "point " + std::to_string(c.point) + " sample " + std::to_string(sample);
      if (!c.splits.empty()) {
        EXPECT_EQ(code(px.alternating_label), detail::label_of(*a.alternation)) << where;
        passing += px.alternating_label == AlternatingLabel::first_increasing;
      } else if (c.split) {
        EXPECT_EQ(code(px.split_label), detail::label_of(*a.split)) << where;
      } else {
        EXPECT_EQ(code(px.label), detail::label_of(c.mode == Mode::cmr ? a.cmr : a.cmrwi)) << where;
      }
    }
  }
  EXPECT_GT(passing, 5) << "some sampled positions should keep the alternation";
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

}  // namespace
}  // namespace cmr
