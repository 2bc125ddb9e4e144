#include "region/weight_region.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <string>

#include "bezierize/analyze.hpp"
#include "spline/errors.hpp"
#include "spline/fields.hpp"
#include "spline/parallel.hpp"

namespace cmr {

BSpline with_weight(const BSpline& spline, int k, double w) {
  if (k < 0 || k >= spline.point_count())
    throw InputError("point " + std::to_string(k) + " is outside 0.." + std::to_string(spline.point_count() - 1));
  const int m = spline.unique_point_count();
  if (spline.closed() && k >= m) k -= m;  // the twin of an unrolled point
  std::vector<double> weights(static_cast<std::size_t>(m));
  for (int i = 0; i < m; ++i) weights[i] = spline.weight(i);
  weights[k] = w;
  if (spline.closed()) {
    std::vector<Vec2> points(spline.points().begin(), spline.points().begin() + m);
    return BSpline::make_closed(spline.degree(), spline.period_knots(), std::move(points), spline.name(),
                                std::move(weights));
  }
  return BSpline::make(spline.degree(), spline.knots(), spline.points(), spline.name(), std::move(weights));
}

WeightState weight_state(const BSpline& spline, const WeightRegionRequest& r, double w) {
  const SplineAnalysis a = analyze(with_weight(spline, r.point, w), region_analyze_options(r.labels));
  bool pole = false;
  for (int i = 0; i < static_cast<int>(a.shapes.size()); ++i) pole = pole || (a.judged(i) && a.shapes[i].pole);
  return {region_label_code(a, r.labels), pole};
}

std::uint8_t weight_label(const BSpline& spline, const WeightRegionRequest& r, double w) {
  return weight_state(spline, r, w).label;}

namespace {

std::string number(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

void validate(const BSpline& spline, const WeightRegionRequest& r) {
  if (r.point < 0 || r.point >= spline.point_count())
    throw InputFieldError(field("WeightRegionRequest::point") + ": point " + std::to_string(r.point) +
                          " is outside 0.." + std::to_string(spline.point_count() - 1));
  if (!std::isfinite(r.from) || !std::isfinite(r.to))
    throw InputFieldError(field("from") + "/" + field("to") + ": the weights must be finite numbers");
  if (!(r.from < r.to))
    throw InputFieldError(field("from") + " " + number(r.from) + " must be smaller than " + field("to") + " " +
                          number(r.to));
  if (r.samples < 2 || r.samples > kMaxWeightSamples)
    throw InputFieldError(field("samples") + ": " + std::to_string(r.samples) + " is outside 2.." +
                          std::to_string(kMaxWeightSamples));
  if (!(r.tolerance > 0 && r.tolerance < 1)) throw InputError("weight region: the tolerance must lie in (0, 1)");
  for (const auto& [w, option] : {std::pair{r.from, field("from")}, std::pair{r.to, field("to")}}) {
    try {
      (void)with_weight(spline, r.point, w);
    } catch (const InputError& e) {
      throw InputFieldError(option + " " + number(w) + ": " + marked_text(e));
    }
  }
  // The label options (split, segments, depth) are validated by analyze.
  (void)analyze(spline, region_analyze_options(r.labels));
}

struct Boundary {
  double left, right;
  WeightState left_state, right_state;
};

}  // namespace

WeightRegion weight_region(const BSpline& spline, const WeightRegionRequest& r) {
  validate(spline, r);
  WeightRegion out;
  out.kind.split = r.labels.split.has_value();
  out.kind.alternating = !r.labels.splits.empty();
  const int n = r.samples;
  std::vector<double> w(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) w[i] = i == n - 1 ? r.to : r.from + (r.to - r.from) * i / (n - 1);
  std::vector<WeightState> label(w.size());
  std::atomic<int> evaluations{0};
  const auto label_at = [&](double x) {
    ++evaluations;
    return weight_state(spline, r, x);
  };
  parallel_for(w.size(), r.threads, [&](std::size_t i) { label[i] = label_at(w[i]); });

  // Each step whose ends differ: bisect every half whose ends differ, so
  // that a third label met inside is kept, down to the tolerance.
  const double width = r.tolerance * (r.to - r.from);
  std::vector<std::size_t> changes;
  for (std::size_t i = 0; i + 1 < w.size(); ++i)
    if (label[i] != label[i + 1]) changes.push_back(i);
  std::vector<std::vector<Boundary>> found(changes.size());
  parallel_for(changes.size(), r.threads, [&](std::size_t c) {
    const std::size_t i = changes[c];
    std::vector<Boundary>& list = found[c];
    const auto resolve = [&](auto&& self, double a, WeightState la, double b, WeightState lb) -> void {
      if (la == lb) return;
      const double m = a + (b - a) / 2;
      if (b - a <= width || !(m > a && m < b)) {
        list.push_back({a, b, la, lb});
        return;
      }
      const WeightState lm = label_at(m);
      self(self, a, la, m, lm);
      self(self, m, lm, b, lb);
    };
    resolve(resolve, w[i], label[i], w[i + 1], label[i + 1]);
  });

  double start = r.from;
  WeightState current = label.front();
  for (const std::vector<Boundary>& list : found)
    for (const Boundary& b : list) {
      CMR_CHECK(b.left_state == current);
      out.intervals.push_back({start, b.left, current.label, current.pole});
      start = b.right;
      current = b.right_state;
    }
  CMR_CHECK(current == label.back());
  out.intervals.push_back({start, r.to, current.label, current.pole});
  out.evaluations = evaluations.load();
  return out;
}

}  // namespace cmr
