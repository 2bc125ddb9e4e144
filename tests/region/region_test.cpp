#include "region/region.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

#include "bezierize/analyze.hpp"
#include "region/region_setup.hpp"
#include "spline/errors.hpp"
#include "spline/fields.hpp"
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

// The library speaks in fields: its messages name RegionRequest's members
// (marked, spline/fields.hpp), never the cmr command's flags.
TEST(Region, InvalidOptionsNameTheRequestsFields) {
  const BSpline s = BSpline::make(3, {0, 1, 2, 3, 4, 5, 6}, {{0, 0}, {1, 1}, {2, 0}, {3, 1}, {4, 0}});
  auto message = [&](auto tweak) {
    RegionRequest o;
    tweak(o);
    try {
      RegionProblem::make(s, o);
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).find("--"), std::string::npos) << e.what();
      return marked_text(e);
    }
    ADD_FAILURE() << "accepted";
    return std::string();
  };
  EXPECT_EQ(message([](RegionRequest& o) { o.with = {9}; }), field("with") + " point 9 is out of range 0..4");
  EXPECT_EQ(message([](RegionRequest& o) { o.with = {0}; }), field("with") + " point 0 is the moved point itself");
  EXPECT_EQ(message([](RegionRequest& o) { o.with = {2, 2}; }), field("with") + " point 2 is named twice");
  EXPECT_EQ(message([](RegionRequest& o) {
              o.split = 1;
              o.each_piece = true;
            }),
            field("split") + " and " + field("each_piece") + " exclude each other: give the joints to " +
                field("each_piece"));
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
  for (const backend::RegionEntry& e : p.setup().entries) {
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
  for (const auto& [range, want] : {std::pair{SegmentRange{1, 2}, Direction::none},
                                    std::pair{SegmentRange{2, 2}, Direction::decreasing},
                                    std::pair{SegmentRange{3, 3}, Direction::increasing}}) {
    AnalyzeOptions ao;
    ao.segments = range;
    ASSERT_EQ(code(want), code(analyze(s, ao).cmrwi));
    RegionRequest o;
    o.point = 0;
    o.segments = range;
    o.width = o.height = 24;
    const RegionResult r = CpuRegionBackend(1).render(RegionProblem::make(s, o));
    for (std::size_t i = 0; i < r.size(); ++i)
      ASSERT_EQ(r.labels[i], want) << "segments " << range.first << ".." << range.last << " pixel " << i;
  }
}

// "In the region" read from one classified position is what the rendered
// image says of the pixel centred there, for every kind of label (plain,
// a split, alternating splits, each piece), on Fig. 10's spline with P4
// moving, where each kind has positions in and out of the region.
TEST(Region, InRegionOfAPixelEqualsTheRenderedImage) {
  const BSpline fig10 = BSpline::make(3, {0, 0, 0, 1, 2, 3, 3, 3},
                                      {{0, 0}, {0.33, 0}, {1.27, -0.27}, {3.46, -2.1}, {5.45, -4.7}, {5.4, -5.8}});
  struct Case {
    std::optional<int> split;
    std::vector<int> splits;
    bool each_piece;
  };
  const Case cases[] = {{{}, {}, false}, {2, {}, false}, {{}, {2}, false}, {{}, {2}, true}};
  for (const Case& c : cases) {
    RegionRequest o;
    o.point = 4;
    o.split = c.split;
    o.splits = c.splits;
    o.each_piece = c.each_piece;
    o.width = o.height = 48;
    const RegionProblem problem = RegionProblem::make(fig10, o);
    const RegionResult img = CpuRegionBackend(1).render(problem);
    int inside = 0;
    for (int j = 0; j < img.height; ++j)
      for (int i = 0; i < img.width; ++i) {
        const std::size_t k = static_cast<std::size_t>(j) * img.width + i;
        const bool here = in_region(problem.classify(pixel_center(img.view, img.width, img.height, i, j)), o);
        ASSERT_EQ(here, img.in_region(k)) << "case " << (&c - cases) << " pixel " << i << "," << j;
        inside += here;
      }
    EXPECT_GT(inside, 0) << "case " << (&c - cases) << ": no position in the region";
    EXPECT_LT(inside, img.width * img.height) << "case " << (&c - cases) << ": every position in the region";
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
        EXPECT_EQ(code(px.alternating_label), code(*a.alternation)) << where;
        passing += px.alternating_label == Alternation::first_increasing;
      } else if (c.split) {
        EXPECT_EQ(code(px.split_label), code(*a.split)) << where;
      } else {
        EXPECT_EQ(code(px.label), code(c.mode == Mode::cmr ? a.cmr : a.cmrwi)) << where;
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
      const int elevated = code(a.cmrwi), original = code(img.labels[j * o.width + i]);
      if (elevated == 3 || original == 3) continue;
      EXPECT_EQ(elevated, original) << "pixel (" << i << ", " << j << ")";
      ++compared;
      in_region += original != 0;
    }
  EXPECT_GT(compared, 150);
  EXPECT_GT(in_region, 5) << "the scene must contain part of the region";
}

// fold_fixed_runs against part_verdict over the full lists: random classes,
// jumps, needed masks, judged ranges and cuts (seeded); the needed segments and their
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
  int cases = 0, not_none = 0, with_range = 0, with_cuts = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const int N = 1 + pick(14);
    const Mode mode = pick(2) ? Mode::cmr : Mode::cmrwi;
    // A judged range (all segments half of the time) and 0..3 cuts strictly inside it.
    SegmentRange range{0, N - 1};
    if (pick(2)) {
      range.first = pick(N);
      range.last = range.first + pick(N - range.first);
    }
    std::vector<int> cuts;
    for (int seg = range.first + 1; seg <= range.last; ++seg)
      if (static_cast<int>(cuts.size()) < 3 && pick(4) == 0) cuts.push_back(seg);
    with_range += range.first != 0 || range.last != N - 1;
    with_cuts += !cuts.empty();
    std::vector<SegmentClass> classes(N);
    std::vector<Joint> joints(N - 1);
    std::vector<bool> needed(N);
    for (auto& c : classes) c = random_class();
    for (int j = 0; j < N - 1; ++j) joints[j].index = j + 1, joints[j].jump = random_jump();
    for (int i = range.first; i <= range.last; ++i) needed[i] = pick(4) == 0;
    const backend::VerdictTemplate t = backend::fold_fixed_runs(classes, joints, needed, range, cuts, mode);
    ASSERT_EQ(t.joints.size() + 1, t.classes.size());
    ASSERT_EQ(t.starts.size(), cuts.size() + 1);
    for (int fill = 0; fill < 8; ++fill) {
      std::vector<SegmentClass> full = classes, folded = t.classes;
      std::vector<Joint> full_joints = joints, folded_joints = t.joints;
      for (int i = range.first; i <= range.last; ++i) {
        if (!needed[i]) continue;
        full[i] = folded[t.slot[i]] = random_class();
        if (i > range.first && joint_counts(range, cuts, i))
          full_joints[i - 1].jump = folded_joints[t.slot[i] - 1].jump = random_jump();
      }
      std::ostringstream what;
      what << "trial " << trial << " fill " << fill << ": N " << N << ", range " << range.first << ".." << range.last
           << ", cuts";
      for (int c : cuts) what << ' ' << c;
      what << ", mode " << (mode == Mode::cmr ? "cmr" : "cmrwi") << ", needed";
      for (int i = 0; i < N; ++i) what << ' ' << needed[i];
      std::vector<Direction> want;
      for (const auto& [a, b] : segment_groups(range, cuts)) want.push_back(part_verdict(full, full_joints, a, b, mode));
      const std::vector<Direction> got = backend::group_verdicts(t, folded, folded_joints, mode);
      ASSERT_EQ(got.size(), want.size()) << what.str();
      for (std::size_t g = 0; g < want.size(); ++g)
        ASSERT_EQ(to_string(got[g]), std::string(to_string(want[g]))) << what.str() << ", group " << g;
      not_none += std::none_of(want.begin(), want.end(), [](Direction d) { return d == Direction::none; });
      const std::vector<SegmentClass> judged(full.begin() + range.first, full.begin() + range.last + 1);
      ASSERT_EQ(depth_of(folded, mode), depth_of(judged, mode)) << what.str();
      ++cases;
    }
  }
  EXPECT_GT(with_range, 500) << "the random cases must exercise judged ranges";
  EXPECT_GT(with_cuts, 500) << "the random cases must exercise cuts";
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
              monotone += px.split_label != Split::none;
            } else {
              const Direction want = mode == Mode::cmr ? a.cmr_algorithm2 : a.cmrwi;
              EXPECT_EQ(code(want), code(px.label)) << "P" << k << " pixel (" << i << ", " << j << ")";
              monotone += px.label != Direction::none;
            }
          }
      }
      EXPECT_GT(monotone, 10) << "the scenes must contain regions";
    }
  }
}

// Closed splines: the seam (the end of segment N-1 against the start of
// segment 0) is judged like every other joint, in the region engine as in
// analyze (the verdict template ends with a neutral class after segment N-1,
// the seam the joint before it). Snail-like closed quadratics (C1 joints, the
// radius growing with the angle, seeded): every pixel equals analyze() of
// the moved spline, whose joints include the seam. (No position can make the
// period monotone with the seam alone failing: by Kneser's theorem the
// osculating circles of an arc of monotone curvature are nested, so such an
// arc cannot end where it starts.)
TEST(Region, ClosedSplineSeamIsJudgedLikeEveryJoint) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.04, 0.04);
  int compared = 0;
  for (int trial = 0; trial < 6; ++trial) {
    const int m = 5 + trial % 3;
    std::vector<Vec2> P;
    for (int i = 0; i < m; ++i) {
      const double t = 2 * M_PI * i / m, r = 1 + 0.6 * i / m + jitter(rng);
      P.push_back({r * std::cos(t), r * std::sin(t)});
    }
    std::vector<double> knots(m + 1);
    for (int i = 0; i <= m; ++i) knots[i] = i;
    const BSpline s = BSpline::make_closed(2, knots, P);
    for (const Mode mode : {Mode::cmrwi, Mode::cmr}) {
      for (int k = 0; k < m; ++k) {
        RegionRequest o;
        o.point = k;
        o.width = o.height = 10;
        o.mode = mode;
        o.view = View{P[k].x - 0.5, P[k].y - 0.5, P[k].x + 0.5, P[k].y + 0.5};
        const RegionProblem problem = RegionProblem::make(s, o);
        const RegionResult img = CpuRegionBackend(1).render(problem);
        for (int j = 0; j < o.height; ++j)
          for (int i = 0; i < o.width; ++i) {
            const Vec2 p = pixel_center(img.view, o.width, o.height, i, j);
            const SplineAnalysis a = analyze(s.with_point(k, p));
            ASSERT_TRUE(a.seam.has_value());
            ASSERT_EQ(a.seam->index, s.segment_count());
            const Direction want = mode == Mode::cmr ? a.cmr_algorithm2 : a.cmrwi;
            ASSERT_EQ(int(img.code_at(j * o.width + i)), int(code(want)))
                << "trial " << trial << " P" << k << (mode == Mode::cmr ? " cmr" : " cmrwi") << " pixel (" << i
                << ", " << j << ")";
            ++compared;
          }
      }
    }
  }
  EXPECT_GT(compared, 1000);
}

// Rational splines (fixed weights): the CPU backend's labels are, pixel by
// pixel, those of an independent exact analysis of the moved spline (the
// spline with point k at the pixel centre), in both modes and split.
TEST(Region, RationalSplineLabelsEqualTheExactAnalysisOfTheMovedSpline) {
  // Fig. 9's polygon (tools/figures.cpp) with weights, on its C2 knots and
  // with a C1 joint (double knot) whose curvature jump varies with the position.
  const std::vector<Vec2> P = {{0, 0}, {0.33, 0}, {1.27, -0.27}, {3.46, -2.1}, {5.45, -4.7}, {6.57, -6.46}};
  const std::vector<double> w = {1, 1.03125, 1, 1, 0.96875, 1.0625};
  for (const BSpline& s : {BSpline::make(3, {0, 0, 0, 1, 2, 3, 3, 3}, P, "C2", w),
                           BSpline::make(3, {0, 0, 0, 1, 1, 2, 2, 2}, P, "C1", w)}) {
  ASSERT_TRUE(s.is_rational());
  int region_pixels = 0;
  for (int mode = 0; mode < 2; ++mode)
    for (const std::optional<int> split : {std::optional<int>(), std::optional<int>(1)}) {
      RegionRequest o;
      o.point = 3;
      o.width = 24;
      o.height = 24;
      o.mode = mode ? Mode::cmr : Mode::cmrwi;
      o.view = View{2.9, -2.6, 4.1, -1.4};  // around P3
      o.split = split;
      const RegionProblem problem = RegionProblem::make(s, o);
      const RegionResult img = CpuRegionBackend().render(problem);
      int in_region = 0;
      for (int j = 0; j < o.height; ++j)
        for (int i = 0; i < o.width; ++i) {
          const Vec2 p = pixel_center(img.view, o.width, o.height, i, j);
          AnalyzeOptions ao;
          ao.split = split;
          ao.split_mode = o.mode;
          const SplineAnalysis a = analyze(s.with_point(o.point, p), ao);
          const int want = split ? code(*a.split) : code(mode ? a.cmr_algorithm2 : a.cmrwi);
          ASSERT_EQ(img.code_at(j * o.width + i), want)
              << s.name() << " mode " << mode << " split " << split.has_value() << " pixel (" << i << ", " << j << ")";
          in_region += want != 0;
        }
      EXPECT_LT(in_region, o.width * o.height) << s.name() << " mode " << mode << " split " << split.has_value();
      region_pixels += in_region;
    }
  EXPECT_GT(region_pixels, 50) << s.name() << ": the scene must hold part of the regions";
  }
}

}  // namespace
}  // namespace cmr

namespace cmr {
namespace {

TEST(Region, ASetCancelFlagStopsTheCpuRenderBeforeItsBlocks) {
  // The caller's cancel flag (RegionRequest::cancel, the Python module's
  // KeyboardInterrupt) is read before each block: set before the render,
  // no block runs and every pixel keeps the blank image's label; unset, the
  // same request labels pixels monotone.
  const BSpline s = BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7},  // Fig. 8
                                  {{1.3, -1.43}, {1.05, -0.06}, {2.15, -1.31}, {1.97, -3.83}, {-2.23, -6.95}, {-6.78, -9.78}});
  RegionRequest o;
  o.point = 3;
  o.width = o.height = 64;
  const auto monotone = [](const RegionResult& r) {
    int n = 0;
    for (const Direction d : r.labels) n += d != Direction::none ? 1 : 0;
    return n;
  };
  const std::atomic<bool> unset{false}, set{true};
  o.cancel = &unset;
  EXPECT_GT(monotone(CpuRegionBackend(2).render(RegionProblem::make(s, o))), 0);
  o.cancel = &set;
  EXPECT_EQ(monotone(CpuRegionBackend(2).render(RegionProblem::make(s, o))), 0);
}

}  // namespace
}  // namespace cmr
