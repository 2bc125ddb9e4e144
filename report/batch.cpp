#include "report/batch.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <set>

#include "bezierize/classify.hpp"
#include "report/certified_fix.hpp"
#include "spline/errors.hpp"
#include "spline/parallel.hpp"

namespace cmr::report {

void judge_gates(SplineReport& report, const ReportOptions& options) {
  report.gates = check_gates(report, options.gates);
  report.pass = report.pass &&
                std::all_of(report.gates.begin(), report.gates.end(), [](const GateResult& g) { return g.pass(); });
}

SplineReport judged_report(const BSpline& spline, const ReportOptions& options) {
  SplineReport r = report_spline(spline, options);
  judge_gates(r, options);
  return r;
}

namespace {

/// Control point k (unrolled index) is a node: its polar label t_k..t_{k+d-1}
/// is one knot repeated, so the curve passes through it.
bool is_node(const BSpline& s, int k) {
  const int d = s.degree();
  if (k + d - 1 >= static_cast<int>(s.knots().size())) return false;
  return s.knots()[k] == s.knots()[k + d - 1];
}

}  // namespace

std::vector<TangentFix> suggest_tangent_fixes(const SplineReport& report, const ReportOptions& options, double grid) {
  std::vector<TangentFix> out;
  if (!report.spline || grid <= 0) return out;
  const BSpline& spline = *report.spline;
  const int d = spline.degree(), m = spline.unique_point_count();
  // The violations a handle of their own segment can remove.
  std::set<std::pair<int, int>> targets;  // (gate index, segment)
  for (std::size_t g = 0; g < report.gates.size(); ++g)
    for (const GateViolation& v : report.gates[g].violations)
      if (v.segment >= 0) targets.insert({static_cast<int>(g), v.segment});
  auto count = [](const SplineReport& r) {
    std::size_t n = 0;
    for (const GateResult& g : r.gates) n += g.violations.size();
    return n;
  };
  const std::size_t before = count(report);
  ReportOptions verify = options;
  verify.regions = false;
  verify.grid = 0;
  static constexpr int kSteps[] = {1, 2, 4, 8, 16, 32, 64};
  std::set<int> tried;
  for (const auto& [gate, segment] : targets) {
    const int span = spline.segments()[segment].span;
    for (int k = span - d + 1; k <= span + 1; ++k) {
      if (is_node(spline, k)) continue;
      const int h = spline.closed() ? k % m : k;
      if (!tried.insert(h).second) continue;
      std::optional<TangentFix> best;
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
            // Screen on the segment alone (Algorithms 1 and 2): no extremum,
            // or no inflection, left inside it; then the whole spline again.
            const SegmentClass c = classify_segment(moved, moved.segments()[segment], {options.max_depth, true});
            const bool extremum_gate = report.gates[gate].gate.kind != Gate::Kind::no_inflection;
            if (extremum_gate ? !(c.monotonicity.curvature == Curvature::increasing ||
                                  c.monotonicity.curvature == Curvature::decreasing ||
                                  c.monotonicity.curvature == Curvature::constant)
                              : c.inflection.inflection != Inflection::none)
              continue;
            const SplineReport r = judged_report(moved, verify);  // re-verified after snapping
            bool ok = count(r) < before;
            for (const GateViolation& v : r.gates[gate].violations) ok = ok && v.segment != segment;
            for (std::size_t i = 0; ok && i < r.joints.size(); ++i) ok = report.joints[i].corner || !r.joints[i].corner;
            if (ok) {
              best = TangentFix{h, P, q, j, true};
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
  std::sort(out.begin(), out.end(), [](const TangentFix& a, const TangentFix& b) {
    return dot(a.to - a.from, a.to - a.from) < dot(b.to - b.from, b.to - b.from);
  });
  return out;
}

namespace {

/// One item of a batch, analysed: its report, or its input error.
SplineReport report_item(const ReportInput& input, const ReportOptions& options) {
  SplineReport r;
  try {
    if (input.spline)
      r = report_spline(*input.spline, options);
    else
      r.error = input.error;
  } catch (const InputError& e) {
    r = SplineReport{};
    r.error = e.what();
  }
  r.file = input.file;
  if (r.name.empty()) r.name = std::filesystem::path(r.file).stem().string();
  return r;
}

}  // namespace

std::vector<SplineReport> report_batch(std::vector<ReportInput> inputs, const ReportOptions& options,
                                       const Progress& progress) {
  const int total = static_cast<int>(inputs.size());
  std::vector<SplineReport> out(total);
  int done = 0;
  std::mutex mutex;
  parallel_for(inputs.size(), options.threads, [&](std::size_t i) {
    out[i] = report_item(inputs[i], options);
    if (out[i].error.empty()) judge_gates(out[i], options);
    if (out[i].error.empty() && !out[i].pass && options.grid > 0 && options.regions)
      out[i].tangent_fixes = suggest_tangent_fixes(out[i], options, options.grid);
    if (out[i].error.empty() && !out[i].pass && options.regions) out[i].certified_fixes = certified_fixes(out[i], options);
    const std::lock_guard lock(mutex);
    ++done;
    if (progress) progress(done, total, out[i].name);
  });
  if (!options.regions) return out;
  // Regions one spline at a time: each render already uses every core (or the GPU).
  std::vector<SplineReport*> failing;
  for (SplineReport& r : out) {
    // Regions search fixes of the monotonicity requirement, not of the gates.
    if (r.error.empty() && !r.requirement_pass && (options.require || options.gates.empty())) failing.push_back(&r);
  }
  for (std::size_t i = 0; i < failing.size(); ++i) {
    find_fixes(*failing[i], options);
    if (progress) progress(static_cast<int>(i) + 1, static_cast<int>(failing.size()), "regions: " + failing[i]->name);
  }
  return out;
}

}  // namespace cmr::report
