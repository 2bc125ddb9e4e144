#include "region/view_fit.hpp"

#include "region/region_setup.hpp"

#include <algorithm>
#include <cstddef>

namespace cmr {

View ViewFit::probe_view(const View& polygon) {
  const double cx = (polygon.x0 + polygon.x1) / 2, cy = (polygon.y0 + polygon.y1) / 2;
  const double hw = 1.5 * std::max(polygon.x1 - polygon.x0, polygon.y1 - polygon.y0);
  return View{cx - hw, cy - hw, cx + hw, cy + hw};
}

int ViewFit::add_region(const RegionResult& probe, const View& view) {
  const double dx = (view.x1 - view.x0) / probe.width, dy = (view.y1 - view.y0) / probe.height;
  int added = 0;
  for (int j = 0; j < probe.height; ++j)
    for (int i = 0; i < probe.width; ++i)
      if (probe.in_region(static_cast<std::size_t>(j) * static_cast<std::size_t>(probe.width) + i)) {
        ++added;  // row 0 is the top
        x0_ = std::min(x0_, view.x0 + i * dx), x1_ = std::max(x1_, view.x0 + (i + 1) * dx);
        y1_ = std::max(y1_, view.y1 - j * dy), y0_ = std::min(y0_, view.y1 - (j + 1) * dy);
      }
  pixels_ += added;
  return added;
}

void ViewFit::add_point(double x, double y) {
  x0_ = std::min(x0_, x), x1_ = std::max(x1_, x), y0_ = std::min(y0_, y), y1_ = std::max(y1_, y);
}

void ViewFit::add_moved_points(const BSpline& spline, const RegionRequest& request) {
  std::vector<int> moved = request.with;
  moved.push_back(request.point);
  for (const int k : moved) {
    if (k < 0 || k >= spline.point_count()) continue;
    const Vec2 p = spline.points()[static_cast<std::size_t>(k)];
    add_point(p.x, p.y);
  }
}

RegionViewFit fit_region_view(const BSpline& spline, const std::vector<RegionRequest>& requests, int probe) {
  RegionViewFit fit;
  fit.probe = probe;
  if (requests.empty()) return fit;
  // The requests as given (their size above all) before any view is made of them.
  for (const RegionRequest& r : requests) backend::validate_region_options(spline, r);
  const RegionRequest& first = requests.front();
  fit.view = default_view(spline, first.width, first.height);
  ViewFit box;
  CpuRegionBackend cpu;
  const auto probe_all = [&](const View& probe_view) {
    fit.probe_pixels.clear();
    for (const RegionRequest& r : requests) {
      RegionRequest p = r;
      p.width = p.height = probe;
      p.view = probe_view;
      p.depth = false;
      fit.probe_pixels.push_back(box.add_region(cpu.render(RegionProblem::make(spline, p)), probe_view));
    }
  };
  probe_all(ViewFit::probe_view(fit.view));
  // Nothing in the wide probe: a region smaller than its pixels may still lie
  // near the curve; a second probe over the polygon's square (3 times finer).
  if (box.empty()) {
    const View wide = ViewFit::probe_view(fit.view);
    const double cx = (wide.x0 + wide.x1) / 2, cy = (wide.y0 + wide.y1) / 2, h = (wide.x1 - wide.x0) / 6;
    probe_all(View{cx - h, cy - h, cx + h, cy + h});
  }
  if (box.empty()) return fit;
  fit.empty = false;
  int all = 0;
  for (const int n : fit.probe_pixels) all += n;
  if (all == probe * probe * static_cast<int>(requests.size())) {
    fit.full = true;
    return fit;
  }
  for (const RegionRequest& r : requests) box.add_moved_points(spline, r);
  fit.view = box.view(first.width, first.height);
  return fit;
}

View ViewFit::view(int width, int height) const {
  double x0 = x0_, y0 = y0_, x1 = x1_, y1 = y1_;
  const double margin = 0.15 * std::max(x1 - x0, y1 - y0);
  x0 -= margin, x1 += margin, y0 -= margin, y1 += margin;
  const double aspect = static_cast<double>(width) / height;
  if ((x1 - x0) / (y1 - y0) < aspect) {
    const double c = (x0 + x1) / 2, h = (y1 - y0) * aspect / 2;
    x0 = c - h, x1 = c + h;
  } else {
    const double c = (y0 + y1) / 2, h = (x1 - x0) / aspect / 2;
    y0 = c - h, y1 = c + h;
  }
  return View{x0, y0, x1, y1};
}

}  // namespace cmr
