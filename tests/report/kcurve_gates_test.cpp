// κ-curves pass cmr's own checks: the cubic chain of 20 seeded designer-like
// point sets (tests/design/kcurve_sets.hpp) passes the curvature-extrema-at-nodes
// gate with every piece certified monotone, and its G2 joints show no
// curvature jump (report JSON `jump`; the exact sign is kept as `exact_jump`).
#include <gtest/gtest.h>

#include "design/kcurve.hpp"
#include "report/gates.hpp"
#include "report/batch.hpp"
#include "report/report.hpp"
#include "tests/design/kcurve_sets.hpp"

namespace cmr::report {
namespace {

TEST(KCurveGates, TwentySeededCubicChainsPassExtremaAtNodes) {
  const std::vector<test::PointSet> sets = test::designer_sets(4242, 20);
  ReportOptions options;
  options.regions = false;
  const std::optional<Gate> gate = parse_gate("curvature-extrema-at-nodes");
  ASSERT_TRUE(gate);
  for (const test::PointSet& s : sets) {
    KCurveOptions o;
    o.closed = s.closed;
    const KCurve k = kcurve(s.points, o);
    ASSERT_TRUE(k.converged()) << s.str();
    ASSERT_TRUE(kcurve_cubic_uncertified(k).empty()) << s.str();
    const SplineReport r = judged_report(kcurve_cubic_chain(k), options);
    for (const SpanReport& span : r.spans) {
      const Curvature c = span.classification.monotonicity.curvature;
      EXPECT_TRUE(c == Curvature::increasing || c == Curvature::decreasing)
          << s.str() << ": piece " << span.segment.index << " is " << to_string(c);
    }
    const std::vector<GateResult> g = check_gates(r, {*gate});
    ASSERT_EQ(g.size(), 1u);
    for (const GateViolation& v : g[0].violations) ADD_FAILURE() << s.str() << ": " << v.message;
    for (const JointReport& j : r.joints) {
      if (j.joint.g2) {
        EXPECT_EQ(shown_jump(j.joint), 0) << s.str() << ": joint " << j.joint.index;
      }
    }
  }
}

}  // namespace
}  // namespace cmr::report
