// The report's certified fixes (report/certified_fix.hpp): one per failing
// check (the requirement, the curvature-extrema-at-nodes gate), each re-judged.
#include "report/certified_fix.hpp"

#include <gtest/gtest.h>

#include <sstream>

#include <cmath>

#include "report/batch.hpp"
#include "report/report.hpp"

namespace cmr::report {
namespace {

BSpline fig8() {
  return BSpline::make(3, {0, 1, 2, 3, 4, 5, 6, 7},
                       {{1.3, -1.43}, {1.05, -0.06}, {2.15, -1.31}, {1.97, -3.83}, {-2.23, -6.95}, {-6.78, -9.78}});
}

BSpline moved(const BSpline& s, const CertifiedFix& f) {
  BSpline m = s;
  for (const PointMove& p : f.moves) m = m.with_point(p.point, p.to);
  return m;
}

TEST(CertifiedFix, OnePerFailingCheckAndEachHolds) {
  ReportOptions o;
  parse_require_list("cmrwi,curvature-extrema-at-nodes,no-inflection,max-extrema-per-segment:0", o);
  o.regions = false;
  const SplineReport r = judged_report(fig8(), o);
  ASSERT_FALSE(r.pass);
  ASSERT_TRUE(r.gates[1].pass());   // fig8 has no inflection: no entry
  ASSERT_FALSE(r.gates[2].pass());  // an extremum inside a segment
  const std::vector<CertifiedFix> fixes = certified_fixes(r, o);
  ASSERT_EQ(fixes.size(), 3u);  // the requirement, curvature-extrema-at-nodes, max-extrema-per-segment
  EXPECT_EQ(fixes[0].check, "cmrwi");
  EXPECT_EQ(fixes[1].check, "curvature-extrema-at-nodes");
  EXPECT_EQ(fixes[2].check, "max-extrema-per-segment:0");
  EXPECT_EQ(fixes[2].requirement, "curvature-extrema-at-nodes");  // every segment monotone: no extremum inside
  EXPECT_EQ(certified_fix_json(fixes[2])["requirement"], "curvature-extrema-at-nodes");
  EXPECT_FALSE(certified_fix_json(fixes[1]).contains("requirement"));
  for (std::size_t i = 0; i < 3; ++i) {
    const CertifiedFix& f = fixes[i];
    ASSERT_TRUE(f.found) << f.check << ": " << f.reason;
    EXPECT_EQ(f.moves.size(), 1u) << f.check;
    ASSERT_TRUE(f.fixed.has_value()) << f.check;
    const std::string req = f.requirement.empty() ? f.check : f.requirement;
    EXPECT_TRUE(requirement_holds(moved(fig8(), f), parse_fix_requirement(req))) << f.check;
    EXPECT_TRUE(requirement_holds(*f.fixed, parse_fix_requirement(req))) << f.check;
    EXPECT_FALSE(f.failing_segments.empty()) << f.check;
    // The report of the moved spline passes that check.
    const SplineReport after = judged_report(moved(fig8(), f), o);
    if (f.check == "cmrwi") {
      EXPECT_TRUE(after.requirement_pass);
    }
    for (const GateResult& g : after.gates) {
      if (to_string(g.gate) == f.check) {
        EXPECT_TRUE(g.pass()) << f.check << ": " << g.violations.size();
      }
    }
    // JSON: point name, displacement, relative distance, certificate.
    const auto j = certified_fix_json(f);
    EXPECT_EQ(j["check"], f.check);
    ASSERT_EQ(j["moves"].size(), 1u);
    const PointMove& m = f.moves[0];
    const std::string pk = std::string("P").append(std::to_string(m.point));
    EXPECT_EQ(j["moves"][0]["name"], pk);
    EXPECT_DOUBLE_EQ(j["moves"][0]["displacement"][0].get<double>(), m.to.x - m.from.x);
    EXPECT_DOUBLE_EQ(j["moves"][0]["displacement"][1].get<double>(), m.to.y - m.from.y);
    EXPECT_DOUBLE_EQ(j["moves"][0]["relative"].get<double>(), m.distance / f.size);
    EXPECT_DOUBLE_EQ(j["max_relative"].get<double>(), largest_relative_move(f));
    EXPECT_TRUE(j.contains("certificate")) << j.dump();
    EXPECT_FALSE(j.contains("reason")) << j.dump();
    // Names given (a font's): they replace P<k>.
    std::vector<std::string> names(fig8().unique_point_count());
    for (std::size_t k = 0; k < names.size(); ++k) names[k] = "c0/p" + std::to_string(k);
    EXPECT_EQ(certified_fix_json(f, &names)["moves"][0]["name"], names[m.point]);
    // HTML: the move by name, and the before/after curvature plots.
    const std::string html = certified_fix_html(f, fig8());
    EXPECT_NE(html.find("move " + pk), std::string::npos) << html;
    EXPECT_NE(html.find("κ before"), std::string::npos) << f.check;
    EXPECT_NE(html.find("κ after"), std::string::npos) << f.check;
    EXPECT_NE(certified_fix_html(f, fig8(), &names).find("move " + names[m.point]), std::string::npos);
  }
}

/// Issue 22, item 4: each gate that had no fix requirement gets a certified
/// fix through one that implies it (curvature-extrema-at-nodes:runs: each-run, else
/// the valleys' handles searched with the gate itself as the judge), and the
/// fixed spline passes the gate itself when judged again (a fresh report of
/// the moved points).
struct GateCase {
  const char* gate;
  const char* requirement;  ///< the fix requirement searched
  BSpline spline;
};

std::vector<GateCase> gate_cases() {
  // An S-shaped cubic: one inflection inside.
  const BSpline s_curve = BSpline::bezier({{0, 0}, {1, 1}, {2, -1}, {3, 0}});
  // Two cubic Beziers meeting at a G1 node (knot of multiplicity 3) with
  // curvature 0.69 | 1.05 there (P5 moved off the split Bezier).
  const BSpline g1_joint = BSpline::make(3, {0, 0, 0, 1, 1, 1, 2, 2, 2},
                                         {{0, 0}, {1, 0}, {1.75, 0.125}, {2.2875, 0.3375}, {2.825, 0.55},
                                          {3.35, 0.65}, {3.3, 1.2}});
  // A uniform quadratic B-spline (one run: no on-curve node inside) along a
  // spiral (curvature rising) with its middle point pushed out: a piece
  // peak falls, then rises again.
  std::vector<Vec2> arc;
  for (int k = 0; k <= 8; ++k) {
    const double a = 3.14159265358979 * k / 8, r = std::pow(0.85, k) * (k == 4 ? 1.08 : 1.0);
    arc.push_back({r * std::cos(a), r * std::sin(a)});
  }
  const BSpline run = BSpline::make(2, {0, 0, 1, 2, 3, 4, 5, 6, 7, 7}, arc);
  return {{"max-extrema-per-segment:0", "curvature-extrema-at-nodes", fig8()},
          {"no-inflection", "no-inflection", s_curve},
          {"g2-at-smooth-nodes:0.01", "g2-at-smooth-nodes:0.01", g1_joint},
          {"curvature-extrema-at-nodes:runs", "each-run", run}};
}

TEST(CertifiedFix, EveryGateGetsAFixThatPassesTheGateReJudged) {
  for (const GateCase& c : gate_cases()) {
    ReportOptions o;
    parse_require_list(c.gate, o);
    o.regions = false;
    const SplineReport r = judged_report(c.spline, o);
    ASSERT_EQ(r.gates.size(), 1u) << c.gate;
    ASSERT_FALSE(r.gates[0].pass()) << c.gate << ": the sample passes the gate already";
    const std::vector<CertifiedFix> fixes = certified_fixes(r, o);
    ASSERT_EQ(fixes.size(), 1u) << c.gate;
    const CertifiedFix& f = fixes[0];
    EXPECT_EQ(f.check, to_string(r.gates[0].gate)) << c.gate;
    const std::string searched = f.requirement.empty() ? f.check : f.requirement;
    // curvature-extrema-at-nodes:runs: each-run, or where that has no fix, the
    // valleys' handles judged by the gate itself.
    const bool by_gate = searched == std::string(c.gate) + " (judged by the gate)";
    EXPECT_TRUE(searched == c.requirement || (by_gate && std::string(c.gate) == "curvature-extrema-at-nodes:runs"))
        << c.gate << ": " << searched;
    ASSERT_TRUE(f.found) << c.gate << ": " << f.reason;
    ASSERT_FALSE(f.moves.empty()) << c.gate;
    // The moved points, judged again by a fresh report: the gate passes.
    const SplineReport after = judged_report(moved(c.spline, f), o);
    EXPECT_TRUE(after.gates[0].pass()) << c.gate << ": " << after.gates[0].violations.front().message;
    if (!by_gate) {
      EXPECT_TRUE(requirement_holds(moved(c.spline, f), parse_fix_requirement(c.requirement))) << c.gate;
    }
    // An open spline's end points stay.
    EXPECT_EQ(f.fixed->points().front(), c.spline.points().front()) << c.gate;
    EXPECT_EQ(f.fixed->points().back(), c.spline.points().back()) << c.gate;
  }
}

// The curvature plot: two panels on one scale, the failing segments shaded in
// "before", one sample path per panel that follows kappa(t).
TEST(CertifiedFix, KappaPlotShadesTheFailingSegmentsAndDrawsBothCurves) {
  const BSpline before = fig8();
  const BSpline after = before.with_point(2, before.points()[2] + Vec2(0.05, 0.05));
  const std::string svg = kappa_before_after_svg(before, after, {1, 2});
  EXPECT_EQ(svg.rfind("<svg", 0), 0u) << svg.substr(0, 40);
  // The shaded bands: one path, a closed subpath ("...z") per failing segment.
  const std::size_t band = svg.find("#fde0e0");
  ASSERT_NE(band, std::string::npos) << svg;
  const std::size_t d0 = svg.find("d=\"", band) + 3, d1 = svg.find('"', d0);
  std::size_t shaded = 0;
  for (std::size_t at = d0; at < d1; ++at) shaded += svg[at] == 'z' ? 1 : 0;
  EXPECT_EQ(shaded, 2u) << svg.substr(d0, d1 - d0);
  EXPECT_NE(svg.find("#c00000"), std::string::npos);  // before
  EXPECT_NE(svg.find("#1a7f1a"), std::string::npos);  // after
  EXPECT_EQ(svg.find("nan"), std::string::npos);
}

// The plot is drawn compactly (whole pixels, relative steps, flat runs
// merged): a font page carries hundreds of them (docs/report.md, <= 2 MB).
// Decoding the curve paths gives points inside the panels.
TEST(CertifiedFix, KappaPlotIsCompactAndItsPathsStayInsideThePanels) {
  const BSpline before = fig8();
  const BSpline after = before.with_point(2, before.points()[2] + Vec2(0.05, 0.05));
  const std::string svg = kappa_before_after_svg(before, after, {1});
  EXPECT_LT(svg.size(), 4000u) << svg;
  int paths = 0;
  for (const char* colour : {"#c00000", "#1a7f1a"}) {
    const std::size_t at = svg.find(std::string("stroke=\"") + colour);
    ASSERT_NE(at, std::string::npos) << colour;
    const std::size_t d0 = svg.find("d=\"", at) + 3, d1 = svg.find('"', d0);
    std::istringstream in(svg.substr(d0, d1 - d0));
    char c = 0;
    long x = 0, y = 0;
    int points = 0;
    in >> c;
    ASSERT_EQ(c, 'M') << colour;
    in >> x >> y >> c;
    ASSERT_EQ(c, 'l') << colour;
    ++points;
    long dx = 0, dy = 0;
    while (in >> dx >> dy) {
      x += dx, y += dy;
      ++points;
      EXPECT_GE(y, 15) << colour << " point " << points;
      EXPECT_LE(y, 145) << colour << " point " << points;
      EXPECT_GE(x, paths == 0 ? 0 : 310) << colour << " point " << points;
      EXPECT_LE(x, paths == 0 ? 300 : 610) << colour << " point " << points;
    }
    EXPECT_GT(points, 12) << colour;  // about 64 samples a panel, straight runs merged
    ++paths;
  }
}

// The tangent line search is gone from the report: no "tangent_fixes" in the
// JSON, the fixes are the certified ones.
TEST(CertifiedFix, ReportJsonCarriesCertifiedFixesAndNoTangentFixes) {
  ReportOptions o;
  parse_require_list("cmrwi,curvature-extrema-at-nodes", o);
  o.regions = true;
  o.region_size = 16;
  o.backend = std::make_shared<CpuRegionBackend>(1);
  const std::vector<SplineReport> rs = report_batch({ReportInput{"fig8.json", fig8(), {}}}, o);
  const auto j = report_json(rs, o);
  const auto& s = j["splines"][0];
  EXPECT_FALSE(s.contains("tangent_fixes")) << s.dump();
  ASSERT_TRUE(s.contains("certified_fixes"));
  ASSERT_EQ(s["certified_fixes"].size(), 2u);
  for (const auto& f : s["certified_fixes"]) EXPECT_TRUE(f["found"].get<bool>()) << f.dump();
  o.certified_fixes = false;  // off: none searched
  const std::vector<SplineReport> off = report_batch({ReportInput{"fig8.json", fig8(), {}}}, o);
  EXPECT_TRUE(off[0].certified_fixes.empty());
}

TEST(CertifiedFix, APassingSplineGetsNone) {
  ReportOptions o;
  parse_require_list("cmr", o);
  o.regions = false;
  const SplineReport r = judged_report(BSpline::bezier({{0, 0}, {2, 0}, {3, 0.5}, {3.3, 1.2}}), o);
  ASSERT_TRUE(r.pass);
  EXPECT_TRUE(certified_fixes(r, o).empty());
}

}  // namespace
}  // namespace cmr::report
