// Segment control (bezierize/segments.hpp): parsing and validation of ranges
// and cut joints, the alternation verdict, and analyze() restricted to a
// range checked against an independent computation (the sub-spline of those
// segments, and dense sampling of the curvature).
#include "bezierize/segments.hpp"

#include <gtest/gtest.h>

#include <random>

#include "bezierize/analyze.hpp"
#include "spline/curvature.hpp"
#include "spline/errors.hpp"
#include "tests/test_util.hpp"

namespace cmr {
namespace {

// A uniform cubic B-spline of 4 segments whose curvature increases on
// segments 0-1, decreases on 2 and increases on 3 (found by a seeded random
// search; the test AlternationAgreesWithSampledCurvature checks it by sampling).
BSpline wave() {
  return BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7, 8},
                       {{0.058, 0.128}, {1.274, 0.936}, {2.065, -0.298}, {3.236, -0.998}, {3.765, 0.132},
                        {5.069, -0.719}, {6.078, 0.783}});
}

// Distinct knots with steps in [0.5, 1.5], as many as a degree-d spline on
// `points` needs: span and segment indices agree.
BSpline distinct_knot_spline(std::mt19937_64& rng, int d, const std::vector<Vec2>& points) {
  std::uniform_real_distribution<double> step(0.5, 1.5);
  std::vector<double> knots{0};
  while (knots.size() < points.size() + d - 1) knots.push_back(knots.back() + step(rng));
  return BSpline::make(d, knots, points);
}

// Segments first..last of s as a spline of their own: points
// P_first..P_{last+d} on knots u_first..u_{last+2d-1}.
BSpline sub_spline(const BSpline& s, int first, int last) {
  const int d = s.degree();
  const std::vector<double> knots(s.knots().begin() + first, s.knots().begin() + last + 2 * d);
  const std::vector<Vec2> points(s.points().begin() + first, s.points().begin() + last + d + 1);
  return BSpline::make(d, knots, points);
}

TEST(Segments, ParseRange) {
  EXPECT_EQ(parse_segment_range("1..3"), (SegmentRange{1, 3}));
  EXPECT_EQ(parse_segment_range("2"), (SegmentRange{2, 2}));
  EXPECT_EQ(parse_segment_range("0..0"), (SegmentRange{0, 0}));
  for (const char* bad : {"", "1..", "..2", "a..b", "-1..2", "1...3", "1..2x", "1-3", " 1..2"})
    EXPECT_THROW(parse_segment_range(bad), InputError) << "'" << bad << "'";
}

TEST(Segments, JudgedRangeIsValidated) {
  EXPECT_EQ(judged_range(std::nullopt, 4), (SegmentRange{0, 3}));
  EXPECT_EQ(judged_range(SegmentRange{1, 2}, 4), (SegmentRange{1, 2}));
  EXPECT_THROW(judged_range(SegmentRange{2, 1}, 4), InputError);
  EXPECT_THROW(judged_range(SegmentRange{0, 4}, 4), InputError);
  EXPECT_THROW(judged_range(SegmentRange{-1, 2}, 4), InputError);
  try {
    judged_range(SegmentRange{2, 7}, 5);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "segments 2..7: the curve has segments 0..4");
  }
}

TEST(Segments, CutsMustBeInsideTheRangeAndIncrease) {
  const SegmentRange r{1, 4};
  EXPECT_NO_THROW(validate_cuts({2, 3, 4}, r, 6));
  EXPECT_THROW(validate_cuts({1}, r, 6), InputError);  // the range's first joint: nothing before it
  EXPECT_THROW(validate_cuts({5}, r, 6), InputError);
  EXPECT_THROW(validate_cuts({3, 2}, r, 6), InputError);
  EXPECT_THROW(validate_cuts({2, 2}, r, 6), InputError);
  try {
    validate_cuts({5}, SegmentRange{0, 2}, 3);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "split 5 is outside 1..2");  // the message analyze gave before ranges existed
  }
}

TEST(Segments, GroupsBetweenTheCuts) {
  using G = std::vector<std::pair<int, int>>;
  EXPECT_EQ(segment_groups({0, 5}, {}), (G{{0, 6}}));
  EXPECT_EQ(segment_groups({1, 5}, {2, 4}), (G{{1, 2}, {2, 4}, {4, 6}}));
  EXPECT_EQ(group_of({2, 4}, 1), 0);
  EXPECT_EQ(group_of({2, 4}, 2), 1);
  EXPECT_EQ(group_of({2, 4}, 3), 1);
  EXPECT_EQ(group_of({2, 4}, 4), 2);
  // Joint j joins segments j-1 and j: it counts strictly inside the range, except at a cut.
  EXPECT_FALSE(joint_counts({1, 5}, {3}, 1));  // the range's start
  EXPECT_TRUE(joint_counts({1, 5}, {3}, 2));
  EXPECT_FALSE(joint_counts({1, 5}, {3}, 3));  // a cut: its jump is free
  EXPECT_TRUE(joint_counts({1, 5}, {3}, 5));
  EXPECT_FALSE(joint_counts({1, 5}, {3}, 6));  // past the range
}

TEST(Segments, AlternationVerdict) {
  using D = Direction;
  EXPECT_EQ(alternation_verdict({D::increasing, D::decreasing, D::increasing}), Alternation::first_increasing);
  EXPECT_EQ(alternation_verdict({D::decreasing, D::increasing}), Alternation::first_decreasing);
  EXPECT_EQ(alternation_verdict({D::increasing, D::increasing}), Alternation::fail);
  EXPECT_EQ(alternation_verdict({D::increasing, D::decreasing, D::none}), Alternation::fail);
  EXPECT_EQ(alternation_verdict({D::increasing, D::undecided, D::increasing}), Alternation::undecided);
  // Two groups certainly going the same way fail whatever an undecided one does.
  EXPECT_EQ(alternation_verdict({D::undecided, D::decreasing, D::decreasing}), Alternation::fail);
  EXPECT_EQ(alternation_verdict({D::undecided, D::decreasing}), Alternation::undecided);
}

// Analysing segments A..B of a spline is analysing the spline made of those
// segments alone: points P_A..P_{B+d} on knots u_A..u_{B+2d-1} (distinct
// knots, so span and segment indices agree).
TEST(Segments, AnalyzeOfARangeIsAnalyzeOfTheSubSpline) {
  std::mt19937_64 rng(1101);
  int checked = 0, monotone = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const int d = 2 + trial % 3, m = d + 5;
    const BSpline s = distinct_knot_spline(rng, d, test::random_points(rng, m, 2.0));
    const int N = s.segment_count();
    for (int a = 0; a < N; ++a)
      for (int b = a; b < N; ++b) {
        AnalyzeOptions o;
        o.segments = SegmentRange{a, b};
        const SplineAnalysis got = analyze(s, o);
        const SplineAnalysis want = analyze(sub_spline(s, a, b));
        const std::string where = "trial " + std::to_string(trial) + " segments " + std::to_string(a) + ".." +
                                  std::to_string(b);
        EXPECT_EQ(got.cmrwi, want.cmrwi) << where;
        EXPECT_EQ(got.cmr, want.cmr) << where;
        for (int seg = 0; seg < N; ++seg) {
          EXPECT_EQ(got.judged(seg), seg >= a && seg <= b) << where;
          if (got.judged(seg)) {
            EXPECT_EQ(got.segments[seg].monotonicity.curvature, want.segments[seg - a].monotonicity.curvature)
                << where << " segment " << seg;
          }
        }
        ++checked;
        monotone += got.cmrwi == Direction::increasing || got.cmrwi == Direction::decreasing;
      }
  }
  EXPECT_GT(monotone, 20) << "of " << checked << ": the family should hold monotone ranges too";
}

TEST(Segments, AnalyzeValidatesRangesAndCuts) {
  const BSpline s = wave();
  AnalyzeOptions o;
  o.segments = SegmentRange{1, 3};
  o.split = 1;  // the range's first joint
  EXPECT_THROW(analyze(s, o), InputError);
  o.split = 2;
  EXPECT_NO_THROW(analyze(s, o));
  o.splits = {2, 3};
  EXPECT_THROW(analyze(s, o), InputError);  // split and splits together
  o.split.reset();
  EXPECT_NO_THROW(analyze(s, o));
  o.splits = {3, 2};
  EXPECT_THROW(analyze(s, o), InputError);
}

// The fixture's verdicts checked by sampling the curvature densely: on each
// group kappa is strictly monotone the way analyze says, and consecutive
// groups go opposite ways (extrema at the joints).
TEST(Segments, AlternationAgreesWithSampledCurvature) {
  const BSpline s = wave();
  AnalyzeOptions o;
  o.splits = {2, 3};
  const SplineAnalysis a = analyze(s, o);
  ASSERT_TRUE(a.alternation);
  EXPECT_EQ(*a.alternation, Alternation::first_increasing);
  ASSERT_EQ(a.groups.size(), 3u);
  const std::vector<std::pair<int, int>> groups = segment_groups(a.range, o.splits);
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const double t0 = s.segments()[groups[g].first].a, t1 = s.segments()[groups[g].second - 1].b;
    const int want = g % 2 == 0 ? 1 : -1;  // increasing, decreasing, increasing
    EXPECT_EQ(a.groups[g], want > 0 ? Direction::increasing : Direction::decreasing) << "group " << g;
    constexpr int kSamples = 2000;
    double prev = curvature(s, t0);
    for (int i = 1; i <= kSamples; ++i) {
      // Interior samples: at a joint the one-sided curvatures agree (C2).
      const double t = t0 + (t1 - t0) * i / kSamples;
      const double k = curvature(s, t);
      EXPECT_GT(want * (k - prev), 0) << "group " << g << " t " << t;
      prev = k;
    }
  }
  // Other cut choices fail: segments 0 and 1 both increase, 2 and 3 differ.
  o.splits = {1, 2, 3};
  EXPECT_EQ(*analyze(s, o).alternation, Alternation::fail);
  o.splits = {2};
  EXPECT_EQ(*analyze(s, o).alternation, Alternation::fail);  // segments 2..3 are not monotone
  // Restricted to segments 1..3, the same joints still alternate.
  o.splits = {2, 3};
  o.segments = SegmentRange{1, 3};
  EXPECT_EQ(*analyze(s, o).alternation, Alternation::first_increasing);
  o.segments = SegmentRange{2, 3};
  o.splits = {3};
  EXPECT_EQ(*analyze(s, o).alternation, Alternation::first_decreasing);
}

}  // namespace
}  // namespace cmr

namespace cmr {
namespace {

TEST(EachPiece, VerdictIgnoresDirections) {
  using D = Direction;
  // Unlike the alternation, neighbours may go the same way.
  EXPECT_EQ(each_piece_verdict({D::increasing, D::increasing, D::decreasing}), EachPiece::monotone);
  EXPECT_EQ(each_piece_verdict({D::increasing, D::none, D::undecided}), EachPiece::fail);
  EXPECT_EQ(each_piece_verdict({D::undecided, D::decreasing}), EachPiece::undecided);
  EXPECT_STREQ(to_string(EachPiece::monotone), "each-monotone");
}

TEST(EachPiece, CutsDefaultToEveryJointOfTheRange) {
  EXPECT_EQ(each_piece_cuts({0, 3}, {}), (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(each_piece_cuts({1, 3}, {}), (std::vector<int>{2, 3}));
  EXPECT_EQ(each_piece_cuts({2, 2}, {}), (std::vector<int>{}));
  EXPECT_EQ(each_piece_cuts({0, 3}, {2}), (std::vector<int>{2}));
  EXPECT_EQ(parse_joint_list(""), (std::vector<int>{}));
  EXPECT_EQ(parse_joint_list("1,3"), (std::vector<int>{1, 3}));
  for (const char* bad : {"x", "1,", ",1", "1,,2", "-1", "1.5"}) EXPECT_THROW(parse_joint_list(bad), InputError) << bad;
}

// The each-piece verdict of a spline is the conjunction of the verdicts of
// its groups analysed alone (the sub-splines of those segments): no joint
// between groups counts, and no group's direction depends on another's.
TEST(EachPiece, AnalyzeIsEachGroupAnalysedAlone) {
  std::mt19937_64 rng(2011);
  int pass = 0, fail = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const int d = 2 + trial % 3, m = d + 4;
    // A bent, noisy polygon: some pieces monotone, some not.
    std::vector<Vec2> pts = test::random_points(rng, m, 0.3);
    for (int i = 0; i < m; ++i) pts[i] += Vec2(i, 0.15 * i * i);
    const BSpline s = distinct_knot_spline(rng, d, pts);
    const int N = s.segment_count();
    for (const std::vector<int>& cuts : {std::vector<int>{}, std::vector<int>{2}}) {
      AnalyzeOptions o;
      o.each_piece = true;
      o.splits = cuts;
      const SplineAnalysis got = analyze(s, o);
      ASSERT_TRUE(got.each_piece.has_value());
      bool all = true, none = false;
      const auto groups = segment_groups({0, N - 1}, each_piece_cuts({0, N - 1}, cuts));
      ASSERT_EQ(got.groups.size(), groups.size());
      for (std::size_t g = 0; g < groups.size(); ++g) {
        const auto [a, end] = groups[g];
        const Direction mine = analyze(sub_spline(s, a, end - 1)).cmrwi;
        EXPECT_EQ(got.groups[g], mine) << "trial " << trial << " group " << g;
        all = all && (mine == Direction::increasing || mine == Direction::decreasing);
        none = none || mine == Direction::none;
      }
      EXPECT_EQ(*got.each_piece, none ? EachPiece::fail : all ? EachPiece::monotone : EachPiece::undecided)
          << "trial " << trial;
      pass += *got.each_piece == EachPiece::monotone;
      fail += *got.each_piece == EachPiece::fail;
    }
  }
  EXPECT_GT(pass, 2);
  EXPECT_GT(fail, 5);
}

TEST(EachPiece, WaveIsEachMonotoneButDoesNotAlternateEverywhere) {
  AnalyzeOptions o;
  o.each_piece = true;
  const SplineAnalysis a = analyze(wave(), o);
  EXPECT_EQ(*a.each_piece, EachPiece::monotone);
  EXPECT_EQ(a.cuts, (std::vector<int>{1, 2, 3}));
  o.each_piece = false;
  o.splits = {1, 2, 3};  // segments 0 and 1 both increase: no alternation
  EXPECT_EQ(*analyze(wave(), o).alternation, Alternation::fail);
  o.split = 2;
  o.splits.clear();
  o.each_piece = true;
  EXPECT_THROW(analyze(wave(), o), InputError);  // --split and --each-piece exclude each other
}

}  // namespace
}  // namespace cmr
