#include "tools/bench/bench_fix_tangent.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>

#include "bezierize/classify.hpp"
#include "report/batch.hpp"

namespace cmr::bench {
namespace {

/// Control point k (unrolled index) is a node: its polar label t_k..t_{k+d-1}
/// is one knot repeated, so the curve passes through it.
bool is_node(const BSpline& s, int k) {
  const int d = s.degree();
  if (k + d - 1 >= static_cast<int>(s.knots().size())) return false;
  return s.knots()[k] == s.knots()[k + d - 1];
}

std::size_t violation_count(const report::SplineReport& r) {
  std::size_t n = 0;
  for (const report::GateResult& g : r.gates) n += g.violations.size();
  return n;
}

}  // namespace

std::vector<TangentMove> tangent_line_search(const report::SplineReport& report, const report::ReportOptions& options,
                                             double grid) {
  std::vector<TangentMove> out;
  if (!report.spline || grid <= 0) return out;
  const BSpline& spline = *report.spline;
  const int d = spline.degree(), m = spline.unique_point_count();
  std::set<std::pair<int, int>> targets;  // (gate index, segment)
  for (std::size_t g = 0; g < report.gates.size(); ++g)
    for (const report::GateViolation& v : report.gates[g].violations)
      if (v.segment >= 0) targets.insert({static_cast<int>(g), v.segment});
  const std::size_t before = violation_count(report);
  report::ReportOptions verify = options;
  verify.regions = false;
  verify.certified_fixes = false;
  static constexpr int kSteps[] = {1, 2, 4, 8, 16, 32, 64};
  std::set<int> tried;
  for (const auto& [gate, segment] : targets) {
    const int span = spline.segments()[segment].span;
    for (int k = span - d + 1; k <= span + 1; ++k) {
      if (is_node(spline, k)) continue;
      const int h = spline.closed() ? k % m : k;
      if (!tried.insert(h).second) continue;
      std::optional<TangentMove> best;
      for (const int nb : {h - 1, h + 1}) {
        const int j = spline.closed() ? (nb + m) % m : nb;
        if (j < 0 || j >= m || j == h) continue;
        const Vec2 P = spline.points()[h], dir = P - spline.points()[j];
        const double len = std::sqrt(dot(dir, dir));
        if (!(len > 0)) continue;
        bool found = false;
        for (const int step : kSteps) {
          for (const double sign : {1.0, -1.0}) {
            Vec2 q = P + (sign * step * grid / len) * dir;
            q = Vec2(std::round(q.x / grid) * grid, std::round(q.y / grid) * grid);  // on the grid
            if (q == P || (best && dot(q - P, q - P) >= dot(best->to - P, best->to - P))) continue;
            const BSpline moved = spline.with_point(h, q);
            const SegmentClass c = classify_segment(moved, moved.segments()[segment], {options.max_depth, true});
            const bool extremum_gate = report.gates[gate].gate.kind != report::Gate::Kind::no_inflection;
            if (extremum_gate ? !(c.monotonicity.curvature == Curvature::increasing ||
                                  c.monotonicity.curvature == Curvature::decreasing ||
                                  c.monotonicity.curvature == Curvature::constant)
                              : c.inflection.inflection != Inflection::none)
              continue;
            const report::SplineReport r = report::judged_report(moved, verify);
            bool ok = violation_count(r) < before;
            for (const report::GateViolation& v : r.gates[gate].violations) ok = ok && v.segment != segment;
            for (std::size_t i = 0; ok && i < r.joints.size(); ++i) ok = report.joints[i].corner || !r.joints[i].corner;
            if (ok) {
              best = TangentMove{h, P, q, j};
              found = true;
              break;
            }
          }
          if (found) break;
        }
      }
      if (best) out.push_back(*best);
    }
  }
  std::sort(out.begin(), out.end(), [](const TangentMove& a, const TangentMove& b) {
    return dot(a.to - a.from, a.to - a.from) < dot(b.to - b.from, b.to - b.from);
  });
  return out;
}

}  // namespace cmr::bench
