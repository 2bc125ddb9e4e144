// Severity (report/severity.hpp): every finding's move, found by a search that
// judges the finding's own segments, is held to the whole spline re-judged
// by the gate: the finding's place passes, and the severity is the move's
// largest point displacement. On a cubic UFO glyph (examples/ufo/Sans.ufo)
// and on quadratic closed contours (DejaVu Sans, TrueType), whose windows
// wrap around the seam.
#include "report/severity.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "io/font.hpp"
#include "io/ufo.hpp"
#include "bezierize/analyze.hpp"
#include "bezierize/extract.hpp"
#include "report/batch.hpp"
#include "report/contour_moves.hpp"
#include "report/gates.hpp"
#include "report/glyph_fix.hpp"

namespace cmr::report {
namespace {

bool same_place(const GateViolation& a, const GateViolation& b) {
  return a.segment >= 0 ? a.segment == b.segment : a.joint == b.joint && b.segment < 0;
}

/// Checks every violation's severity move; returns how many had one.
int check_contours(const std::vector<import::Glyph>& glyphs) {
  ReportOptions o;
  parse_require_list("curvature-extrema-at-nodes,g2-at-smooth-nodes", o);
  o.regions = false;
  o.threads = 1;
  int found = 0;
  for (const import::Glyph& g : glyphs)
    for (const import::Contour& c : g.contours) {
      const SplineReport r = judged_report(c.spline, o);
      for (const GateResult& gr : r.gates)
        for (const GateViolation& v : gr.violations) {
          const SeverityMove m = severity_move(c.spline, gr.gate, v, o);
          if (!std::isfinite(m.distance)) continue;
          ++found;
          SCOPED_TRACE(c.spline.name() + " " + to_string(gr.gate) + " " + v.message);
          EXPECT_TRUE(m.moved.has_value());
          if (!m.moved) continue;
          const SplineReport after = judged_report(*m.moved, judge_only(o, gr.gate));
          EXPECT_TRUE(std::none_of(after.gates[0].violations.begin(), after.gates[0].violations.end(),
                                   [&](const GateViolation& w) { return same_place(v, w); }));
          double largest = 0;
          for (int k = 0; k < c.spline.unique_point_count(); ++k)
            largest = std::max(largest, std::hypot(m.moved->points()[k].x - c.spline.points()[k].x, m.moved->points()[k].y - c.spline.points()[k].y));
          EXPECT_NEAR(largest, m.distance, 1e-9 * std::max(1.0, largest));
          EXPECT_GT(m.distance, 0);
        }
    }
  return found;
}

TEST(Severity, EveryMoveOnACubicUfoGlyphPassesTheWholeSplineReJudged) {
  const import::Font f = import::read_ufo(std::filesystem::path(CMR_SOURCE_DIR) / "examples/ufo/Sans.ufo", {true, {}, {}});
  EXPECT_GT(check_contours(f.glyphs), 3);
}

TEST(Severity, EveryMoveOnQuadraticClosedContoursPassesTheWholeSplineReJudged) {
  const std::filesystem::path dejavu = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
  if (!std::filesystem::exists(dejavu)) GTEST_SKIP() << "fonts-dejavu-core is not installed";
  const import::Font f = import::read_font(dejavu, {'S', 'o', 'e'});
  EXPECT_GT(check_contours(f.glyphs), 3);
}

TEST(Severity, AViolationsMoveIsNoLargerWithinTheThresholdThanWithout) {
  // The coarse-to-fine step: a search within a bound returns no move beyond it.
  const import::Font f = import::read_ufo(std::filesystem::path(CMR_SOURCE_DIR) / "examples/ufo/Sans.ufo", {true, {}, {}});
  ReportOptions o;
  parse_require_list("curvature-extrema-at-nodes,g2-at-smooth-nodes", o);
  o.regions = false;
  o.threads = 1;
  int bounded = 0;
  for (const import::Glyph& g : f.glyphs)
    for (const import::Contour& c : g.contours) {
      const SplineReport r = judged_report(c.spline, o);
      for (const GateResult& gr : r.gates)
        for (const GateViolation& v : gr.violations) {
          const SeverityMove all = severity_move(c.spline, gr.gate, v, o);
          if (!std::isfinite(all.distance)) continue;
          const SeverityMove within = severity_move(c.spline, gr.gate, v, o, 2 * all.distance);
          if (std::isfinite(within.distance)) ++bounded;
          EXPECT_LE(within.distance, 2 * all.distance + 1e-9) << c.spline.name();
        }
    }
  EXPECT_GT(bounded, 0);
}


// ---- The designer's moves (report/contour_moves.hpp, issue 36 item 5) ----

/// Every straight piece of `before` (a line: all its Bezier points exactly
/// collinear) has the same Bezier points in `after`; every G1 joint of
/// `before` is G1 in `after`; every moved point is one `moves` allows.
void expect_designer_move(const BSpline& before, const BSpline& after, const ContourMoves& moves,
                          const std::string& what) {
  SCOPED_TRACE(what);
  for (int k = 0; k < before.unique_point_count(); ++k)
    if (before.points()[k] != after.points()[k]) {
      EXPECT_TRUE(moves.movable(k)) << "P" << k << " moved";
    }
  for (const Segment& seg : before.segments()) {
    const std::vector<Vec2> b = bezier_segment(before, seg).points, a = bezier_segment(after, seg).points;
    bool straight = true;
    for (const Vec2 q : b) {
      const Vec2 u = q - b.front(), v = b.back() - b.front();
      straight = straight && u.x * v.y - u.y * v.x == 0;
    }
    if (!straight) continue;
    for (std::size_t i = 0; i < b.size(); ++i)
      EXPECT_EQ(a[i], b[i]) << "the line of segment " << seg.span << " moved (Bezier point " << i << ")";
  }
  AnalyzeOptions ao;
  const SplineAnalysis x = analyze(before, ao), y = analyze(after, ao);
  std::vector<Joint> jx = x.joints, jy = y.joints;
  if (x.seam) jx.push_back(*x.seam);
  if (y.seam) jy.push_back(*y.seam);
  ASSERT_EQ(jx.size(), jy.size());
  for (std::size_t i = 0; i < jx.size(); ++i)
    if (jx[i].g1) {
      EXPECT_TRUE(jy[i].g1) << "joint " << jx[i].index << " lost G1";
    }
}

/// Every finding's severity move on these contours keeps the designer's
/// rules; returns how many moves were checked.
int check_designer_moves(const std::vector<import::Glyph>& glyphs) {
  ReportOptions o;
  parse_require_list("curvature-extrema-at-nodes,g2-at-smooth-nodes", o);
  o.regions = false;
  o.threads = 1;
  int checked = 0;
  for (const import::Glyph& g : glyphs)
    for (const import::Contour& c : g.contours) {
      const ContourMoves moves = contour_moves(contour_of(c.spline, {}));
      const SplineReport r = judged_report(c.spline, o);
      for (const GateResult& gr : r.gates)
        for (const GateViolation& v : gr.violations) {
          const SeverityMove m = severity_move(c.spline, gr.gate, v, o, moves);
          if (!m.moved) continue;
          ++checked;
          expect_designer_move(c.spline, *m.moved, moves, c.spline.name() + " " + to_string(gr.gate) + " " + v.message);
        }
    }
  return checked;
}

TEST(Severity, ContourOfASourceContourAllowsWhatTheImportSays) {
  // contour_of(spline) (what the report has) and the import's own contour
  // (what `cmr fix FONT.ufo` has) give the same moves on a UFO's glyphs.
  const import::Font f = import::read_ufo(std::filesystem::path(CMR_SOURCE_DIR) / "examples/ufo/Sans.ufo", {true, {}, {}});
  int contours = 0;
  for (const import::Glyph& g : f.glyphs)
    for (const import::Contour& c : g.contours) {
      EXPECT_EQ(contour_moves(contour_of(c.spline, {})).points, contour_moves(c).points) << c.spline.name();
      ++contours;
    }
  EXPECT_GT(contours, 2);
}

TEST(Severity, EveryMoveKeepsLinesStraightAndSmoothNodesG1OnAUfo) {
  const import::Font f = import::read_ufo(std::filesystem::path(CMR_SOURCE_DIR) / "examples/ufo/Sans.ufo", {true, {}, {}});
  EXPECT_GT(check_designer_moves(f.glyphs), 3);
}

TEST(Severity, EveryMoveKeepsLinesStraightAndSmoothNodesG1OnFonts) {
  // Glyphs whose findings sit where stems meet bowls (DejaVu j, U; Nimbus
  // ordfeminine, whose old severity bent a 3-unit line by half a unit).
  const std::filesystem::path dejavu = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
  const std::filesystem::path nimbus = "/usr/share/fonts/opentype/urw-base35/NimbusSans-Regular.otf";
  int checked = 0;
  if (std::filesystem::exists(dejavu)) checked += check_designer_moves(import::read_font(dejavu, {'j', 'U', 'g'}).glyphs);
  if (std::filesystem::exists(nimbus)) checked += check_designer_moves(import::read_font(nimbus, {0xAA, 'j', 'U'}).glyphs);
  if (checked == 0) GTEST_SKIP() << "neither fonts-dejavu-core nor fonts-urw-base35 is installed";
  EXPECT_GT(checked, 3);
}

/// A cubic contour (one glyph of a CFF font or a UFO): a 3-unit line n0 (0,0)
/// -> n1 (0,3), a curve n1 -> (0,40) (60,100) -> n2 (100,100), lines to
/// (100,0) and back. n1 is smooth (line and handle both point up), so
/// g2-at-smooth-nodes finds a 100 % jump there: the line's curvature is 0.
import::Contour short_line_into_a_curve() {
  using T = import::OutlinePoint::Tag;
  const std::vector<import::OutlinePoint> pts = {{{0, 0}, T::on},     {{0, 3}, T::on},      {{0, 40}, T::cubic},
                                                 {{60, 100}, T::cubic}, {{100, 100}, T::on}, {{100, 0}, T::on}};
  return *import::outline_contour(pts, 0, 3, "t", import::PointNaming::source);
}

TEST(Severity, AJumpWhereALineMeetsACurveIsRemovedByStraighteningTheCurveNotByBendingTheLine) {
  // Derivation: the line's side has curvature 0, so the jump goes only when
  // the curve's start curvature is 0 too: (2/3) cross(P1 - P0, P2 - P1) /
  // |P1 - P0|^3 = 0, i.e. P2 on the tangent line x = 0. The designer may
  // not move the line (n0, n1, its third-points), nor n2 (a line's end);
  // P1 (n1's handle) only slides along x = 0, which leaves the cross product
  // 0 only with P2 there too. So no allowed move below 60 units (P2 (60,
  // 100) -> (0, 100)) removes it: the severity is at least 60.
  // The old search bent the line instead (n1 and its group moved).
  const import::Contour c = short_line_into_a_curve();
  ReportOptions o;
  parse_require_list("g2-at-smooth-nodes", o);
  o.regions = false;
  o.threads = 1;
  const SplineReport r = judged_report(c.spline, o);
  ASSERT_EQ(r.gates.size(), 1u);
  const auto v = std::find_if(r.gates[0].violations.begin(), r.gates[0].violations.end(),
                              [&](const GateViolation& w) { return w.joint >= 0; });
  ASSERT_NE(v, r.gates[0].violations.end());
  const ContourMoves moves = contour_moves(c);
  EXPECT_EQ(moves.points, (std::vector<int>{4, 5}));  // the curve's handles (0,40) and (60,100)
  EXPECT_EQ(contour_moves(contour_of(c.spline, {})).points, moves.points);
  const SeverityMove m = severity_move(c.spline, r.gates[0].gate, *v, o, moves);
  EXPECT_GE(m.distance, 60 - 1e-9) << v->message;
  // And 60 is reached: the severity search constructs such a join's move
  // (P2 onto the stem's line, exactly) rather than searching for it.
  ASSERT_TRUE(m.moved.has_value()) << v->message;
  EXPECT_EQ(m.distance, 60);
  EXPECT_EQ(m.moved->points()[5], Vec2(0, 100));
  expect_designer_move(c.spline, *m.moved, moves, v->message);
  // The same through assess_severity, as the report does it: an error at
  // the default threshold, not info.
  SplineReport rr = r;
  o.min_severity = kDefaultMinSeverity;
  assess_severity(rr, o);
  for (const GateViolation& w : rr.gates[0].violations) {
    EXPECT_GE(w.severity, 60 - 1e-9) << w.message;
    EXPECT_FALSE(w.info) << w.message;
  }
}

TEST(Severity, ASlantedLinesJumpIsRemovedByPuttingTheCurvesSecondPointOnTheLine) {
  // The same join with an italic stem: the line (0,0) -> (10,30), direction
  // (1,3); the curve (10,30) (20,60) (60,100) (100,100). Its start curvature
  // is 0 only with (20,60) and P2 on the line 3x = y; (20,60) slides along
  // it (its node is smooth) and the line may not move, so no allowed move
  // is shorter than P2's distance to the line, |det((60,100), (1,3))| /
  // sqrt(10) = 80 / sqrt(10) = sqrt(640), reached at the foot (36,108).
  using T = import::OutlinePoint::Tag;
  const std::vector<import::OutlinePoint> pts = {{{0, 0}, T::on},      {{10, 30}, T::on},    {{20, 60}, T::cubic},
                                                 {{60, 100}, T::cubic}, {{100, 100}, T::on}, {{100, 0}, T::on}};
  const import::Contour c = *import::outline_contour(pts, 0, 3, "t", import::PointNaming::source);
  ReportOptions o;
  parse_require_list("g2-at-smooth-nodes", o);
  o.regions = false;
  o.threads = 1;
  const SplineReport r = judged_report(c.spline, o);
  const auto v = std::find_if(r.gates[0].violations.begin(), r.gates[0].violations.end(),
                              [&](const GateViolation& w) { return w.joint >= 0 && w.message.find("curvature 0 |") != std::string::npos; });
  ASSERT_NE(v, r.gates[0].violations.end());
  const ContourMoves moves = contour_moves(c);
  const SeverityMove m = severity_move(c.spline, r.gates[0].gate, *v, o, moves);
  ASSERT_TRUE(m.moved.has_value()) << v->message;
  EXPECT_NEAR(m.distance, std::sqrt(640.0), 1e-9);
  EXPECT_EQ(m.moved->points()[5], Vec2(36, 108));
  expect_designer_move(c.spline, *m.moved, moves, v->message);
  const SplineReport after = judged_report(*m.moved, judge_only(o, r.gates[0].gate));
  EXPECT_TRUE(std::none_of(after.gates[0].violations.begin(), after.gates[0].violations.end(),
                           [&](const GateViolation& w) { return same_place(*v, w); }));
}

TEST(Severity, WhereNoPointOfTheFindingMayMoveItHasNoneNotZero) {
  // A TrueType contour: a line (0,0) -> (0,50), a quadratic (0,50) (0,100)
  // (50,100) smooth at both ends (the line before, the line after), lines
  // round. The jumps at (0,50) and (50,100) lie between a line and the
  // curve; the line's points and its end nodes may not move, and the one
  // handle (0,100) is held by both smooth nodes' tangents. So no allowed
  // move exists: severity +inf, "no allowed move", an error at any threshold.
  using T = import::OutlinePoint::Tag;
  const std::vector<import::OutlinePoint> pts = {{{0, 0}, T::on},     {{0, 50}, T::on},     {{0, 100}, T::conic},
                                                 {{50, 100}, T::on},  {{100, 100}, T::on},  {{100, 0}, T::on}};
  const import::Contour c = *import::outline_contour(pts, 0, 2, "q", import::PointNaming::source);
  ReportOptions o;
  parse_require_list("g2-at-smooth-nodes", o);
  o.regions = false;
  o.threads = 1;
  o.min_severity = 1e6;
  SplineReport r = judged_report(c.spline, o);
  ASSERT_EQ(r.gates.size(), 1u);
  ASSERT_GE(r.gates[0].violations.size(), 1u);
  assess_severity(r, o);
  for (const GateViolation& v : r.gates[0].violations) {
    SCOPED_TRACE(v.message);
    EXPECT_TRUE(std::isinf(v.severity));
    EXPECT_EQ(v.severity_outcome, SeverityOutcome::no_allowed_move);
    EXPECT_FALSE(v.info);
  }
  EXPECT_FALSE(r.pass);
}


/// The severity search's judge of an extremum (segment_extrema_count) must
/// count what the gate finds on the one-segment window, judged by the whole
/// report machinery: random Bezier segments of degrees 2-5 on integer
/// coordinates (with polar knots a^d b^d, as a window of a contour has),
/// straight ones, cusps (interior and at an end), exact circle-like arcs,
/// and near-constant tolerances from the default to a large one, which
/// exempts extrema that the default counts.
TEST(Severity, TheExtremumJudgeCountsWhatTheGateFindsOnTheWindow) {
  std::mt19937 rng(20261203);
  auto coord = [&](int range) { return static_cast<double>(static_cast<int>(rng() % (2 * range + 1)) - range); };
  std::vector<std::vector<Vec2>> shapes = {
      {{0, 0}, {1, 1}, {0, 1}, {1, 0}},                  // a cusp at t = 1/2
      {{0, 0}, {0, 0}, {100, 50}, {200, 0}},             // P' = 0 at the start
      {{0, 0}, {100, 0}, {200, 0}, {300, 0}},            // straight
      {{0, 0}, {100, 0}, {50, 0}, {300, 0}},             // straight, turning back
      {{1000, 0}, {1000, 552}, {552, 1000}, {0, 1000}},  // a quarter circle, nearly
      {{0, 0}, {0, 55}, {45, 100}, {100, 100}},
      {{0, 0}, {50, 100}, {100, 0}},
  };
  for (int trial = 0; trial < 1500; ++trial) {
    const int d = 2 + static_cast<int>(rng() % 4);
    std::vector<Vec2> pts;
    const int range = trial % 3 == 0 ? 10 : 1000;
    for (int i = 0; i <= d; ++i) pts.push_back({coord(range), coord(range)});
    if (trial % 7 == 0) pts[1] = pts[0];  // a zero end tangent
    shapes.push_back(std::move(pts));
  }
  const std::vector<double> tolerances = {kDefaultConstantTolerance, 1e-3, 0.05, 10};
  int with_extrema = 0, exempt = 0, compared = 0;
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    const int d = static_cast<int>(shapes[k].size()) - 1;
    const double a = static_cast<double>(static_cast<int>(rng() % 9)), b = a + 1 + static_cast<double>(rng() % 3);
    std::vector<double> knots(static_cast<std::size_t>(d), a);
    knots.insert(knots.end(), static_cast<std::size_t>(d), b);
    const BSpline w = BSpline::make(d, knots, shapes[k], "w" + std::to_string(k));
    for (const double tolerance : tolerances) {
      ReportOptions o;
      parse_require_list("curvature-extrema-at-nodes", o);
      o.constant_tolerance = tolerance;
      const ReportOptions judge = judge_only(o, o.gates[0]);
      const SplineReport r = judged_report(w, judge);
      const int expected = static_cast<int>(std::count_if(r.gates[0].violations.begin(), r.gates[0].violations.end(),
                                                          [](const GateViolation& v) { return v.segment == 0; }));
      const std::optional<int> got = segment_extrema_count(w, judge);
      ASSERT_TRUE(got.has_value());
      EXPECT_EQ(*got, expected) << "shape " << k << ", degree " << d << ", tolerance " << tolerance;
      ++compared;
      with_extrema += expected > 0;
      exempt += expected == 0 && !r.extrema.empty();
    }
  }
  EXPECT_GT(compared, 6000);
  EXPECT_GT(with_extrema, 1000);  // not all trivially 0
  EXPECT_GT(exempt, 50);          // the near-constant exemption was exercised
  // Not for more than one segment, a closed or a rational spline.
  ReportOptions o;
  parse_require_list("curvature-extrema-at-nodes", o);
  EXPECT_FALSE(segment_extrema_count(BSpline::make(3, {0, 0, 0, 1, 2, 2, 2}, {{0, 0}, {1, 2}, {3, 3}, {4, 0}, {6, 1}}), o));
  EXPECT_FALSE(segment_extrema_count(BSpline::bezier({{0, 0}, {1, 2}, {3, 3}}, "", {1, 2, 1}), o));
}

}  // namespace
}  // namespace cmr::report
