// The report on a large batch: 1,000 seeded random cubic B-splines of 10
// segments each, analysed (roots included) and rendered to JSON and HTML in
// memory, without regions. Prints the wall time of each stage and the total
// (target: under 2 s on a 2-core machine).
//   build/tools/bench/bench_report [SPLINES]
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "report/batch.hpp"

namespace {

// 13 control points marching along x with random heights, uniform polar
// knots 0..14: segments [2,3] .. [11,12].
cmr::BSpline random_spline(std::mt19937_64& rng, int index) {
  std::uniform_real_distribution<double> jitter(-0.3, 0.3), height(-1.0, 1.0);
  std::vector<cmr::Vec2> points;
  for (int i = 0; i < 13; ++i) points.emplace_back(i + jitter(rng), height(rng));
  std::vector<double> knots;
  for (int i = 0; i < 15; ++i) knots.push_back(i);
  return cmr::BSpline::make(3, std::move(knots), std::move(points), "random " + std::to_string(index));
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

int main(int argc, char** argv) {
  const int count = argc > 1 ? std::atoi(argv[1]) : 1000;
  std::mt19937_64 rng(6);
  std::vector<cmr::report::ReportInput> inputs;
  for (int i = 0; i < count; ++i) inputs.push_back({"random" + std::to_string(i) + ".json", random_spline(rng, i), {}});
  cmr::report::ReportOptions options;
  options.regions = false;
  options.require = cmr::report::Requirement{};

  const std::clock_t cpu_start = std::clock();
  const auto start = std::chrono::steady_clock::now();
  const auto reports = cmr::report::report_batch(std::move(inputs), options);
  const double analysed = seconds_since(start);
  const std::string json = cmr::report::report_json(reports, options).dump(2);
  const double with_json = seconds_since(start);
  const std::string html = cmr::report::report_html(reports, options);
  const double total = seconds_since(start);

  std::size_t extrema = 0, inflections = 0;
  for (const auto& r : reports) {
    extrema += r.extrema.size();
    inflections += r.inflections.size();
  }
  std::printf("report of %d cubic splines x 10 segments (%zu curvature extrema, %zu inflections)\n", count, extrema,
              inflections);
  std::printf(
      "  analysis + roots  %.3f s\n  JSON              %.3f s (%.1f MB)\n  HTML              %.3f s (%.1f MB)\n",
      analysed, with_json - analysed, json.size() / 1e6, total - with_json, html.size() / 1e6);
  // CPU time over all threads: the wall time is that over the cores when the machine is otherwise idle.
  std::printf("total %.3f s (CPU %.3f s)\n", total, double(std::clock() - cpu_start) / CLOCKS_PER_SEC);
  return 0;
}
