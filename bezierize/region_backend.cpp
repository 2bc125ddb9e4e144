// RegionProblem (validation and preparation, once) and the CPU backend.
#include <chrono>

#include "bezierize/region_setup.hpp"

namespace cmr {

RegionProblem RegionProblem::make(const BSpline& spline, const RegionRequest& request) {
  return RegionProblem(std::make_shared<const detail::RegionSetup>(detail::prepare_region(spline, request)));
}

std::vector<RegionProblem> RegionProblem::make_each(const BSpline& spline, const RegionRequest& request,
                                                   const std::vector<int>& points) {
  std::vector<RegionProblem> out;
  std::shared_ptr<const detail::RegionBase> base;
  for (int k : points) {
    RegionRequest r = request;
    r.point = k;
    // Validate before the (one) analysis: a bad request fails fast.
    if (!base) {
      detail::validate_region_options(spline, r);
      base = detail::region_base(spline, r.max_depth);
    }
    out.push_back(RegionProblem(std::make_shared<const detail::RegionSetup>(detail::prepare_region(spline, r, base))));
  }
  return out;
}

const BSpline& RegionProblem::spline() const { return setup_->spline(); }

const RegionRequest& RegionProblem::request() const { return setup_->options; }

RegionPixel RegionProblem::classify(Vec2 position) const {
  return detail::to_pixel(detail::classify_position(*setup_, position), detail::labels_of(request()));
}

RegionResult CpuRegionBackend::render(const RegionProblem& problem) {
  const auto t0 = std::chrono::steady_clock::now();
  RegionResult r = detail::to_result(detail::region_cpu(problem.setup(), threads_),
                                        detail::labels_of(problem.request()));
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace cmr
