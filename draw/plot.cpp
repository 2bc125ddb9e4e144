#include "draw/draw.hpp"
#include "draw/draw_detail.hpp"
#include "draw/cairo_canvas.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "spline/curvature.hpp"
#include "spline/errors.hpp"

// Plots (draw.hpp): a figure's curvature and lambda panels, and line plots as
// PNG. Region pictures and figures are in draw.cpp.

namespace cmr::draw {

using namespace detail;  // the shared helpers (draw_detail.hpp)

namespace {


// --------------------------------------------------------- curvature plot --

struct PlotSample {
  double t, kappa, lambda;
};

/// Samples per segment from the segment's own polynomial; the last sample of
/// each segment is its end value (curvature_at would take the next segment's).
/// Where the curve is not drawn (near a pole: CurveSampler) kappa is NaN, and
/// the plot leaves it out.
std::vector<std::vector<PlotSample>> sample_curvature(const BSpline& s, int per_segment) {
  std::vector<std::vector<PlotSample>> out;
  const CurveSampler sampler(s);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const Segment& seg : s.segments()) {
    std::vector<PlotSample> v;
    for (int k = 0; k < per_segment; ++k) {
      const CurvatureSample c = curvature_at(s, seg.a + (seg.b - seg.a) * k / per_segment);
      v.push_back({c.t, sampler.inside(c.point) ? c.kappa : nan, c.lambda});
    }
    const double end = sampler.inside(evaluate(s, seg.b)) ? segment_end_curvature(s, seg, 1) : nan;
    v.push_back({seg.b, end, v.back().lambda});
    out.push_back(std::move(v));
  }
  return out;
}

std::string short_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

Rgb class_colour(Curvature c) {
  switch (c) {
    case Curvature::increasing: return {0.85, 0.1, 0.1};
    case Curvature::decreasing: return {0.1, 0.2, 0.85};
    case Curvature::constant: return {0.2, 0.2, 0.2};
    default: return {0.75, 0.75, 0.75};  // non-monotone, undecided
  }
}

/// The plot's frame in device coordinates and its world ranges.
struct PlotFrame {
  double left, right, top, bottom;  ///< the plotting rectangle
  double t0, t1, lo, hi;            ///< parameter and curvature ranges
  double px(double t) const { return left + (t - t0) / (t1 - t0) * (right - left); }
  double py(double k) const { return bottom - (k - lo) / (hi - lo) * (bottom - top); }
};

PlotFrame plot_frame(const BSpline& s, const std::vector<std::vector<PlotSample>>& samples, double x, double y,
                     double w, double h) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& seg : samples)
    for (const PlotSample& p : seg) {
      if (!std::isfinite(p.kappa)) continue;  // a cusp, or near a pole
      lo = std::min(lo, p.kappa);
      hi = std::max(hi, p.kappa);
    }
  if (lo > hi) lo = hi = 0;  // nothing finite to plot
  // A flat plot still needs a vertical extent; 5% padding keeps the line off the frame.
  const double pad = std::max(hi - lo, 1e-3 * std::max(std::abs(lo), std::abs(hi)) + 1e-12) * 0.05;
  return {x + 56, x + w - 12, y + 26, y + h - 52, s.domain_begin(), s.domain_end(), lo - pad, hi + pad};
}

/// Joints as dashed lines, the kappa = 0 line (crossings are inflections),
/// the frame, the y extremes, and knot ticks with their values.
void draw_plot_axes(cairo_t* cr, const BSpline& s, const PlotFrame& f, double x, Labels& labels) {
  const double dash[] = {4, 3};
  cairo_set_line_width(cr, 1);
  set_colour(cr, {0.6, 0.6, 0.6});
  cairo_set_dash(cr, dash, 2, 0);
  for (std::size_t i = 1; i < s.segments().size(); ++i) {
    cairo_move_to(cr, f.px(s.segments()[i].a), f.top);
    cairo_line_to(cr, f.px(s.segments()[i].a), f.bottom);
  }
  cairo_stroke(cr);
  if (f.lo < 0 && f.hi > 0) {
    set_colour(cr, {0.3, 0.3, 0.3});
    cairo_move_to(cr, f.left, f.py(0));
    cairo_line_to(cr, f.right, f.py(0));
    cairo_stroke(cr);
  }
  cairo_set_dash(cr, nullptr, 0, 0);
  set_colour(cr, {0, 0, 0});
  cairo_rectangle(cr, f.left, f.top, f.right - f.left, f.bottom - f.top);
  cairo_stroke(cr);
  // The y range's ends first, then kappa = 0 where it fits between them.
  labels.put(cr, x + 4, f.top + 10, short_number(f.hi), 11);
  labels.put(cr, x + 4, f.bottom, short_number(f.lo), 11);
  if (f.lo < 0 && f.hi > 0) labels.put(cr, x + 4, f.py(0) + 4, "0", 11);
  double last_knot = -1e300;
  for (double u : s.knots()) {
    if (u < f.t0 || u > f.t1) continue;
    cairo_move_to(cr, f.px(u), f.bottom);
    cairo_line_to(cr, f.px(u), f.bottom + 6);
    cairo_stroke(cr);
    if (u == last_knot) continue;  // repeated knots share one label
    last_knot = u;
    const std::string label = short_number(u);
    cairo_set_font_size(cr, 11);
    labels.put(cr, f.px(u) - 0.5 * text_width(cr, label), f.bottom + 18, label, 11);  // left out where crowded
  }
}

/// The curvature, red where kappa increases, blue where it decreases.
void draw_plot_curve(cairo_t* cr, const std::vector<std::vector<PlotSample>>& samples, const PlotFrame& f) {
  cairo_save(cr);
  cairo_rectangle(cr, f.left, f.top, f.right - f.left, f.bottom - f.top);
  cairo_clip(cr);
  cairo_set_line_width(cr, 2.2);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  for (const auto& seg : samples) {
    for (std::size_t k = 1; k < seg.size(); ++k) {
      if (!std::isfinite(seg[k - 1].kappa) || !std::isfinite(seg[k].kappa)) continue;
      const double l = seg[k - 1].lambda;
      set_colour(cr, l > 0 ? Rgb{0.85, 0.1, 0.1} : (l < 0 ? Rgb{0.1, 0.2, 0.85} : Rgb{0.2, 0.2, 0.2}));
      cairo_move_to(cr, f.px(seg[k - 1].t), f.py(seg[k - 1].kappa));
      cairo_line_to(cr, f.px(seg[k].t), f.py(seg[k].kappa));
      cairo_stroke(cr);
    }
  }
  cairo_restore(cr);
}

/// Certified class of each segment (Algorithms 1 and 2, exact) as a band under the axis.
void draw_class_band(cairo_t* cr, const BSpline& s, const SplineAnalysis& analysis, const PlotFrame& f,
                     Labels& labels) {
  const double band = f.bottom + 26;
  for (std::size_t i = 0; i < s.segments().size() && i < analysis.segments.size(); ++i) {
    const Segment& seg = s.segments()[i];
    const SegmentClass& c = analysis.segments[i];
    set_colour(cr, class_colour(c.monotonicity.curvature));
    cairo_rectangle(cr, f.px(seg.a) + 1, band, f.px(seg.b) - f.px(seg.a) - 2, 8);
    cairo_fill(cr);
    std::string tag = to_string(c.monotonicity.curvature);
    if (c.inflection.inflection == Inflection::present) tag += ", inflection";
    set_colour(cr, {0.2, 0.2, 0.2});
    cairo_set_font_size(cr, 10);
    if (text_width(cr, tag) < f.px(seg.b) - f.px(seg.a)) labels.put(cr, f.px(seg.a) + 2, band + 20, tag, 10);
  }
}
}  // namespace

namespace detail {


void draw_curvature_panel(cairo_t* cr, const CurvaturePlot& plot, double x, double y, double w, double h,
                          Labels& labels) {
  CMR_CHECK(plot.spline != nullptr);
  const BSpline& s = *plot.spline;
  const auto samples = sample_curvature(s, std::max(50, 800 / s.segment_count()));
  const PlotFrame f = plot_frame(s, samples, x, y, w, h);
  set_colour(cr, {1, 1, 1});
  cairo_rectangle(cr, x, y, w, h);
  cairo_fill(cr);
  set_colour(cr, {0, 0, 0});
  labels.put(cr, f.left, y + 17, "curvature \xCE\xBA against the parameter t", 13, true);
  draw_plot_axes(cr, s, f, x, labels);
  draw_plot_curve(cr, samples, f);
  if (plot.analysis) draw_class_band(cr, s, *plot.analysis, f, labels);
  set_colour(cr, {0.5, 0.5, 0.5});
  cairo_rectangle(cr, x + 0.5, y + 0.5, w - 1, h - 1);
  cairo_stroke(cr);
}

}  // namespace detail

namespace {

// ------------------------------------------------------------ lambda plot --

double bernstein_at(std::vector<double> c, double t) {
  for (std::size_t r = 1; r < c.size(); ++r)
    for (std::size_t i = 0; i + r < c.size(); ++i) c[i] = (1 - t) * c[i] + t * c[i + 1];
  return c[0];
}

}  // namespace

namespace detail {

void draw_lambda_panel(cairo_t* cr, const LambdaPlot& plot, double x, double y, double w, double h, Labels& labels) {
  CMR_CHECK(plot.xi.size() >= 2);
  const int n = static_cast<int>(plot.xi.size()) - 1;
  std::vector<std::pair<double, double>> curve;
  double lo = 0, hi = 0;  // the range always shows lambda = 0
  for (int k = 0; k <= 200; ++k) {
    const double t = k / 200.0, v = bernstein_at(plot.xi, t);
    curve.push_back({t, v});
    lo = std::min(lo, v), hi = std::max(hi, v);
  }
  for (double c : plot.xi) lo = std::min(lo, c), hi = std::max(hi, c);
  const double pad = std::max(hi - lo, 1e-300) * 0.06;
  const PlotFrame f{x + 56, x + w - 12, y + 26, y + h - 40, 0, 1, lo - pad, hi + pad};
  set_colour(cr, {1, 1, 1});
  cairo_rectangle(cr, x, y, w, h);
  cairo_fill(cr);
  set_colour(cr, {0, 0, 0});
  labels.put(cr, f.left, y + 17, "\xCE\xBB(t) and its Bernstein coefficients \xCE\xBE\xE1\xB5\xA2", 13, true);
  cairo_set_line_width(cr, 1);
  cairo_rectangle(cr, f.left, f.top, f.right - f.left, f.bottom - f.top);
  cairo_stroke(cr);
  set_colour(cr, {0.3, 0.3, 0.3});
  cairo_move_to(cr, f.left, f.py(0));
  cairo_line_to(cr, f.right, f.py(0));
  cairo_stroke(cr);
  set_colour(cr, {0, 0, 0});
  labels.put(cr, x + 4, f.top + 10, short_number(f.hi), 11);
  labels.put(cr, x + 4, f.bottom, short_number(f.lo), 11);
  labels.put(cr, x + 4, f.py(0) + 4, "0", 11);
  labels.put(cr, f.left - 3, f.bottom + 16, "0", 11);
  labels.put(cr, f.right - 6, f.bottom + 16, "1", 11);
  labels.put(cr, 0.5 * (f.left + f.right) - 3, f.bottom + 16, "t", 11);
  // The coefficients' control polygon, dashed.
  const double dash[] = {4, 3};
  cairo_set_dash(cr, dash, 2, 0);
  set_colour(cr, {0.55, 0.55, 0.55});
  for (int i = 0; i <= n; ++i) {
    const double px = f.px(static_cast<double>(i) / n), py = f.py(plot.xi[i]);
    i == 0 ? cairo_move_to(cr, px, py) : cairo_line_to(cr, px, py);
  }
  cairo_stroke(cr);
  cairo_set_dash(cr, nullptr, 0, 0);
  set_colour(cr, {0, 0, 0});
  cairo_set_line_width(cr, 2.2);
  for (std::size_t k = 0; k < curve.size(); ++k) {
    const double px = f.px(curve[k].first), py = f.py(curve[k].second);
    k == 0 ? cairo_move_to(cr, px, py) : cairo_line_to(cr, px, py);
  }
  cairo_stroke(cr);
  for (int i = 0; i <= n; ++i) {
    const double px = f.px(static_cast<double>(i) / n), py = f.py(plot.xi[i]);
    set_colour(cr, plot.xi[i] > 0 ? Rgb{0.85, 0.1, 0.1} : (plot.xi[i] < 0 ? Rgb{0.1, 0.2, 0.85} : Rgb{0.3, 0.3, 0.3}));
    cairo_arc(cr, px, py, 4.5, 0, 2 * M_PI);
    cairo_fill(cr);
    std::string name = "\xCE\xBE";  // xi
    name += std::to_string(i);
    set_colour(cr, {0.15, 0.15, 0.15});
    // Above a dot on the upper side of zero, below one on the lower side; else the other side.
    const double up = py - 8, down = py + 17;
    const bool above = plot.xi[i] >= 0;
    if (!labels.put(cr, px - 6, above ? up : down, name, 11)) labels.put(cr, px - 6, above ? down : up, name, 11);
  }
  set_colour(cr, {0.5, 0.5, 0.5});
  cairo_set_line_width(cr, 1);
  cairo_rectangle(cr, x + 0.5, y + 0.5, w - 1, h - 1);
  cairo_stroke(cr);
}
}  // namespace detail

std::string line_plot_png(const LinePlot& plot, PlotArea* area) {
  Surface surface = make_surface(plot.width, plot.height);
  Context cr = make_context(surface.get());
  cairo_t* c = cr.get();
  set_colour(c, {1, 1, 1});
  cairo_paint(c);
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  bool any = false;
  for (const Series& s : plot.series)
    for (const auto& [x, y] : s.points) {
      if (!std::isfinite(x) || !std::isfinite(y)) continue;
      if (!any) x0 = x1 = x, y0 = y1 = y, any = true;
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  if (y0 >= 0) y0 = 0;
  if (!(x1 > x0)) x0 -= 0.5, x1 += 0.5;
  if (!(y1 > y0)) y1 = y0 + 1;
  y1 += 0.05 * (y1 - y0);
  const double left = 80, right = plot.width - 20, top = 40, bottom = plot.height - 60;
  const PlotArea frame{plot.width, plot.height, left, right, top, bottom, x0, x1, y0, y1};
  if (area != nullptr) *area = frame;
  auto px = [&](double x) { return frame.px(x); };
  auto py = [&](double y) { return frame.py(y); };
  set_colour(c, {0, 0, 0});
  text_at(c, left, 24, plot.title, 15, true);
  cairo_set_line_width(c, 1);
  cairo_rectangle(c, left, top, right - left, bottom - top);
  cairo_stroke(c);
  for (int k = 0; k <= 4; ++k) {
    const double xv = x0 + (x1 - x0) * k / 4, yv = y0 + (y1 - y0) * k / 4;
    set_colour(c, {0.85, 0.85, 0.85});
    cairo_move_to(c, px(xv), top);
    cairo_line_to(c, px(xv), bottom);
    cairo_move_to(c, left, py(yv));
    cairo_line_to(c, right, py(yv));
    cairo_stroke(c);
    set_colour(c, {0, 0, 0});
    const std::string xs = short_number(xv), ys = short_number(yv);
    text_at(c, px(xv) - text_width(c, xs) / 2, bottom + 16, xs, 11);
    cairo_set_font_size(c, 11);
    text_at(c, left - 6 - text_width(c, ys), py(yv) + 4, ys, 11);
  }
  text_at(c, (left + right) / 2 - 40, bottom + 36, plot.x_label, 12);
  cairo_save(c);
  cairo_move_to(c, 18, (top + bottom) / 2 + 40);
  cairo_rotate(c, -std::numbers::pi / 2);
  cairo_set_font_size(c, 12);
  cairo_show_text(c, plot.y_label.c_str());
  cairo_restore(c);
  double ly = top + 16;
  for (const Series& s : plot.series) {
    set_colour(c, s.colour);
    cairo_set_line_width(c, 2);
    bool first = true;
    for (const auto& [x, y] : s.points) {
      if (!std::isfinite(x) || !std::isfinite(y)) continue;
      if (first) cairo_move_to(c, px(x), py(y));
      else cairo_line_to(c, px(x), py(y));
      first = false;
    }
    cairo_stroke(c);
    cairo_move_to(c, right - 170, ly - 4);
    cairo_line_to(c, right - 150, ly - 4);
    cairo_stroke(c);
    set_colour(c, {0, 0, 0});
    text_at(c, right - 144, ly, s.name, 11);
    ly += 16;
  }
  return encode_png(surface.get());
}

}  // namespace cmr::draw
