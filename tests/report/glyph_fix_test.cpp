// The glyph fix on the font's grid (report/glyph_fix.hpp) settles what its
// search found: no moved point has a passing grid position that lowers the
// total squared move, the rest held. Checked here by enumerating, for each
// moved source point, every grid position a designer's move allows it
// (written out here, not taken from the fix): a node moves with its
// handles by grid translations, a handle of a smooth node slides on its
// tangent by the primitive grid vector, any other handle moves freely; each
// candidate that lowers the total and keeps every smooth node smooth is
// judged by the report's gates, and none may pass.
#include <gtest/gtest.h>

#include <array>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "bezierize/extract.hpp"
#include "design/fix.hpp"
#include "io/font.hpp"
#include "report/batch.hpp"
#include "report/glyph_fix.hpp"
#include "report/glyph_settle.hpp"
#include "report/report.hpp"
#include "spline/cpu_clock.hpp"

namespace cmr {
namespace {

const char* kNimbus = "/usr/share/fonts/opentype/urw-base35/NimbusSans-Regular.otf";
const char* kNimbusItalic = "/usr/share/fonts/opentype/urw-base35/NimbusSans-Italic.otf";
const char* kDejaVu = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
const char* kNotoSans = "/usr/share/fonts/truetype/noto/NotoSans-Regular.ttf";

/// The first of Nimbus Sans and DejaVu Sans that is not installed, else null.
const char* missing_font() {
  for (const char* path : {kNimbus, kDejaVu})
    if (!std::filesystem::exists(path)) return path;
  return nullptr;
}

/// The judge of `gates` (comma separated) alone.
report::ReportOptions judge_of(const char* gates) {
  report::ReportOptions o;
  report::parse_require_list(gates, o);
  return report::judge_only(o);
}

/// The shortcut tests' shapes: the source contours of Nimbus Sans `g`, `D`
/// and DejaVu Sans `S`, `e`, `o`, named glyph/cN.
std::vector<std::pair<std::string, import::Contour>> shortcut_contours() {
  std::vector<std::pair<std::string, import::Contour>> out;
  for (const auto& [path, glyphs] : {std::pair{kNimbus, "g,D"}, std::pair{kDejaVu, "S,e,o"}})
    for (const import::Glyph& g : import::read_font(path, import::parse_glyph_spec(glyphs)).glyphs)
      for (const import::Contour& c : g.contours) out.emplace_back(g.name + "/c" + std::to_string(c.index), c);
  return out;
}

double total_squared(const std::vector<Vec2>& p, const std::vector<Vec2>& src) {
  double t = 0;
  for (std::size_t k = 0; k < p.size(); ++k) t += dot(p[k] - src[k], p[k] - src[k]);
  return t;
}

// Every node whose neighbours are both off-curve and exactly collinear with
// it, on opposite sides, is smooth; it must stay so.
bool smooth_nodes_kept(const import::Contour& c, const std::vector<Vec2>& p) {
  const int m = static_cast<int>(p.size());  // distinct points
  const std::vector<Vec2>& s = c.spline.points();
  for (int k = 0; k < m; ++k) {
    if (!c.node[k]) continue;
    const int a = (k + m - 1) % m, b = (k + 1) % m;
    const Vec2 u = s[a] - s[k], v = s[b] - s[k];
    if (u == Vec2(0.0) || v == Vec2(0.0) || det(u, v) != 0 || !(dot(u, v) < 0)) continue;
    const Vec2 u2 = p[a] - p[k], v2 = p[b] - p[k];
    if (u2 == Vec2(0.0) || v2 == Vec2(0.0) || det(u2, v2) != 0 || !(dot(u2, v2) < 0)) return false;
  }
  return true;
}

BSpline with_points(const import::Contour& c, const std::vector<Vec2>& p) {
  BSpline s = c.spline;
  for (int k = 0; k < s.unique_point_count(); ++k)
    if (p[k] != s.points()[k]) s = s.with_point(k, p[k]);
  return s;
}

int violations(const import::Contour& c, const std::vector<Vec2>& p, const report::ReportOptions& o) {
  const report::SplineReport r = report::gate_report(with_points(c, p), o);
  int n = 0;
  for (const report::GateResult& g : r.gates) n += static_cast<int>(g.violations.size());
  return n;
}

TEST(GlyphFix, NoMovedPointHasANearerPassingGridPosition) {
  if (!std::filesystem::exists(kNimbus)) GTEST_SKIP() << kNimbus << " is not installed (tools/setup.sh installs fonts-urw-base35)";
  // The italic's `e` has smooth nodes on slanted tangents: turns to check.
  std::vector<import::Glyph> glyphs = import::read_font(kNimbus, import::parse_glyph_spec("b,y")).glyphs;
  glyphs.push_back(import::read_font(kNimbusItalic, import::parse_glyph_spec("e")).glyphs.at(0));
  report::GlyphFixOptions o;
  report::parse_require_list("curvature-extrema-at-nodes,g2-at-smooth-nodes", o.judge);
  o.judge.regions = false;
  o.glyph_work = 20 * report::kGlyphWork;  // work enough to settle (about 1 s each here)
  o.guard_seconds = 120;                   // and time for it on a loaded machine
  int contours = 0, candidates = 0, turns = 0;
  for (const import::Glyph& g : glyphs) {
    const std::vector<report::ContourFix> fixes = report::fix_glyph(g, o);
    for (const report::ContourFix& f : fixes) {
      if (f.already) continue;
      ASSERT_TRUE(f.fixed) << g.name << "/c" << f.contour << ": " << f.reason;
      EXPECT_TRUE(f.settled) << g.name << "/c" << f.contour;
      const import::Contour& c = g.contours[static_cast<std::size_t>(f.contour)];
      const int m = c.spline.unique_point_count();  // a closed spline's points() repeat its first ones
      const std::vector<Vec2> src(c.spline.points().begin(), c.spline.points().begin() + m);
      std::vector<Vec2> at = src;
      for (const PointMove& mv : f.moves) at[static_cast<std::size_t>(mv.point)] = mv.to;
      ASSERT_EQ(violations(c, at, o.judge), 0) << g.name;
      ASSERT_TRUE(smooth_nodes_kept(c, at)) << g.name;
      const double now = total_squared(at, src);
      // Each moved source point's unit (a node: with its off-curve
      // neighbours) and lattice direction (a smooth node's handle: its
      // tangent's primitive grid vector; else 0: free).
      struct Unit {
        std::string name;
        std::vector<int> points;
        Vec2 along{0.0};
      };
      std::vector<Unit> units;
      for (std::size_t i = 0; i < f.moves.size(); ++i) {
        const int k = f.moves[i].point;
        if (c.font_point[k] < 0) continue;  // an added point moves only with its node
        Unit u{f.names[i], {k}};
        if (c.node[k])
          for (int d : {m - 1, 1})
            if (!c.node[(k + d) % m]) u.points.push_back((k + d) % m);
        if (!c.node[k])
          for (int d : {m - 1, 1}) {
            const int node = (k + d) % m, other = (k + 2 * d) % m;
            if (!c.node[node]) continue;
            const Vec2 a = src[k] - src[node], b = src[other] - src[node];
            if (a != Vec2(0.0) && b != Vec2(0.0) && det(a, b) == 0 && dot(a, b) < 0)
              u.along = a / static_cast<double>(std::gcd(std::lround(std::abs(a.x)), std::lround(std::abs(a.y))));
          }
        units.push_back(u);
      }
      auto steps_of = [](const Unit& u, double r, double slide_r) {
        std::vector<Vec2> out;
        if (u.along != Vec2(0.0)) {
          for (double j = -slide_r; j <= slide_r; ++j)
            if (j != 0) out.push_back(j * u.along);
        } else {
          for (double x = -r; x <= r; ++x)
            for (double y = -r; y <= r; ++y)
              if (x != 0 || y != 0) out.emplace_back(x, y);
        }
        return out;
      };
      auto try_move = [&](const std::vector<std::pair<const Unit*, Vec2>>& moves, const std::string& what) {
        std::vector<Vec2> t = at;
        for (const auto& [u, d] : moves)
          for (int q : u->points) t[static_cast<std::size_t>(q)] = t[static_cast<std::size_t>(q)] + d;
        if (!(total_squared(t, src) < now) || !smooth_nodes_kept(c, t)) return;
        ++candidates;
        EXPECT_NE(violations(c, t, o.judge), 0) << what << " passes nearer the source";
      };
      // Single points: every lattice position that lowers the total.
      const double r = std::ceil(std::sqrt(now)) + 1;
      for (const Unit& u : units)
        for (const Vec2 d : steps_of(u, r, r))
          try_move({{&u, d}}, u.name + " moved by (" + std::to_string(d.x) + ", " + std::to_string(d.y) + ")");
      // Two moved points within three along the contour, each up to 2 cells
      // (a slide 4 steps).
      for (std::size_t a = 0; a < units.size(); ++a)
        for (std::size_t b = a + 1; b < units.size(); ++b) {
          const int gap = std::abs(units[a].points[0] - units[b].points[0]);
          if (std::min(gap, m - gap) > 3) continue;
          for (const Vec2 da : steps_of(units[a], 2, 4))
            for (const Vec2 db : steps_of(units[b], 2, 4))
              try_move({{&units[a], da}, {&units[b], db}}, units[a].name + " and " + units[b].name + " together");
        }
      // Turns of a smooth node's tangent (its handles source points, the
      // tangent neither level nor upright): one handle up to 3 cells, the
      // other on the new tangent, at the two whole multiples nearest its source.
      for (int k = 0; k < m; ++k) {
        const int a = (k + m - 1) % m, b = (k + 1) % m;
        if (!c.node[k] || c.node[a] || c.node[b] || c.font_point[a] < 0 || c.font_point[b] < 0) continue;
        const Vec2 ta = at[k] - at[a], tb = at[b] - at[k];
        if (det(ta, tb) != 0 || dot(ta, tb) <= 0 || ta.x == 0 || ta.y == 0) continue;
        for (const auto& [lead, other] : {std::pair{a, b}, std::pair{b, a}})
          for (double x = -3; x <= 3; ++x)
            for (double y = -3; y <= 3; ++y) {
              const Vec2 l = at[lead] + Vec2(x, y), w = at[k] - l;
              const long cells = std::gcd(std::lround(w.x), std::lround(w.y));
              if (x * x + y * y > 9 || cells == 0 || det(w, ta) == 0) continue;
              const Vec2 v = w / static_cast<double>(cells);
              const double whole = dot(src[other] - at[k], v) / dot(v, v);
              for (const double n : {std::floor(whole), std::ceil(whole)}) {
                std::vector<Vec2> t = at;
                t[lead] = l, t[other] = at[k] + v * std::max(1.0, n);
                if (!(total_squared(t, src) < now)) continue;
                ++turns;
                EXPECT_NE(violations(c, t, o.judge), 0) << g.name << ": the turn at point " << k << " passes nearer";
              }
            }
      }
      ++contours;
    }
  }
  EXPECT_GE(contours, 2);
  EXPECT_GT(candidates, 100);
  EXPECT_GT(turns, 20);
}

// The settling lists a unit's positions band by band of their cost: a
// point that the search left thousands of cells from its source (a glyph
// drawn at 20 times a font's size) still gets the nearest passing grid
// position, in bounded work, where listing its whole disc at once took
// longer than the glyph's time guard (28 million positions here). One free
// point starts 3000 cells out and passes above the source's line and
// outside a disc of radius 102.5 below it (the nearest such lattice point,
// 73 cells straight up, lies in the third ring just past its inner edge);
// one slide starts 10000 steps out and passes only beyond 4096.5 steps on
// that side (the third band of 2048 steps, just past its inner edge). The
// nearest passing positions are found here by enumeration.
TEST(GlyphFix, SettlingAFarPointFindsTheNearestPassingPositionBandByBand) {
  using report::glyph_detail::LatticeUnit;
  // Eight points; the units are points 0 and 4, too far apart along the
  // contour to be a pair (the pairs' small steps would mend a band's miss).
  std::vector<Vec2> src(8, Vec2(0.0));
  src[4] = Vec2(10.0, 0.0);
  std::vector<LatticeUnit> units(2);
  units[0].points = {0};
  units[1].points = {4};
  units[1].slide = true;
  units[1].step = Vec2(3.0, 4.0);  // |step| = 5
  std::vector<Vec2> at = src;
  at[0] = Vec2(3000.0, 7.0);
  at[4] = src[4] + 10000.0 * units[1].step;
  const Vec2 hole(0.4, -30.0);
  auto free_passes = [&](Vec2 p) { return p.y > 0.5 && std::hypot(p.x - hole.x, p.y - hole.y) > 102.5; };
  long judged = 0;
  auto passes = [&](const std::vector<Vec2>&, const std::vector<Vec2>& t) {
    ++judged;
    return free_passes(t[0] - src[0]) && dot(t[4] - src[4], units[1].step) > 4096.5 * 25;
  };
  auto depends = [](const std::vector<int>&) { return std::vector<int>{0, 4}; };
  report::glyph_detail::Work work(50'000'000, 60);
  ASSERT_TRUE(report::glyph_detail::settle_nearer(src, at, units, 1.0, 1e9, passes, depends, {}, work));
  double best = 1e18;
  Vec2 nearest(0.0);
  for (long i = -200; i <= 200; ++i)
    for (long j = -200; j <= 200; ++j) {
      const Vec2 p(static_cast<double>(i), static_cast<double>(j));
      if (free_passes(p) && dot(p, p) < best) best = dot(p, p), nearest = p;
    }
  EXPECT_GT(best, 72.5 * 72.5);  // beyond the first two rings (36 cells each)
  EXPECT_EQ(dot(at[0] - src[0], at[0] - src[0]), best) << at[0].x << ", " << at[0].y << " (nearest " << nearest.x
                                                        << ", " << nearest.y << ")";
  EXPECT_EQ(at[4], src[4] + 4097.0 * units[1].step);
  // In order of cost, judging stops at the first that passes: the disc's
  // positions (about 50,000 a scan), not the 28 million.
  EXPECT_LT(judged, 1'000'000);
}

// The settling turns a smooth node's tangent where slides cannot come
// nearer (asked to, from a settled position): node N = (0, 0) with handles
// on the tangent (2, 1), A = -3 (2, 1) and B = 3 (2, 1) in the source. The
// fix left A at -10 (2, 1); on that tangent a position passes only with
// |A - N| >= 20 (A = -9 (2, 1) at best, where the settling without turns
// ends: total 180), on any other it passes. The nearest turn within kTurnReach
// cells of A = -9 (2, 1) is A = -3 (5, 3), B = (5, 3) (117 + 1), and A then
// slides on the new tangent to -(5, 3): total 2, the least of every exactly
// smooth position off the source's tangent (each handle then moves).
TEST(GlyphFix, SettlingTurnsASmoothNodesTangent) {
  using report::glyph_detail::LatticeUnit;
  const std::vector<Vec2> src{Vec2(-6.0, -3.0), Vec2(0.0), Vec2(6.0, 3.0)};
  std::vector<LatticeUnit> units(2);
  for (int i = 0; i < 2; ++i)
    units[i].points = {2 * i}, units[i].slide = true, units[i].step = Vec2(2.0, 1.0), units[i].anchor = 1;
  std::vector<Vec2> at = src;
  at[0] = Vec2(-20.0, -10.0);
  auto passes = [&](const std::vector<Vec2>&, const std::vector<Vec2>& t) {
    const Vec2 a = t[1] - t[0], b = t[2] - t[1];
    if (t[1] != src[1] || det(a, b) != 0 || dot(a, b) <= 0) return false;  // exactly smooth about the node
    return det(a, Vec2(2.0, 1.0)) != 0 || dot(a, a) >= 400;
  };
  auto depends = [](const std::vector<int>&) { return std::vector<int>{0, 1, 2}; };
  report::glyph_detail::Work work(1'000'000, 60);
  ASSERT_TRUE(report::glyph_detail::settle_nearer(src, at, units, 1.0, 1e9, passes, depends, {}, work));
  EXPECT_EQ(report::glyph_detail::squared_move(src, at), 180.0);  // slides only: A = -9 (2, 1)
  ASSERT_TRUE(report::glyph_detail::settle_nearer(src, at, units, 1.0, 1e9, passes, depends, {}, work, true));
  EXPECT_TRUE(passes(src, at));
  EXPECT_EQ(report::glyph_detail::squared_move(src, at), 2.0) << at[0].x << ", " << at[0].y << " / " << at[2].x << ", "
                                                              << at[2].y;
  // A level tangent is not turned (a node at an x or y extremum keeps its handles level).
  std::vector<Vec2> level{Vec2(-3.0, 0.0), Vec2(0.0), Vec2(3.0, 0.0)}, at_level = level;
  at_level[0] = Vec2(-20.0, 0.0);
  for (LatticeUnit& u : units) u.step = Vec2(1.0, 0.0);
  auto passes_level = [&](const std::vector<Vec2>&, const std::vector<Vec2>& t) {
    const Vec2 a = t[1] - t[0], b = t[2] - t[1];
    return t[1] == level[1] && det(a, b) == 0 && dot(a, b) > 0 && (a.y != 0 || a.x >= 20);
  };
  ASSERT_TRUE(
      report::glyph_detail::settle_nearer(level, at_level, units, 1.0, 1e9, passes_level, depends, {}, work, true));
  EXPECT_EQ(at_level[0], Vec2(-20.0, 0.0));
  EXPECT_EQ(at_level[2], level[2]);
}

// A settling whose every candidate is rejected unjudged (glyph_detail::
// Rejects) still ends when its work is spent: a point 10^6 cells from its
// source has some 28,000 bands of positions between, and a random glyph
// whose fix moved points that far took 844 million units of a 2 million
// budget (three minutes) when only a judgement looked at the budget.
TEST(GlyphFix, SettlingEndsWithItsWorkWhereEveryCandidateIsRejected) {
  using report::glyph_detail::LatticeUnit;
  const std::vector<Vec2> src(4, Vec2(0.0));
  std::vector<LatticeUnit> units(1);
  units[0].points = {0};
  std::vector<Vec2> at = src;
  at[0] = Vec2(1e6, 0.0);
  report::glyph_detail::Work work(2'000, 60);
  long calls = 0;
  const report::glyph_detail::Rejects rejects = [&](const std::vector<Vec2>&, const LatticeUnit&,
                                                    const std::vector<Vec2>& steps) {
    work.charge(100);
    // Every step rejected, but for a settling that went on 80 bands past
    // its work: then none, and the first candidate passes (so the test ends).
    return std::vector<char>(steps.size(), ++calls <= 100 ? 1 : 0);
  };
  auto passes = [](const std::vector<Vec2>&, const std::vector<Vec2>&) { return true; };
  auto depends = [](const std::vector<int>&) { return std::vector<int>{0}; };
  EXPECT_FALSE(report::glyph_detail::settle_nearer(src, at, units, 1.0, 1e9, passes, depends, rejects, work));
  EXPECT_EQ(at[0], Vec2(1e6, 0.0));
  EXPECT_LE(calls, 21);  // 2,000 units at 100 a band, and the band that found them spent
}

// The settling's judge (glyph_detail::local_judge) and the grid descent's
// violation counts judge a moved position on the run of segments the moved
// points touch (glyph_detail::RunJudge); they must say what the whole
// spline's judge says. From each passing fix, random moves of one or two
// source points (a node with its off-curve neighbours, or a point alone,
// up to 6 units each way) are judged both ways; from the passing fix and
// from the failing source, the change in the whole contour's violations
// must be the change on the run.
TEST(GlyphFix, LocalJudgeIsTheWholeJudge) {
  if (const char* path = missing_font()) GTEST_SKIP() << path << " is not installed (tools/setup.sh installs it)";
  report::GlyphFixOptions o;
  report::parse_require_list("curvature-extrema-at-nodes,g2-at-smooth-nodes", o.judge);
  o.judge.regions = false;
  o.guard_seconds = 120;
  const report::ReportOptions judge = report::judge_only(o.judge);
  std::mt19937 rng(36);
  int passing = 0, failing = 0, runs_checked = 0;
  for (const auto& [path, glyphs] : {std::pair{kNimbus, "b,y"}, std::pair{kDejaVu, "c,G"}}) {
    const import::Font font = import::read_font(path, import::parse_glyph_spec(glyphs));
    for (const import::Glyph& g : font.glyphs)
      for (const report::ContourFix& f : report::fix_glyph(g, o)) {
        if (!f.fixed || f.already) continue;
        const import::Contour& c = g.contours[static_cast<std::size_t>(f.contour)];
        const int m = c.spline.unique_point_count();
        std::vector<Vec2> from(c.spline.points().begin(), c.spline.points().begin() + m);
        for (const PointMove& mv : f.moves) from[static_cast<std::size_t>(mv.point)] = mv.to;
        const auto local = report::glyph_detail::local_judge(c, judge);
        const report::glyph_detail::RunJudge runs(c.spline, judge);
        const std::vector<Vec2> source(c.spline.points().begin(), c.spline.points().begin() + m);
        ASSERT_GT(violations(c, source, judge), 0) << g.name;
        auto on_run = [&](const std::vector<Vec2>& p, const report::glyph_detail::RunJudge::Run& r) {
          int n = 0;
          for (const report::GateResult& gr : runs.report(with_points(c, p), r).gates) n += static_cast<int>(gr.violations.size());
          return n;
        };
        std::vector<int> points;
        for (int k = 0; k < m; ++k)
          if (c.font_point[k] >= 0) points.push_back(k);
        std::uniform_int_distribution<std::size_t> pick(0, points.size() - 1);
        std::uniform_int_distribution<int> step(-6, 6);
        for (int trial = 0; trial < 300; ++trial) {
          std::vector<Vec2> to = from;
          for (int moved = 0; moved < 1 + trial % 2; ++moved) {
            const int k = points[pick(rng)];
            const Vec2 d(step(rng), step(rng));
            to[static_cast<std::size_t>(k)] = to[static_cast<std::size_t>(k)] + d;
            if (c.node[k] && trial % 3 == 0)  // a node with its handles
              for (int side : {m - 1, 1})
                if (!c.node[(k + side) % m]) to[static_cast<std::size_t>((k + side) % m)] = to[static_cast<std::size_t>((k + side) % m)] + d;
          }
          const bool whole = smooth_nodes_kept(c, to) && violations(c, to, judge) == 0;
          ASSERT_EQ(local(from, to), whole) << g.name << "/c" << f.contour << " trial " << trial;
          ++(whole ? passing : failing);
          for (const std::vector<Vec2>* base : {static_cast<const std::vector<Vec2>*>(&from), &source}) {
            std::vector<Vec2> moved = *base;  // the same move from this base
            for (int k = 0; k < m; ++k) moved[k] = moved[k] + (to[k] - from[k]);
            const std::optional<report::glyph_detail::RunJudge::Run> r = runs.run(*base, moved);
            if (!r) continue;
            ASSERT_EQ(violations(c, moved, judge) - violations(c, *base, judge), on_run(moved, *r) - on_run(*base, *r))
                << g.name << "/c" << f.contour << " trial " << trial;
            ++runs_checked;
          }
        }
      }
  }
  EXPECT_GT(passing, 100);
  EXPECT_GT(failing, 100);
  EXPECT_GT(runs_checked, 1500);  // most moves change a run short of the whole contour
}

// The settling's shortcut (glyph_detail::extremum_rejects) passes over a
// candidate unjudged only where the curvature-extrema gate fails it: every
// step it rejects must give a violation of that gate on a segment the unit
// shapes. Units of the sources of DejaVu `S`, `e`, `o` and Nimbus `g`, `D`
// (a point alone, and a node with its off-curve neighbours), each with the
// steps of a disc of radius 6 (one render whose pixel centres are the
// candidates) and with 30 steps along a long diagonal (each classified
// alone).
TEST(GlyphFix, ExtremumRejectsAreFailures) {
  if (const char* path = missing_font()) GTEST_SKIP() << path << " is not installed (tools/setup.sh installs it)";
  const report::ReportOptions judge = judge_of("curvature-extrema-at-nodes");
  std::vector<Vec2> disc, diagonal;
  for (int i = -6; i <= 6; ++i)
    for (int j = -6; j <= 6; ++j)
      if (i * i + j * j <= 36 && (i != 0 || j != 0)) disc.emplace_back(i, j);
  for (int j = -15; j <= 15; ++j)
    if (j != 0) diagonal.push_back(static_cast<double>(j) * Vec2(7.0, 3.0));
  long rejected = 0, kept = 0, units = 0;
  for (const auto& [name, c] : shortcut_contours()) {
    const int m = c.spline.unique_point_count();
    const std::vector<Vec2> at(c.spline.points().begin(), c.spline.points().begin() + m);
    report::glyph_detail::Work work(1'000'000'000, 600);
    const report::glyph_detail::Rejects rejects =
        report::glyph_detail::extremum_rejects(c.spline, judge, 1.0, work);
    ASSERT_TRUE(rejects);
    for (int k = 0; k < m; ++k) {
      report::glyph_detail::LatticeUnit u;
      u.points = {k};
      if (c.node[k] && !c.node[(k + 1) % m] && !c.node[(k + m - 1) % m])
        u.points = {k, (k + 1) % m, (k + m - 1) % m};
      ++units;
      for (const std::vector<Vec2>* steps : {&disc, &diagonal}) {
        const std::vector<char> out = rejects(at, u, *steps);
        ASSERT_EQ(out.size(), steps->size());
        for (std::size_t s = 0; s < steps->size(); ++s) {
          ++(out[s] ? rejected : kept);
          if (!out[s]) continue;
          std::vector<Vec2> moved = at;
          for (int p : u.points)
            moved[static_cast<std::size_t>(p)] = moved[static_cast<std::size_t>(p)] + (*steps)[s];
          const BSpline spline = with_points(c, moved);
          bool shaped = false;
          for (const report::GateResult& gr : report::gate_report(spline, judge).gates)
            for (const report::GateViolation& v : gr.violations) {
              if (v.segment < 0) continue;
              for (int p : segment_points(spline, spline.segments()[static_cast<std::size_t>(v.segment)]))
                shaped = shaped || std::find(u.points.begin(), u.points.end(), p % m) != u.points.end();
            }
          ASSERT_TRUE(shaped) << name << " point " << k << " step " << (*steps)[s].x << ", "
                              << (*steps)[s].y;
        }
      }
    }
  }
  EXPECT_GT(units, 40);
  EXPECT_GT(rejected, 10000);
  EXPECT_GT(kept, 5000);
}

// The settling's quick proofs of failure (glyph_detail::with_failure_proofs)
// give the judge's answer: random moves of one or two points (up to 12
// units each way; a node with its off-curve neighbours or a point alone)
// of the sources of DejaVu `S`, `e`, `o` and Nimbus `g`, `D`, judged with
// and without them. Most failing moves are decided by a proof alone.
TEST(GlyphFix, FailureProofsAreTheJudge) {
  if (const char* path = missing_font()) GTEST_SKIP() << path << " is not installed (tools/setup.sh installs it)";
  const report::ReportOptions judge = judge_of("curvature-extrema-at-nodes,g2-at-smooth-nodes");
  std::mt19937 rng(39);
  long trials = 0, passing = 0, proved = 0;
  for (const auto& [name, c] : shortcut_contours()) {
    const int m = c.spline.unique_point_count();
    const std::vector<Vec2> from(c.spline.points().begin(), c.spline.points().begin() + m);
    const report::glyph_detail::RunJudge runs(c.spline, judge);
    const report::glyph_detail::Judge local = report::glyph_detail::local_judge(c, judge);
    long judged = 0;
    report::glyph_detail::Work work(1'000'000'000, 600);
    const report::glyph_detail::Judge quick = report::glyph_detail::with_failure_proofs(
        c.spline, judge, runs,
        [&](const std::vector<Vec2>& a, const std::vector<Vec2>& b) { return ++judged, local(a, b); }, work);
    std::uniform_int_distribution<int> pick(0, m - 1), step(-12, 12);
    for (int trial = 0; trial < 200; ++trial) {
      std::vector<Vec2> to = from;
      for (int moved = 0; moved < 1 + trial % 2; ++moved) {
        const int k = pick(rng);
        const Vec2 d(step(rng), step(rng));
        to[static_cast<std::size_t>(k)] = to[static_cast<std::size_t>(k)] + d;
        if (c.node[k] && trial % 3 == 0)  // a node with its handles
          for (int side : {m - 1, 1})
            if (!c.node[(k + side) % m])
              to[static_cast<std::size_t>((k + side) % m)] = to[static_cast<std::size_t>((k + side) % m)] + d;
      }
      const long before = judged;
      const bool expected = local(from, to);
      ASSERT_EQ(quick(from, to), expected) << name << " trial " << trial;
      ++trials, passing += expected, proved += judged == before;
    }
  }
  EXPECT_GT(trials, 1500);
  EXPECT_GT(passing, 50);
  EXPECT_GT(proved, 300);
}

// A glyph is fixed only when every contour is: where one is refused with a
// proof, no contour is searched (their fixes would be thrown away), and
// each refused one says why. DejaVu Sans `B` under both type gates: each
// contour joins a line to a quadratic smoothly, which no move passes (the
// counters were searched for 5 s before). Where a contour's search finds
// no fix, the contours after it are not searched: Noto Sans `Q` with a
// small budget, its outer contour out of work and its counter listed as
// not searched.
TEST(GlyphFix, AContourWithNoFixLeavesTheRestUnsearched) {
  if (!std::filesystem::exists(kDejaVu)) GTEST_SKIP() << kDejaVu << " is not installed (tools/setup.sh installs it)";
  const import::Font font = import::read_font(kDejaVu, import::parse_glyph_spec("B"));
  ASSERT_EQ(font.glyphs.size(), 1u);
  ASSERT_EQ(font.glyphs[0].contours.size(), 3u);
  report::GlyphFixOptions o;
  report::parse_require_list("curvature-extrema-at-nodes,g2-at-smooth-nodes", o.judge);
  o.judge.regions = false;
  const std::vector<report::ContourFix> fixes = report::fix_glyph(font.glyphs[0], o);
  ASSERT_EQ(fixes.size(), 3u);
  EXPECT_FALSE(fixes[0].fixed);
  EXPECT_NE(fixes[0].reason.find("joins a line to a quadratic curve"), std::string::npos) << fixes[0].reason;
  for (std::size_t i = 1; i < fixes.size(); ++i) {
    EXPECT_EQ(fixes[i].contour, font.glyphs[0].contours[i].index);
    EXPECT_TRUE(fixes[i].moves.empty());
    EXPECT_FALSE(fixes[i].rejudged.empty());
    for (const report::GateCount& g : fixes[i].rejudged) EXPECT_EQ(g.after, g.before);
    if (!fixes[i].already) {
      EXPECT_NE(fixes[i].reason.find("joins a line to a quadratic curve"), std::string::npos) << fixes[i].reason;
      EXPECT_FALSE(fixes[i].not_searched);
    }
  }
  EXPECT_LT(fixes[0].glyph_work, 1000);  // the refusal's few units: no search ran
  if (!std::filesystem::exists(kNotoSans))
    GTEST_SKIP() << kNotoSans << " is not installed (tools/setup.sh installs it)";
  const import::Font q = import::read_font(kNotoSans, import::parse_glyph_spec("Q"));
  ASSERT_EQ(q.glyphs.at(0).contours.size(), 2u);
  o.glyph_work = 20000;
  const std::vector<report::ContourFix> searched = report::fix_glyph(q.glyphs[0], o);
  ASSERT_EQ(searched.size(), 2u);
  EXPECT_FALSE(searched[0].fixed);
  EXPECT_FALSE(searched[0].not_searched);
  EXPECT_TRUE(searched[0].out_of_work);
  EXPECT_FALSE(searched[1].fixed);
  EXPECT_TRUE(searched[1].not_searched);
  EXPECT_EQ(searched[1].reason, "not searched: another contour has no fix");
}

// The grid snap's shortcut (glyph_fix.cpp, land): proves_extremum_violation
// may answer "fails" for a candidate only where the gate itself finds a
// curvature extremum inside one of the segments the move changed (the
// sources fail elsewhere too, so a violation anywhere would prove nothing).
// Without the gate it proves nothing.
TEST(GlyphFix, ChangedSegmentProofsAreTheGate) {
  if (const char* path = missing_font()) GTEST_SKIP() << path << " is not installed (tools/setup.sh installs it)";
  const report::ReportOptions gates = judge_of("curvature-extrema-at-nodes,g2-at-smooth-nodes");
  const report::ReportOptions g2 = judge_of("g2-at-smooth-nodes");
  std::mt19937 rng(41);
  long trials = 0, proved = 0, classified = 0;
  for (const auto& [name, c] : shortcut_contours()) {
    const int m = c.spline.unique_point_count();
    const std::vector<Vec2> from(c.spline.points().begin(), c.spline.points().begin() + m);
    const std::vector<BezierSegment> pieces = bezier_segments(c.spline);
    std::uniform_int_distribution<int> pick(0, m - 1), step(-12, 12);
    for (int trial = 0; trial < 200; ++trial) {
      std::vector<Vec2> to = from;
      for (int moved = 0; moved < 1 + trial % 3; ++moved) {
        const int k = pick(rng);
        to[static_cast<std::size_t>(k)] = to[static_cast<std::size_t>(k)] + Vec2(step(rng), step(rng));
      }
      const BSpline s = c.spline.with_points(to);
      long work = 0;
      ++trials;
      EXPECT_FALSE(report::glyph_detail::proves_extremum_violation(pieces, s, g2, work)) << name;
      if (!report::glyph_detail::proves_extremum_violation(pieces, s, gates, classified)) continue;
      ++proved;
      std::set<int> changed;
      for (int i = 0; i < s.segment_count(); ++i)
        if (bezier_segment(s, s.segments()[static_cast<std::size_t>(i)]).points !=
            pieces[static_cast<std::size_t>(i)].points)
          changed.insert(i);
      bool found = false;
      for (const report::GateResult& g : report::gate_report(s, gates).gates)
        for (const report::GateViolation& v : g.violations)
          found = found || (g.gate.kind == report::Gate::Kind::extrema_at_nodes && changed.count(v.segment));
      EXPECT_TRUE(found) << name << " trial " << trial;
    }
  }
  EXPECT_GT(trials, 1500);
  EXPECT_GT(proved, 300);
  EXPECT_GE(classified, proved);
}

// The glyph fix's budget is work, not time (report/glyph_settle.hpp, Work):
// a glyph whose search runs out of it gets the same fix when the machine is
// busy. DejaVu Sans `S` under both type gates runs out of a small budget
// (about a second here) before its fix is settled; it is fixed again while
// two threads keep both cores busy, and the moves must be the same, bit for
// bit. With the budget in seconds the busy run gets less search done.
TEST(GlyphFix, TheSameGlyphGetsTheSameFixOnABusyMachine) {
  if (!std::filesystem::exists(kDejaVu)) GTEST_SKIP() << kDejaVu << " is not installed (tools/setup.sh installs it)";
  const import::Font font = import::read_font(kDejaVu, import::parse_glyph_spec("S"));
  ASSERT_EQ(font.glyphs.size(), 1u);
  report::GlyphFixOptions o;
  report::parse_require_list("curvature-extrema-at-nodes,g2-at-smooth-nodes", o.judge);
  o.judge.regions = false;
  o.glyph_work = 300000;
  o.guard_seconds = 120;  // the guard never ends it here, not even in a sanitizer build
  auto moves_of = [&] {
    std::vector<std::array<double, 3>> out;
    for (const report::ContourFix& f : report::fix_glyph(font.glyphs[0], o)) {
      EXPECT_FALSE(f.guarded);
      EXPECT_GT(f.glyph_work, 0);
      for (const PointMove& m : f.moves) out.push_back({static_cast<double>(m.point), m.to.x, m.to.y});
      out.push_back({-1.0, f.fixed ? 1.0 : 0.0, f.settled ? 1.0 : 0.0});
    }
    return out;
  };
  const double cpu0 = thread_cpu_seconds();
  const std::vector<std::array<double, 3>> quiet = moves_of();
  const double quiet_cpu = thread_cpu_seconds() - cpu0;
  for (const auto& row : quiet) {
    if (row[0] < 0) {
      EXPECT_EQ(row[1], 1.0) << "the small budget still fixes S";
    }
  }
  std::atomic<bool> stop{false};
  std::vector<std::thread> busy;
  for (int t = 0; t < 4; ++t)
    busy.emplace_back([&stop] {
      volatile double x = 1;
      while (!stop.load(std::memory_order_relaxed)) x = x * 1.0000001 + 1e-9;
    });
  const std::vector<std::array<double, 3>> loaded = moves_of();
  // The guard counts the thread's CPU seconds (spline/cpu_clock.hpp): one
  // a little above what the quiet run used is not reached under load,
  // where the run takes several times as long by the wall clock.
  o.guard_seconds = 1.5 * quiet_cpu + 0.3;
  const auto wall0 = std::chrono::steady_clock::now();
  const std::vector<std::array<double, 3>> guarded = moves_of();
  const double loaded_wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  stop = true;
  for (std::thread& t : busy) t.join();
  EXPECT_EQ(quiet, loaded);
  EXPECT_EQ(quiet, guarded) << "quiet: " << quiet_cpu << " s of CPU; loaded, with a guard of " << o.guard_seconds
                            << " s: " << loaded_wall << " s wall";
  EXPECT_FALSE(quiet.empty());
}

}  // namespace
}  // namespace cmr
