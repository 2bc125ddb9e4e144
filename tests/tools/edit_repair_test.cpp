// The editor's opening selection and its repairs, without a window
// (tools/edit/repair.cpp): which point opens, checked against
// RegionProblem::classify on the same coarse grid; "fix" and "snap into
// region" re-judged by the exact engine (analyze), compared with
// bezierize/fix's own answer, and undone to the exact original coordinates.
#include <gtest/gtest.h>

#include <cmath>

#include "bezierize/analyze.hpp"
#include "design/fix.hpp"
#include "region/region.hpp"
#include "region/region_reason.hpp"
#include "spline/spline_json.hpp"
#include "tools/edit/editor.hpp"

namespace {

using namespace cmr;
using namespace cmr::edit;

const std::string kFigures = std::string(CMR_SOURCE_DIR) + "/examples/figures/";

constexpr int kW = 1024, kH = 768;  // cmr edit's default window, panels shown

/// The certified monotone pixel centres of point k's region on the grid the
/// opening search uses (the request of `e` for its selected point, moved to
/// k): RegionProblem::classify, the engine's single-position answer.
int region_cells(const Editor& e, int k) {
  const int coarse = opening_coarse(e.canvas());
  RegionRequest q = e.region_requests(false, coarse).front();
  q.point = k;
  q.with.clear();
  if (e.doc().spline.closed() && !e.doc().segments) q.segments = closed_support_range(e.doc().spline, k);
  const RegionProblem p = RegionProblem::make(e.doc().spline, q);
  int n = 0;
  for (int j = 0; j < q.height; ++j)
    for (int i = 0; i < q.width; ++i) {
      const Direction l = p.classify(pixel_center(*q.view, q.width, q.height, i, j)).label;
      n += l == Direction::increasing || l == Direction::decreasing;
    }
  return n;
}

bool shows_region(const Editor& e, int k) { return region_cells(e, k) > 0; }

/// Opens like `cmr edit FILE`: the whole window, the opening rule.
Editor opened(BSpline s) {
  Editor e(std::move(s), "t.json", kW, kH);
  e.open_on_region_point();
  return e;
}

/// The opening rule: the first point with kOpeningCells region cells, else
/// the one with the most (the first of equals).
void expect_first_with_region(const Editor& e, const std::string& what) {
  const int k = e.doc().selected, n = e.doc().spline.unique_point_count();
  const int mine = region_cells(e, k);
  if (mine >= Editor::kOpeningCells) {
    for (int j = 0; j < k; ++j)
      EXPECT_LT(region_cells(e, j), Editor::kOpeningCells) << what << ": P" << j << " comes first and shows one";
    EXPECT_EQ(e.message, "opened on P" + std::to_string(k) + ": the first point whose region shows in this view")
        << what;
  } else {
    EXPECT_GT(mine, 0) << what << ": P" << k << " was opened but shows no region";
    for (int j = 0; j < n; ++j) {
      const int c = region_cells(e, j);
      EXPECT_LE(c, mine) << what << ": P" << j << " has a larger region";
      if (j < k) {
        EXPECT_LT(c, mine) << what << ": P" << j << " is as large and comes first";
      }
    }
    EXPECT_EQ(e.message, "opened on P" + std::to_string(k) + ": the largest region in this view, and a small one")
        << what;
  }
  EXPECT_FALSE(e.doc().all_points);
}

TEST(EditOpening, Fig8OpensOnTheFirstPointWithARegion) {
  const Editor e = opened(read_spline_file(kFigures + "fig8.json"));
  EXPECT_GT(e.doc().selected, 0) << "P0's region is empty in fig8: it should not open on it";
  expect_first_with_region(e, "fig8");
}

TEST(EditOpening, Fig10OpensOnTheFirstPointWithARegion) {
  for (const char* f : {"fig10a.json", "fig10b.json"}) expect_first_with_region(opened(read_spline_file(kFigures + f)), f);
}

TEST(EditOpening, ClosedContourJudgesTheSupportAndOpensOnAPointWithARegion) {
  // A closed cubic close to an ellipse (20 points): judged over its whole
  // period no point has a region; a point whose support lies between a
  // sharpest and a flattest point has one.
  std::vector<Vec2> pts;
  std::vector<double> knots;
  for (int i = 0; i < 20; ++i) {
    const double a = 2 * M_PI * i / 20;
    pts.push_back({2 * std::cos(a), std::sin(a)});
    knots.push_back(i);
  }
  knots.push_back(20);
  const BSpline loop = BSpline::make_closed(3, knots, pts);
  const Editor e = opened(loop);
  expect_first_with_region(e, "closed loop");
  const auto support = e.closed_support();
  ASSERT_TRUE(support.has_value()) << "a closed curve's region judges the spans the point acts on";
  EXPECT_EQ(support, closed_support_range(loop, e.doc().selected));
  // Judged over every segment, none has one: the reason line names the period.
  Editor all(loop, "t.json", kW, kH);
  all.set_segments(SegmentRange{0, loop.segment_count() - 1});
  EXPECT_FALSE(all.open_on_region_point().has_value());
  EXPECT_EQ(all.doc().selected, 0);
  EXPECT_NE(all.message.find("never monotone over its whole period"), std::string::npos) << all.message;
  // A closed zigzag (radii 1.3 and 1 in turn): no point's support has a
  // region; the line gives the first reason that names segments, not P0's
  // (whose support wraps around the seam).
  std::vector<Vec2> zig;
  for (int i = 0; i < 20; ++i) {
    const double a = 2 * M_PI * i / 20, r = i % 2 ? 1.0 : 1.3;
    zig.push_back({r * std::cos(a), r * std::sin(a)});
  }
  Editor z(BSpline::make_closed(3, knots, zig), "t.json", kW, kH);
  EXPECT_FALSE(z.open_on_region_point().has_value());
  for (int k = 0; k < 20; ++k) EXPECT_FALSE(shows_region(z, k)) << "closed zigzag P" << k;
  EXPECT_EQ(z.message.rfind("no point has a region in this view: ", 0), 0u) << z.message;
  EXPECT_NE(z.message.find("segments "), std::string::npos) << z.message;
  EXPECT_EQ(z.message.find("whole period"), std::string::npos) << z.message;
}

TEST(EditOpening, NoPointWithARegionSaysWhyNamingTheSegment) {
  // A quadratic zigzag: every segment has a curvature maximum inside, and
  // each point acts on three of the six, so every region is empty.
  std::vector<Vec2> pts;
  for (int i = 0; i < 8; ++i) pts.push_back({static_cast<double>(i), i % 2 ? 1.0 : -1.0});
  const BSpline zig = BSpline::make(2, {0, 1, 2, 3, 4, 5, 6, 7, 8}, pts);
  Editor e(zig, "t.json", kW, kH);
  EXPECT_FALSE(e.open_on_region_point().has_value());
  EXPECT_EQ(e.doc().selected, 0) << "opens as before";
  for (int k = 0; k < zig.point_count(); ++k) EXPECT_FALSE(shows_region(e, k)) << "P" << k;
  const std::string prefix = "no point has a region in this view: ";
  ASSERT_EQ(e.message.rfind(prefix, 0), 0u) << e.message;
  EXPECT_NE(e.message.find("non-monotone whatever P0 does"), std::string::npos) << e.message;
  EXPECT_NE(e.message.find("segments "), std::string::npos) << e.message;
  EXPECT_EQ(e.message.find('\n'), std::string::npos) << "one line";
  // The status line survives the first frame's region (it would otherwise
  // say P0's reason alone).
  e.region();
  EXPECT_EQ(e.message.rfind(prefix, 0), 0u) << e.message;
}

TEST(EditOpening, NamedPointIsKept) {
  Editor e(read_spline_file(kFigures + "fig8.json"), "t.json", kW, kH);
  EXPECT_EQ(e.open_on_region_point(0), 0);
  EXPECT_EQ(e.doc().selected, 0);
  EXPECT_EQ(e.message.rfind("opened on P0 (--point); segment 1 is non-monotone whatever P0 does", 0), 0u) << e.message;
  EXPECT_FALSE(e.undo()) << "opening is not an undo step";
  EXPECT_THROW(e.open_on_region_point(6), InputError);
}

void settle(Editor& e) {
  for (int i = 0; i < 100 && e.animating(); ++i) e.advance_animation(0.05);
  ASSERT_FALSE(e.animating());
}

FixRequest request_of(FixRequirement r, std::vector<int> points, Keep keep) {
  FixRequest q;
  q.requirement = r;
  q.points = std::move(points);
  q.keep = keep;
  q.max_seconds = Editor::kFixSeconds;
  return q;
}

// "fix" reaches bezierize/fix's answer for the view's requirement, animated
// (the first frames lie between), certified by analyze; undo is exact.
TEST(EditRepair, FixIsTheCertifiedFixAnimatedAndUndoneExactly) {
  const BSpline fig8 = read_spline_file(kFigures + "fig8.json");
  struct Case {
    std::string what;
    std::optional<int> split;
    bool chain;
    FixRequirement::Kind kind;
  };
  for (const Case& c : {Case{"cmrwi", std::nullopt, false, FixRequirement::Kind::cmrwi},
                        Case{"split:2", 2, false, FixRequirement::Kind::split},
                        Case{"each-piece", std::nullopt, true, FixRequirement::Kind::each_piece}}) {
    Editor e(fig8, "t.json", 320, 240);
    if (c.split) e.set_split(c.split);
    if (c.chain) e.set_chain(true);
    ASSERT_EQ(e.fix_requirement().kind, c.kind) << c.what;
    ASSERT_FALSE(requirement_holds(fig8, e.fix_requirement())) << c.what << ": fig8 should fail it";
    ASSERT_TRUE(e.fix_curve()) << c.what << ": " << e.message;
    EXPECT_TRUE(e.animating()) << c.what;
    EXPECT_EQ(e.doc().spline.points(), fig8.points()) << c.what << ": the animation starts where the curve was";
    e.advance_animation(Editor::kFixAnimationSeconds / 2);
    EXPECT_NE(e.doc().spline.points(), fig8.points()) << c.what << ": half way";
    settle(e);
    const BSpline fixed = e.doc().spline;
    EXPECT_TRUE(requirement_holds(fixed, e.fix_requirement())) << c.what << ": re-judged by analyze";
    const FixResult want = fix(fig8, request_of(e.fix_requirement(), {}, Keep::g1));
    ASSERT_TRUE(want.fixed) << c.what;
    EXPECT_EQ(fixed.points(), want.spline->points()) << c.what << ": bezierize/fix's answer";
    EXPECT_NE(e.message.find("certified by analyze"), std::string::npos) << e.message;
    ASSERT_TRUE(e.undo());
    EXPECT_EQ(e.doc().spline.points(), fig8.points()) << c.what << ": one undo restores the exact coordinates";
    ASSERT_TRUE(e.redo());
    EXPECT_EQ(e.doc().spline.points(), fixed.points()) << c.what;
  }
}

// "snap" with a judged segment range (set_segments) reaches the requirement
// on that range only: the range is in fix_requirement(), and the snapped
// curve passes there (re-judged by analyze on the range) while the whole
// curve need not.
TEST(EditRepair, SnapHonoursTheJudgedSegmentRange) {
  const BSpline fig8 = read_spline_file(kFigures + "fig8.json");
  Editor e(fig8, "t.json", 320, 240);
  e.set_segments(SegmentRange{1, 1});
  ASSERT_EQ(e.fix_requirement().segments, (std::optional<SegmentRange>(SegmentRange{1, 1})));
  ASSERT_FALSE(requirement_holds(fig8, e.fix_requirement())) << "fig8's segment 1 should fail alone";
  e.select(2);
  ASSERT_TRUE(e.snap_selected()) << e.message;
  settle(e);
  const BSpline s = e.doc().spline;
  EXPECT_TRUE(requirement_holds(s, e.fix_requirement())) << "segment 1 re-judged";
  const FixResult want = fix(fig8, request_of(e.fix_requirement(), {2}, Keep::none));
  ASSERT_TRUE(want.fixed) << want.reason;
  EXPECT_EQ(s.points(), want.spline->points());
  EXPECT_EQ(want.certificate.range, (SegmentRange{1, 1}));
}

// "snap": the selected point alone, to bezierize/fix's nearest certified
// position; it lands inside its region (RegionProblem::classify) and moves
// exactly the distance fix reports.
TEST(EditRepair, SnapMovesTheSelectedPointTheDistanceFixReportsIntoItsRegion) {
  const BSpline fig8 = read_spline_file(kFigures + "fig8.json");
  for (int k : {1, 2, 3}) {
    Editor e(fig8, "t.json", 320, 240);
    e.select(k);
    RegionRequest rq;
    rq.point = k;
    const RegionProblem before = RegionProblem::make(fig8, rq);
    const Direction at = before.classify(fig8.points()[k]).label;
    if (at == Direction::increasing || at == Direction::decreasing) {
      ASSERT_TRUE(e.snap_selected());
      EXPECT_NE(e.message.find("already"), std::string::npos) << e.message;
      continue;
    }
    const FixResult want = fix(fig8, request_of(e.fix_requirement(), {k}, Keep::none));
    ASSERT_TRUE(e.snap_selected()) << "P" << k << ": " << e.message;
    settle(e);
    const BSpline s = e.doc().spline;
    for (int i = 0; i < s.point_count(); ++i)
      if (i != k) {
        EXPECT_EQ(s.points()[i], fig8.points()[i]) << "P" << k << " snapped, P" << i << " moved";
      }
    ASSERT_TRUE(want.fixed) << want.reason;
    ASSERT_EQ(want.moves.size(), 1u);
    const Vec2 d = s.points()[k] - fig8.points()[k];
    EXPECT_DOUBLE_EQ(std::hypot(d.x, d.y), want.moves[0].distance) << "P" << k;
    const Direction l = before.classify(s.points()[k]).label;
    EXPECT_TRUE(l == Direction::increasing || l == Direction::decreasing) << "P" << k << " is not in its region";
    EXPECT_TRUE(requirement_holds(s, e.fix_requirement()));
    ASSERT_TRUE(e.undo());
    EXPECT_EQ(e.doc().spline.points(), fig8.points()) << "P" << k << ": undo";
  }
}

// No fix: nothing moves, no undo step, one status line that says why.
TEST(EditRepair, NoFixSaysWhyInOneLine) {
  const BSpline fig8 = read_spline_file(kFigures + "fig8.json");
  {
    Editor e(fig8, "t.json", 320, 240);
    e.select(0);  // P0 acts on segment 0 only
    e.set_group({5});
    EXPECT_FALSE(e.snap_selected());
    EXPECT_NE(e.message.find("rigid group"), std::string::npos) << e.message;
  }
  // fig8 fails cmrwi in segments 0 and 1: P0 (segment 0 only) has no
  // position that fixes both; P5 acts on neither.
  for (const auto& [k, why] : {std::pair{0, std::string("snap P0 (cmrwi): no certified fix within")},
                               std::pair{5, std::string("snap P5: --points: P5 does not act on a failing segment")}}) {
    Editor e(fig8, "t.json", 320, 240);
    e.select(k);
    EXPECT_FALSE(e.snap_selected()) << "P" << k;
    EXPECT_FALSE(e.animating());
    EXPECT_EQ(e.doc().spline.points(), fig8.points());
    EXPECT_EQ(e.message.rfind(why, 0), 0u) << e.message;
    EXPECT_EQ(e.message.find('\n'), std::string::npos);
    ASSERT_TRUE(e.undo());  // the selection only
    EXPECT_FALSE(e.undo()) << "P" << k << ": the failed snap left no undo step";
  }
  {
    const BSpline loop = BSpline::make_closed(3, {0, 1, 2, 3, 4, 5, 6, 7},
                                              {{2, 0}, {1, 1.5}, {-1, 1.5}, {-2, 0}, {-1, -1.5}, {1, -1.5}, {1.8, -0.9}});
    Editor e(loop, "t.json", 320, 240);
    EXPECT_FALSE(e.fix_curve());
    EXPECT_NE(e.message.find("never monotone over its whole period"), std::string::npos) << e.message;
    EXPECT_FALSE(e.undo()) << "nothing was done";
  }
}

}  // namespace
