// Library example: the analysis and the QA report of a spline file from C++,
// in memory (no command line, no files written). Built with the project and
// run by ctest; the README's "Library" section shows the same lines.
//
//   analysis_example SPLINE.json
//
// Prints the verdicts and the report's sizes; exit 2 for an invalid file.
#include <iostream>

#include "bezierize/analyze.hpp"
#include "spline/errors.hpp"
#include "spline/spline_json.hpp"
#include "report/report.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: analysis_example SPLINE.json\n";
    return 2;
  }
  try {
    // Analysis: Algorithms 1 and 2 on every segment, and the spline's verdicts.
    const cmr::BSpline spline = cmr::read_spline_file(argv[1]);
    const cmr::SplineAnalysis analysis = cmr::analyze(spline);
    std::cout << "CMRWI " << cmr::to_string(analysis.cmrwi) << ", CMR " << cmr::to_string(analysis.cmr) << '\n';

    // Report: extrema, inflections, joints; JSON (cmr-report/2) and HTML as strings.
    cmr::report::ReportOptions options;  // judged by CMR, depth kDefaultDepth
    const std::vector<cmr::report::SplineReport> reports = {cmr::report::report_spline(spline, options)};
    const std::string json = cmr::report::report_json(reports, options).dump(2);
    const std::string html = cmr::report::report_html(reports, options);

    std::cout << reports[0].extrema.size() << " curvature extrema, " << reports[0].inflections.size()
              << " inflections; " << (reports[0].pass ? "pass" : "fail") << "; JSON " << json.size() << " bytes, HTML "
              << html.size() << " bytes\n";
    return html.rfind("<!DOCTYPE html>", 0) == 0 && !json.empty() ? 0 : 1;
  } catch (const cmr::InputError& e) {
    std::cerr << "analysis_example: " << e.what() << '\n';
    return 2;
  }
}
