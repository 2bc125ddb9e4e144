#pragma once
/// The report pipeline of `cmr report`: report -> gates -> fixes.
///
/// report.hpp builds the model of a spline (report_spline: classification,
/// roots, joints, events); gates.hpp judges a model (check_gates); this
/// step runs them in that order and adds the fixes: the smallest certified
/// fix of each failing check (certified_fixes, report/certified_fix.hpp: the
/// moved spline re-judged by analyze) and the region fixes of a failing
/// requirement (find_fixes). Nothing runs back
/// up: the model knows neither gates nor fixes, the gates do not re-report.
#include <atomic>
#include <cstdint>
#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "report/gates.hpp"
#include "report/report.hpp"

namespace cmr::report {

/// Judges options.gates on a report model: fills report.gates and folds them
/// into report.pass (every gate must pass).
void judge_gates(SplineReport& report, const ReportOptions& options);

/// The options that judge a moved spline in a fix search: `options` with
/// no region images, no fixes, no severity and one thread (the search runs
/// on its own threads); with `gate`, that gate alone and no requirement.
ReportOptions judge_only(const ReportOptions& options, const std::optional<Gate>& gate = std::nullopt);

/// report_spline, then judge_gates: one spline's report with its gates (no
/// fixes). Throws InputError as report_spline.
SplineReport judged_report(const BSpline& spline, const ReportOptions& options);
/// judged_report for a judge that reads the gates (and the joints, spans and
/// events they are made of), not the segments' classes: without a
/// requirement and without the each-piece gate, the only readers of
/// Algorithm 1 and 2, those are not run (report_spline(..., false)), and the
/// gates' violations and verdicts are judged_report's. The search judges of
/// the severity, the glyph fix and the certified fixes.
SplineReport gate_report(const BSpline& spline, const ReportOptions& options);
/// Segments [first, first + count) of `spline` (indices taken cyclically on
/// a closed spline) as an open spline of their own, with the same polar
/// knots and control points (for a closed spline, its periodic extension):
/// each of its segments is the same polynomial piece as the spline's.
BSpline segments_window(const BSpline& spline, int first, int count);

/// gate_report's model before its gates are judged (check_gates judges any
/// of options' checks on it: a search that judges two sets of the same
/// checks on one spline builds it once).
SplineReport gate_model(const BSpline& spline, const ReportOptions& options);

/// The most control points a spline may have for its fix searches
/// (find_fixes renders one region image per control point, ~9 ms each at
/// 96 x 96 on this 2-core machine: 512 points are ~5 s; a certified fix
/// re-analyses the whole spline per candidate, and a 32,000-point contour's
/// search took more than 1.3 GB); a larger spline is reported and judged
/// without fixes (FixBudget::too_large).
inline constexpr int kMaxRegionFixPoints = 512;
/// The default of `cmr report --fix-budget` (seconds for all fix searches of a run).
inline constexpr double kDefaultFixBudgetSeconds = 20;

/// The time a run gives its fix searches (the region fixes and the certified
/// fixes of failing splines), shared by all its files and threads: a search
/// not started before `deadline` is skipped, and the spline is reported and
/// judged without it (counted in `skipped`). Each search already started
/// finishes (a certified fix search stops at kReportFixSeconds, a region fix
/// search renders at most kMaxRegionFixPoints images).
struct FixBudget {
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
  double seconds = 0;                ///< what the deadline was set from (0: none; for the note)
  std::atomic<int> skipped{0};       ///< failing splines without fixes: the budget was spent
  std::atomic<int> too_large{0};     ///< failing splines without fixes: more than kMaxRegionFixPoints points
  /// A budget of `seconds` from now (<= 0: none).
  void start(double budget_seconds);
  /// Time the run spent on severity (report/severity.hpp), per thread:
  /// it moves the deadline, so that the budget is the fix searches' alone.
  std::atomic<std::int64_t> severity_ns{0};
  bool spent() const {
    return deadline != std::chrono::steady_clock::time_point::max() &&
           std::chrono::steady_clock::now() > deadline + std::chrono::nanoseconds(severity_ns.load());
  }
  /// The note for the run's stderr and page ("" when nothing was skipped).
  std::string note() const;
};

/// Called after each spline is analysed, then after each failing one has its
/// regions: (done, total, name; "regions: name" in the second pass).
using Progress = std::function<void(int, int, const std::string&)>;
/// Reports a batch: per item on options.threads threads the model, its gates
/// and (with regions and options.certified_fixes on) the certified fixes of
/// each failing check; then, one spline at a time, the region fixes of each spline that
/// fails the requirement. An input error of one item becomes that item's
/// error; the others go on.
/// With `budget`, the fix searches are budgeted as FixBudget says.
std::vector<SplineReport> report_batch(std::vector<ReportInput> inputs, const ReportOptions& options,
                                       const Progress& progress = {}, FixBudget* budget = nullptr);

}  // namespace cmr::report
