// The report's certified fixes (report/certified_fix.hpp): one per failing
// check (the requirement, the extrema-at-nodes gate), each re-judged.
#include "report/certified_fix.hpp"

#include <gtest/gtest.h>

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
  parse_require_list("cmrwi,extrema-at-nodes,no-inflection", o);
  o.regions = false;
  const SplineReport r = judged_report(fig8(), o);
  ASSERT_FALSE(r.pass);
  const std::vector<CertifiedFix> fixes = certified_fixes(r, o);
  ASSERT_EQ(fixes.size(), 2u);  // the requirement and extrema-at-nodes; no-inflection has no fix requirement
  EXPECT_EQ(fixes[0].check, "cmrwi");
  EXPECT_EQ(fixes[1].check, "extrema-at-nodes");
  for (const CertifiedFix& f : fixes) {
    ASSERT_TRUE(f.found) << f.check << ": " << f.reason;
    EXPECT_EQ(f.moves.size(), 1u) << f.check;
    EXPECT_TRUE(requirement_holds(moved(fig8(), f), parse_fix_requirement(f.check))) << f.check;
    // The report of the moved spline passes that check.
    const SplineReport after = judged_report(moved(fig8(), f), o);
    if (f.check == "cmrwi") EXPECT_TRUE(after.requirement_pass);
    else EXPECT_TRUE(after.gates[0].pass()) << after.gates[0].violations.size();
    const auto j = certified_fix_json(f);
    EXPECT_EQ(j["check"], f.check);
    EXPECT_EQ(j["moves"].size(), 1u);
    EXPECT_NE(certified_fix_html(f).find("move P"), std::string::npos);
  }
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
