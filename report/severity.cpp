#include "report/severity.hpp"

#include <algorithm>
#include <limits>
#include <set>

#include "bezierize/fix.hpp"
#include "report/batch.hpp"
#include "report/certified_fix.hpp"
#include "spline/errors.hpp"

namespace cmr::report {
namespace {

bool has_severity(const Gate& g) {
  return g.kind == Gate::Kind::extrema_at_nodes || g.kind == Gate::Kind::max_extrema_per_segment ||
         g.kind == Gate::Kind::g2_at_smooth_nodes;
}

/// The same place: the segment of an extremum, the joint of a jump.
bool same_place(const GateViolation& a, const GateViolation& b) {
  return a.segment >= 0 ? a.segment == b.segment : a.joint == b.joint && b.segment < 0;
}

double severity_of(const BSpline& spline, const Gate& gate, const GateViolation& v, const ReportOptions& options) {
  const int n = spline.segment_count();
  std::set<int> points;
  auto add_segment = [&](int i) {
    if (i < 0 || i >= n) return;
    for (int k : segment_points(spline, spline.segments()[i])) points.insert(k);
  };
  if (v.segment >= 0) {
    add_segment(v.segment);
  } else if (v.joint >= 0) {
    add_segment(v.joint % n);
    add_segment(v.joint > 0 ? v.joint - 1 : (spline.closed() ? n - 1 : -1));
  }
  if (points.empty()) return std::numeric_limits<double>::infinity();
  const ReportOptions judge = judge_only(options, gate);
  FixRequest q = gate_fix_request(gate, options.max_depth, kSeverityFixSeconds);
  q.points.assign(points.begin(), points.end());
  q.judge = [judge, v](const BSpline& s) {
    try {
      const SplineReport r = judged_report(s, judge);
      return static_cast<int>(std::count_if(r.gates[0].violations.begin(), r.gates[0].violations.end(),
                                            [&](const GateViolation& w) { return same_place(v, w); }));
    } catch (const InputError&) {
      return std::numeric_limits<int>::max() / 2;
    }
  };
  try {
    const FixResult f = fix(spline, q);
    if (f.already) return 0;
    return f.fixed ? f.max_distance : std::numeric_limits<double>::infinity();
  } catch (const InputError&) {
    return std::numeric_limits<double>::infinity();
  }
}

}  // namespace

void assess_severity(SplineReport& r, const ReportOptions& options) {
  if (options.min_severity < 0 || !r.spline || !r.error.empty()) return;
  for (GateResult& g : r.gates) {
    if (!has_severity(g.gate)) continue;
    for (GateViolation& v : g.violations) {
      v.severity = severity_of(*r.spline, g.gate, v, options);
      v.info = v.severity < options.min_severity && !options.strict;
    }
  }
  const bool gates_pass = std::all_of(r.gates.begin(), r.gates.end(), [](const GateResult& g) { return g.pass(); });
  // report.pass is the requirement's verdict (when one is asked) and every gate's.
  const bool requirement = r.requirement_pass || (!options.require && !options.gates.empty());
  r.pass = requirement && gates_pass;
}

}  // namespace cmr::report
