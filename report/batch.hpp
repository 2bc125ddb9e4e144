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

/// Called after each spline is analysed, then after each failing one has its
/// regions: (done, total, name; "regions: name" in the second pass).
using Progress = std::function<void(int, int, const std::string&)>;
/// Reports a batch: per item on options.threads threads the model, its gates
/// and (with regions and options.certified_fixes on) the certified fixes of
/// each failing check; then, one spline at a time, the region fixes of each spline that
/// fails the requirement. An input error of one item becomes that item's
/// error; the others go on.
std::vector<SplineReport> report_batch(std::vector<ReportInput> inputs, const ReportOptions& options,
                                       const Progress& progress = {});

}  // namespace cmr::report
