// RegionProblem (validation and preparation, once) and the CPU backend.
#include <chrono>
#include <cmath>
#include <string>

#include "region/region_setup.hpp"

namespace cmr {

RegionProblem RegionProblem::make(const BSpline& spline, const RegionRequest& request) {
  return RegionProblem(std::make_shared<const backend::RegionSetup>(backend::prepare_region(spline, request)));
}

std::vector<RegionProblem> RegionProblem::make_each(const BSpline& spline, const RegionRequest& request,
                                                   const std::vector<int>& points) {
  std::vector<RegionProblem> out;
  std::shared_ptr<const backend::RegionBase> base;
  for (int k : points) {
    RegionRequest r = request;
    r.point = k;
    // Validate before the (one) analysis: a bad request fails fast.
    if (!base) {
      backend::validate_region_options(spline, r);
      base = backend::region_base(spline, r.max_depth);
    }
    out.push_back(RegionProblem(std::make_shared<const backend::RegionSetup>(backend::prepare_region(spline, r, base))));
  }
  return out;
}

const BSpline& RegionProblem::spline() const { return setup_->spline(); }

const RegionRequest& RegionProblem::request() const { return setup_->options; }

RegionPixel RegionProblem::classify(Vec2 position) const {
  // Exact classification converts the position to a GMP rational, which
  // raises SIGFPE on NaN or infinity (found by fuzz_region_classify).
  if (!std::isfinite(position.x) || !std::isfinite(position.y))
    throw InputError("position (" + std::to_string(position.x) + ", " + std::to_string(position.y) +
                     ") is not finite");
  return backend::to_pixel(backend::classify_position(*setup_, position), backend::labels_of(request()));
}

RegionResult CpuRegionBackend::render(const RegionProblem& problem) {
  const auto t0 = std::chrono::steady_clock::now();
  RegionResult r = backend::to_result(backend::region_cpu(problem.setup(), threads_));
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace cmr
