#include "tools/edit/engine.hpp"

#include <algorithm>
#include <cmath>

#include "bezierize/extract.hpp"
#include "bezierize/knot_ops.hpp"
#include "spline/errors.hpp"
#include "spline/parallel.hpp"
#include "tools/draw.hpp"
#include "tools/report.hpp"

namespace cmr::edit {

std::vector<RegionResult> compute_regions(const BSpline& spline, const RegionQuery& query) {
  std::vector<RegionResult> layers;
  layers.reserve(query.points.size());
  CpuRegionBackend backend;  // all cores
  for (int k : query.points) {
    RegionRequest o;
    o.point = k;
    if (query.points.size() == 1) o.with = query.with;
    o.mode = query.mode;
    o.split = query.split;
    o.max_depth = query.max_depth;
    o.width = query.width;
    o.height = query.height;
    o.view = query.view;
    o.depth = query.depth_map;
    layers.push_back(backend.render(RegionProblem::make(spline, o)));
  }
  return layers;
}

std::vector<uint8_t> region_rgba(const std::vector<RegionResult>& layers, bool split, bool depth_shading,
                                 int max_depth) {
  if (layers.empty()) return {};
  draw::RegionPicture picture;
  for (const RegionResult& l : layers) picture.layers.push_back(&l);
  picture.split = split;
  picture.depth_shading = depth_shading;
  picture.max_depth = max_depth;
  const std::size_t count = layers.front().size();
  std::vector<uint8_t> rgba(count * 4);
  // Rows in parallel: the colour of a pixel depends on that pixel alone, so a
  // pixel whose labels (and levels, when shaded) equal its left neighbour's
  // takes that colour without recomputing it (regions are mostly runs).
  const int width = layers.front().width;
  const auto byte = [](double c) { return static_cast<uint8_t>(std::lround(255 * std::clamp(c, 0.0, 1.0))); };
  const auto same_as_left = [&](std::size_t i) {
    for (const RegionResult& l : layers) {
      if (l.code_at(i) != l.code_at(i - 1) || (depth_shading && l.depth[i] != l.depth[i - 1])) return false;
    }
    return true;
  };
  parallel_for(static_cast<std::size_t>(layers.front().height), 0, [&](std::size_t row) {
    for (std::size_t i = row * width; i < (row + 1) * width; ++i) {
      if (i > row * width && same_as_left(i)) {
        std::copy_n(&rgba[4 * (i - 1)], 4, &rgba[4 * i]);
        continue;
      }
      const draw::Rgb c = draw::pixel_colour(picture, i);
      rgba[4 * i] = byte(c.r);
      rgba[4 * i + 1] = byte(c.g);
      rgba[4 * i + 2] = byte(c.b);
      rgba[4 * i + 3] = 255;
    }
  });
  return rgba;
}

SplineAnalysis verdicts(const BSpline& spline, int max_depth, std::optional<int> split, Mode mode) {
  AnalyzeOptions o;
  o.classify.max_depth = max_depth;
  o.split = split;
  o.split_mode = mode;
  return analyze(spline, o);
}

CurvatureEvents curvature_events(const BSpline& spline, int max_depth) {
  report::ReportOptions o;
  o.max_depth = max_depth;
  o.regions = false;
  o.threads = 1;
  const report::SplineReport r = report::report_spline(spline, o);
  CurvatureEvents e;
  for (const report::CurveEvent& x : r.extrema) (x.kind > 0 ? e.maxima : e.minima).push_back(x.t);
  for (const report::CurveEvent& x : r.inflections) e.inflections.push_back(x.t);
  return e;
}

KnotResult knot_operation(const BSpline& spline, const std::string& name, double a, double b) {
  if (name == "insert") {
    if (!(a > spline.domain_begin() && a < spline.domain_end()))
      throw InputError("insert: knot " + std::to_string(a) + " is not inside the domain");
    const int times = b > 0 ? static_cast<int>(b) : 1;
    // knot_ops' blossom insertion: also for rational splines (homogeneous).
    const BSpline s = insert_knot(spline, a, times);
    return {s, "inserted knot " + std::to_string(a) + " x" + std::to_string(times)};
  }
  throw InputError("knot operation '" + name + "' is not available in this build");
}

}  // namespace cmr::edit
