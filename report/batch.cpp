#include "report/batch.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <set>

#include "bezierize/classify.hpp"
#include "report/certified_fix.hpp"
#include "report/severity.hpp"
#include "spline/errors.hpp"
#include "spline/fields.hpp"
#include "spline/parallel.hpp"

namespace cmr::report {

void judge_gates(SplineReport& report, const ReportOptions& options) {
  report.gates = check_gates(report, options.gates);
  report.pass = report.pass &&
                std::all_of(report.gates.begin(), report.gates.end(), [](const GateResult& g) { return g.pass(); });
}

ReportOptions judge_only(const ReportOptions& options, const std::optional<Gate>& gate) {
  ReportOptions o = options;
  if (gate) {
    o.gates = {*gate};
    o.require.reset();
  }
  o.regions = false;
  o.certified_fixes = false;
  o.min_severity = -1;
  o.threads = 1;
  return o;
}

SplineReport judged_report(const BSpline& spline, const ReportOptions& options) {
  SplineReport r = report_spline(spline, options);
  judge_gates(r, options);
  return r;
}

SplineReport gate_model(const BSpline& spline, const ReportOptions& options) {
  const bool classes_read =
      options.require.has_value() || options.gates.empty() ||
      std::any_of(options.gates.begin(), options.gates.end(), [](const Gate& g) { return g.kind == Gate::Kind::each_piece; });
  return report_spline(spline, options, classes_read);
}

SplineReport gate_report(const BSpline& spline, const ReportOptions& options) {
  SplineReport r = gate_model(spline, options);
  judge_gates(r, options);
  return r;
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
    r.error = options.show_fields(marked_text(e));
  }
  r.file = input.file;
  r.motions = input.motions;
  if (r.name.empty()) r.name = std::filesystem::path(r.file).stem().string();
  return r;
}

}  // namespace

void FixBudget::start(double budget_seconds) {
  seconds = budget_seconds;
  deadline = budget_seconds > 0 ? std::chrono::steady_clock::now() +
                                      std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                          std::chrono::duration<double>(budget_seconds))
                                : std::chrono::steady_clock::time_point::max();
}

std::string FixBudget::note() const {
  std::string note;
  if (const int n = skipped.load(); n > 0) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g", seconds);
    note = std::to_string(n) + (n == 1 ? " failing spline has" : " failing splines have") +
           " no fix search or only part of one: the run's fix search budget of " + buf + " s (" + field("fix_budget") +
           ") was spent";
  }
  if (const int n = too_large.load(); n > 0) {
    if (!note.empty()) note += "; ";
    note += std::to_string(n) + (n == 1 ? " failing spline has" : " failing splines have") +
            " no fix search: more than " + std::to_string(kMaxRegionFixPoints) + " control points";
  }
  return note;
}

std::vector<SplineReport> report_batch(std::vector<ReportInput> inputs, const ReportOptions& options,
                                       const Progress& progress, FixBudget* budget) {
  const int total = static_cast<int>(inputs.size());
  std::vector<SplineReport> out(total);
  std::vector<char> unbudgeted(inputs.size(), 0);  // a fix search skipped: the budget was spent
  std::vector<char> too_large_certified(inputs.size(), 0);  // no certified fix search: too many points
  const auto too_large = [](const SplineReport& r) {
    return r.spline && r.spline->unique_point_count() > kMaxRegionFixPoints;
  };
  const auto count_unbudgeted = [&] {
    if (budget == nullptr) return;
    budget->skipped += static_cast<int>(std::count(unbudgeted.begin(), unbudgeted.end(), 1));
    budget->too_large += static_cast<int>(std::count(too_large_certified.begin(), too_large_certified.end(), 1));
  };
  int done = 0;
  std::mutex mutex;
  SeverityMemo severity_memo;  // a contour copied into another glyph: its severities once
  parallel_for(inputs.size(), options.threads, [&](std::size_t i) {
    out[i] = report_item(inputs[i], options);
    if (out[i].error.empty()) {
      judge_gates(out[i], options);
      const auto t0 = std::chrono::steady_clock::now();
      assess_severity(out[i], options, &severity_memo);  // with min_severity >= 0: below it a finding is info
      if (budget != nullptr && options.min_severity >= 0)  // severity does not spend the fix budget
        budget->severity_ns += std::chrono::duration_cast<std::chrono::nanoseconds>(
                                   std::chrono::steady_clock::now() - t0).count() /
                               std::min<std::int64_t>(thread_count(options.threads), static_cast<std::int64_t>(total));
    }
    if (out[i].error.empty() && !out[i].pass && options.regions && options.certified_fixes) {
      if (budget != nullptr && budget->spent()) unbudgeted[i] = 1;
      else if (budget != nullptr && too_large(out[i])) too_large_certified[i] = 1;
      else out[i].certified_fixes = certified_fixes(out[i], options);
    }
    const std::lock_guard lock(mutex);
    ++done;
    if (progress) progress(done, total, out[i].name);
  });
  if (!options.regions) {
    count_unbudgeted();
    return out;
  }
  // Regions one spline at a time: each render already uses every core (or the GPU).
  std::vector<SplineReport*> failing;
  for (SplineReport& r : out) {
    // Regions search fixes of the monotonicity requirement, not of the gates.
    if (!r.error.empty() || r.requirement_pass || !(options.require || options.gates.empty())) continue;
    if (budget != nullptr && too_large(r)) {
      too_large_certified[static_cast<std::size_t>(&r - out.data())] = 1;  // counted once
      continue;
    }
    failing.push_back(&r);
  }
  for (std::size_t i = 0; i < failing.size(); ++i) {
    if (budget != nullptr && budget->spent()) {
      unbudgeted[static_cast<std::size_t>(failing[i] - out.data())] = 1;
      continue;
    }
    find_fixes(*failing[i], options);
    if (progress) progress(static_cast<int>(i) + 1, static_cast<int>(failing.size()), "regions: " + failing[i]->name);
  }
  count_unbudgeted();
  return out;
}

BSpline segments_window(const BSpline& spline, int first, int count) {
  const int d = spline.degree(), n = spline.segment_count(), m = spline.unique_point_count();
  // A closed spline's segment i + n is segment i one period on: its span is m further.
  auto span = [&](int i) { return spline.segments()[static_cast<std::size_t>(((i % n) + n) % n)].span + (i >= n ? m : 0); };
  const int j0 = span(first), j1 = span(first + count - 1);
  std::vector<double> period;
  if (spline.closed()) period = spline.period_knots();
  const double T = spline.closed() ? period.back() - period.front() : 0;
  auto knot = [&](int k) {
    if (!spline.closed()) return spline.knots()[static_cast<std::size_t>(k)];
    const int i = k - d + 1;  // the periodic extension's index (BSpline::make_closed)
    const int q = i >= 0 ? i / m : -((-i + m - 1) / m);
    return period[static_cast<std::size_t>(i - q * m)] + q * T;
  };
  std::vector<double> knots, weights;
  std::vector<Vec2> points;
  for (int k = j0 - d + 1; k <= j1 + d; ++k) knots.push_back(knot(k));
  for (int k = j0 - d + 1; k <= j1 + 1; ++k) {
    const int p = spline.closed() ? ((k % m) + m) % m : k;
    points.push_back(spline.points()[static_cast<std::size_t>(p)]);
    if (spline.is_rational()) weights.push_back(spline.weight(p));
  }
  return BSpline::make(d, std::move(knots), std::move(points), spline.name(), std::move(weights));
}

}  // namespace cmr::report
