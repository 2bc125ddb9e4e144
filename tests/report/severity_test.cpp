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

#include "io/font.hpp"
#include "io/ufo.hpp"
#include "report/batch.hpp"
#include "report/gates.hpp"

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

}  // namespace
}  // namespace cmr::report
