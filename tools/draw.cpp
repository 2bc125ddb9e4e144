#include "tools/draw.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <new>

#include "spline/curvature.hpp"
#include "spline/errors.hpp"
#include "tools/io.hpp"

namespace cmr::draw {

namespace {

// ---------------------------------------------------------------- colours --

// What one layer takes away from white; layers add up (Fig. 3's rule).
using Absorb = Rgb;

constexpr Absorb kNone{0, 0, 0};
constexpr Absorb kRed{0, 0.6, 0.6};          // white - this = (1, .4, .4)
constexpr Absorb kBlue{0.6, 0.6, 0};         // (.4, .4, 1)
constexpr Absorb kDarkRed{0.35, 0.85, 0.85};  // (.65, .15, .15)
constexpr Absorb kDarkBlue{0.85, 0.85, 0.35}; // (.15, .15, .65)

Rgb lerp(Rgb a, Rgb b, double s) { return {a.r + s * (b.r - a.r), a.g + s * (b.g - a.g), a.b + s * (b.b - a.b)}; }
Absorb absorb_of(Rgb c) { return {1 - c.r, 1 - c.g, 1 - c.b}; }
Rgb colour_of(Absorb a) { return {std::max(0.0, 1 - a.r), std::max(0.0, 1 - a.g), std::max(0.0, 1 - a.b)}; }

Absorb plain_absorb(uint8_t label) {
  switch (label) {
    case 1: return kRed;
    case 2: return kBlue;
    default: return kNone;  // 0 not monotone, 3 undecided
  }
}

Absorb split_absorb(uint8_t label) {
  switch (label) {
    case 1: return kRed;       // inc-inc
    case 2: return kDarkBlue;  // inc-dec: maximum at the joint
    case 3: return kDarkRed;   // dec-inc: minimum at the joint
    case 4: return kBlue;      // dec-dec
    default: return kNone;     // 0 none, 5 undecided
  }
}

// Fig. 7. Most pixels are decided within a few levels, so the shade saturates
// (d / (d + 2)) instead of growing linearly up to D, which would leave every
// shade but the lightest unused.
Absorb depth_absorb(uint8_t label, uint8_t depth, int max_depth) {
  const double d = std::min<double>(depth, std::max(max_depth, 0));
  const double s = d / (d + 2.0);
  switch (label) {
    case 1: return absorb_of(lerp({1, 0.72, 0.72}, {0.45, 0, 0}, s));
    case 2: return absorb_of(lerp({0.72, 0.72, 1}, {0, 0, 0.45}, s));
    default: return absorb_of(lerp({0.92, 0.92, 0.92}, {0.25, 0.25, 0.25}, s));  // not monotone, undecided
  }
}

// ------------------------------------------------------------ cairo helpers --

using Surface = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
using Context = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;

Surface make_surface(int width, int height) {
  Surface s(cairo_image_surface_create(CAIRO_FORMAT_ARGB32, width, height), &cairo_surface_destroy);
  if (cairo_surface_status(s.get()) != CAIRO_STATUS_SUCCESS) throw std::bad_alloc();
  return s;
}

Context make_context(cairo_surface_t* surface) {
  Context cr(cairo_create(surface), &cairo_destroy);
  if (cairo_status(cr.get()) != CAIRO_STATUS_SUCCESS) throw std::bad_alloc();
  return cr;
}

void set_colour(cairo_t* cr, Rgb c) { cairo_set_source_rgb(cr, c.r, c.g, c.b); }

/// Appends each chunk Cairo's PNG encoder hands over to a std::string.
cairo_status_t append_png_chunk(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

/// The surface encoded as PNG bytes, in memory. Encoding can only fail for
/// lack of memory.
std::string encode_png(cairo_surface_t* surface) {
  cairo_surface_flush(surface);
  std::string bytes;
  if (cairo_surface_write_to_png_stream(surface, append_png_chunk, &bytes) != CAIRO_STATUS_SUCCESS)
    throw std::bad_alloc();
  return bytes;
}

void text_at(cairo_t* cr, double x, double y, const std::string& s, double size, bool bold = false) {
  cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_move_to(cr, x, y);
  cairo_show_text(cr, s.c_str());
}

double text_width(cairo_t* cr, const std::string& s) {
  cairo_text_extents_t e;
  cairo_text_extents(cr, s.c_str(), &e);
  return e.x_advance;
}

/// Greedy word wrap at `width` pixels with the current font.
std::vector<std::string> wrap(cairo_t* cr, const std::string& text, double width, double size, bool bold = false) {
  cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  std::vector<std::string> lines;
  std::string line, word;
  auto flush_word = [&] {
    if (word.empty()) return;
    const std::string candidate = line.empty() ? word : line + " " + word;
    if (!line.empty() && text_width(cr, candidate) > width) {
      lines.push_back(line);
      line = word;
    } else {
      line = candidate;
    }
    word.clear();
  };
  for (char c : text) {
    if (c == ' ' || c == '\n') {
      flush_word();
      if (c == '\n') {
        lines.push_back(line);
        line.clear();
      }
    } else {
      word += c;
    }
  }
  flush_word();
  if (!line.empty()) lines.push_back(line);
  return lines;
}

void arrow(cairo_t* cr, double x0, double y0, double x1, double y1) {
  const double len = std::hypot(x1 - x0, y1 - y0);
  if (len < 1) return;
  const double ux = (x1 - x0) / len, uy = (y1 - y0) / len, head = std::min(10.0, 0.5 * len);
  cairo_move_to(cr, x0, y0);
  cairo_line_to(cr, x1 - ux * head * 0.8, y1 - uy * head * 0.8);
  cairo_stroke(cr);
  cairo_move_to(cr, x1, y1);
  cairo_line_to(cr, x1 - ux * head - uy * head * 0.45, y1 - uy * head + ux * head * 0.45);
  cairo_line_to(cr, x1 - ux * head + uy * head * 0.45, y1 - uy * head - ux * head * 0.45);
  cairo_close_path(cr);
  cairo_fill(cr);
}

// ----------------------------------------------------------- region panel --

/// Device coordinates of a world point inside the panel rectangle.
struct WorldMap {
  View v;
  double x, y, w, h;
  std::pair<double, double> operator()(Vec2 p) const {
    return {x + (p.x - v.x0) / (v.x1 - v.x0) * w, y + (v.y1 - p.y) / (v.y1 - v.y0) * h};
  }
};

void check_picture(const RegionPicture& p) {
  CMR_CHECK(p.spline != nullptr);
  CMR_CHECK(!p.layers.empty());
  for (const RegionResult* l : p.layers) {
    CMR_CHECK(l != nullptr);
    CMR_CHECK(l->split == p.split);
    CMR_CHECK(l->width == p.layers[0]->width && l->height == p.layers[0]->height);
    CMR_CHECK((l->split ? l->split_labels.size() : l->labels.size()) == static_cast<std::size_t>(l->width) * l->height);
    CMR_CHECK(l->depth.size() == static_cast<std::size_t>(l->width) * l->height);
  }
}

void draw_labels(cairo_t* cr, const RegionPicture& p, double x, double y, double w, double h) {
  const int W = p.layers[0]->width, H = p.layers[0]->height;
  Surface img = make_surface(W, H);
  cairo_surface_flush(img.get());
  unsigned char* data = cairo_image_surface_get_data(img.get());
  const int stride = cairo_image_surface_get_stride(img.get());
  auto byte = [](double c) { return static_cast<uint32_t>(std::lround(255 * std::clamp(c, 0.0, 1.0))); };
  for (int j = 0; j < H; ++j) {
    auto* row = reinterpret_cast<uint32_t*>(data + static_cast<std::ptrdiff_t>(j) * stride);
    for (int i = 0; i < W; ++i) {
      const Rgb c = pixel_colour(p, static_cast<std::size_t>(j) * W + i);
      row[i] = 0xff000000u | byte(c.r) << 16 | byte(c.g) << 8 | byte(c.b);
    }
  }
  cairo_surface_mark_dirty(img.get());
  cairo_save(cr);
  cairo_translate(cr, x, y);
  cairo_scale(cr, w / W, h / H);
  cairo_set_source_surface(cr, img.get(), 0, 0);
  // Labels are exact per pixel: no smoothing between them.
  cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
  cairo_paint(cr);
  cairo_restore(cr);
}

/// The control polygon, then the curve over it as a dense polyline.
void draw_polygon_and_curve(cairo_t* cr, const BSpline& s, const WorldMap& map) {
  set_colour(cr, {0.35, 0.35, 0.35});
  cairo_set_line_width(cr, 1.2);
  for (int i = 0; i < s.point_count(); ++i) {
    const auto [px, py] = map(s.points()[i]);
    i == 0 ? cairo_move_to(cr, px, py) : cairo_line_to(cr, px, py);
  }
  cairo_stroke(cr);
  // Enough samples per segment for a smooth look.
  set_colour(cr, {0, 0, 0});
  cairo_set_line_width(cr, 2.2);
  const int per_segment = std::max(64, 600 / s.segment_count());
  bool first = true;
  for (const Segment& seg : s.segments()) {
    for (int k = 0; k <= per_segment; ++k) {
      const auto [px, py] = map(evaluate(s, seg.a + (seg.b - seg.a) * k / per_segment));
      first ? cairo_move_to(cr, px, py) : cairo_line_to(cr, px, py);
      first = false;
    }
  }
  cairo_stroke(cr);
}

/// A moved point: a ring at its old place and an arrow to the new one.
void draw_moved(cairo_t* cr, const std::pair<Vec2, Vec2>& moved, const WorldMap& map) {
  const auto [ox, oy] = map(moved.first);
  const auto [nx, ny] = map(moved.second);
  set_colour(cr, {0.1, 0.55, 0.1});
  cairo_set_line_width(cr, 1.8);
  cairo_arc(cr, ox, oy, 5.5, 0, 2 * M_PI);
  cairo_stroke(cr);
  const double len = std::hypot(nx - ox, ny - oy);
  if (len > 12)
    arrow(cr, ox + (nx - ox) * 6 / len, oy + (ny - oy) * 6 / len, nx - (nx - ox) * 5 / len, ny - (ny - oy) * 5 / len);
}

/// Points and their names, pushed away from the polygon's centre so that
/// they sit outside the curve where they can.
void draw_point_names(cairo_t* cr, const BSpline& s, const WorldMap& map) {
  Vec2 centre(0.0);
  for (const Vec2& q : s.points()) centre += q;
  centre /= static_cast<double>(s.point_count());
  const auto [cx, cy] = map(centre);
  for (int i = 0; i < s.point_count(); ++i) {
    const auto [px, py] = map(s.points()[i]);
    set_colour(cr, {0.1, 0.1, 0.1});
    cairo_arc(cr, px, py, 3.5, 0, 2 * M_PI);
    cairo_fill(cr);
    double dx = px - cx, dy = py - cy;
    const double d = std::hypot(dx, dy);
    dx = d > 1e-9 ? dx / d : 0.7;
    dy = d > 1e-9 ? dy / d : -0.7;
    std::string name = "P";
    name += std::to_string(i);
    cairo_set_font_size(cr, 13);
    text_at(cr, px + 11 * dx - 0.5 * text_width(cr, name), py + 11 * dy + 5, name, 13, true);
  }
}

void draw_region_panel(cairo_t* cr, const RegionPicture& p, double x, double y, double w, double h) {
  check_picture(p);
  const WorldMap map{p.layers[0]->view, x, y, w, h};
  cairo_save(cr);
  cairo_rectangle(cr, x, y, w, h);
  cairo_clip(cr);
  draw_labels(cr, p, x, y, w, h);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  draw_polygon_and_curve(cr, *p.spline, map);
  if (p.moved) draw_moved(cr, *p.moved, map);
  draw_point_names(cr, *p.spline, map);
  cairo_restore(cr);
  set_colour(cr, {0.5, 0.5, 0.5});
  cairo_set_line_width(cr, 1);
  cairo_rectangle(cr, x + 0.5, y + 0.5, w - 1, h - 1);
  cairo_stroke(cr);
}

// --------------------------------------------------------- curvature plot --

struct PlotSample {
  double t, kappa, lambda;
};

/// Samples per segment from the segment's own polynomial; the last sample of
/// each segment is its end value (curvature_at would take the next segment's).
std::vector<std::vector<PlotSample>> sample_curvature(const BSpline& s, int per_segment) {
  std::vector<std::vector<PlotSample>> out;
  for (const Segment& seg : s.segments()) {
    std::vector<PlotSample> v;
    for (int k = 0; k < per_segment; ++k) {
      const CurvatureSample c = curvature_at(s, seg.a + (seg.b - seg.a) * k / per_segment);
      v.push_back({c.t, c.kappa, c.lambda});
    }
    v.push_back({seg.b, segment_end_curvature(s, seg, 1), v.back().lambda});
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
  double lo = samples[0][0].kappa, hi = lo;
  for (const auto& seg : samples)
    for (const PlotSample& p : seg) {
      lo = std::min(lo, p.kappa);
      hi = std::max(hi, p.kappa);
    }
  // A flat plot still needs a vertical extent; 5% padding keeps the line off the frame.
  const double pad = std::max(hi - lo, 1e-3 * std::max(std::abs(lo), std::abs(hi)) + 1e-12) * 0.05;
  return {x + 56, x + w - 12, y + 26, y + h - 52, s.domain_begin(), s.domain_end(), lo - pad, hi + pad};
}

/// Joints as dashed lines, the kappa = 0 line (crossings are inflections),
/// the frame, the y extremes, and knot ticks with their values.
void draw_plot_axes(cairo_t* cr, const BSpline& s, const PlotFrame& f, double x) {
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
    if (f.py(0) - f.top > 14 && f.bottom - f.py(0) > 14) text_at(cr, x + 4, f.py(0) + 4, "0", 11);
  }
  cairo_set_dash(cr, nullptr, 0, 0);
  set_colour(cr, {0, 0, 0});
  cairo_rectangle(cr, f.left, f.top, f.right - f.left, f.bottom - f.top);
  cairo_stroke(cr);
  text_at(cr, x + 4, f.top + 10, short_number(f.hi), 11);
  text_at(cr, x + 4, f.bottom, short_number(f.lo), 11);
  double last_label = -1e9;
  for (double u : s.knots()) {
    if (u < f.t0 || u > f.t1) continue;
    cairo_move_to(cr, f.px(u), f.bottom);
    cairo_line_to(cr, f.px(u), f.bottom + 6);
    cairo_stroke(cr);
    const std::string label = short_number(u);
    if (f.px(u) - last_label < 24) continue;  // repeated knots share one label
    cairo_set_font_size(cr, 11);
    text_at(cr, f.px(u) - 0.5 * text_width(cr, label), f.bottom + 18, label, 11);
    last_label = f.px(u);
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
void draw_class_band(cairo_t* cr, const BSpline& s, const SplineAnalysis& analysis, const PlotFrame& f) {
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
    if (text_width(cr, tag) < f.px(seg.b) - f.px(seg.a)) text_at(cr, f.px(seg.a) + 2, band + 20, tag, 10);
  }
}

void draw_curvature_panel(cairo_t* cr, const CurvaturePlot& plot, double x, double y, double w, double h) {
  CMR_CHECK(plot.spline != nullptr);
  const BSpline& s = *plot.spline;
  const auto samples = sample_curvature(s, std::max(50, 800 / s.segment_count()));
  const PlotFrame f = plot_frame(s, samples, x, y, w, h);
  set_colour(cr, {1, 1, 1});
  cairo_rectangle(cr, x, y, w, h);
  cairo_fill(cr);
  set_colour(cr, {0, 0, 0});
  text_at(cr, f.left, y + 17, "curvature \xCE\xBA against the parameter t", 13, true);
  draw_plot_axes(cr, s, f, x);
  draw_plot_curve(cr, samples, f);
  if (plot.analysis) draw_class_band(cr, s, *plot.analysis, f);
  set_colour(cr, {0.5, 0.5, 0.5});
  cairo_rectangle(cr, x + 0.5, y + 0.5, w - 1, h - 1);
  cairo_stroke(cr);
}

// ----------------------------------------------------------- figure page --

constexpr double kMargin = 16, kGap = 12, kLabelSize = 12.5, kCaptionSize = 13, kTitleSize = 18;

/// Where everything of a figure goes; measured before drawing so that the
/// page is as tall as it needs to be.
struct FigureLayout {
  double width = 0, height = 0, side = 0;
  std::vector<std::vector<std::vector<std::string>>> labels;  ///< per row, per panel: wrapped lines
  std::vector<double> row_label_height;
  std::vector<std::string> title, caption;
  std::vector<std::pair<double, double>> legend_at;  ///< offsets from the legend's top left
  double legend_height = 0, title_height = 0;
};

/// Legend entries flow left to right and wrap like words.
void layout_legend(cairo_t* pc, const Figure& f, double text_width_px, FigureLayout& l) {
  double lx = 0, ly = 0;
  cairo_select_font_face(pc, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(pc, 12);
  for (const LegendEntry& e : f.legend) {
    const double w = 22 + text_width(pc, e.text) + 18;
    if (lx > 0 && lx + w > text_width_px) {
      lx = 0;
      ly += 22;
    }
    l.legend_at.emplace_back(lx, ly);
    lx += w;
  }
  l.legend_height = f.legend.empty() ? 0 : ly + 24;
}

FigureLayout measure_figure(const Figure& f) {
  FigureLayout l;
  l.side = f.panel_size;
  std::size_t columns = 1;
  for (const auto& row : f.rows) columns = std::max(columns, row.size());
  l.width = 2 * kMargin + columns * l.side + (columns - 1) * kGap;
  const double text_width_px = l.width - 2 * kMargin;
  Surface probe = make_surface(1, 1);
  Context pc = make_context(probe.get());
  for (const auto& row : f.rows) {
    l.labels.emplace_back();
    std::size_t most = 0;
    for (const Panel& p : row) {
      l.labels.back().push_back(wrap(pc.get(), p.label, l.side, kLabelSize));
      most = std::max(most, l.labels.back().back().size());
    }
    l.row_label_height.push_back(most * (kLabelSize + 4) + 6);
  }
  l.title = wrap(pc.get(), f.title, text_width_px, kTitleSize, true);
  l.caption = wrap(pc.get(), f.caption, text_width_px, kCaptionSize);
  layout_legend(pc.get(), f, text_width_px, l);
  l.title_height = l.title.size() * (kTitleSize + 6) + 6;
  l.height = kMargin + l.title_height;
  for (double lh : l.row_label_height) l.height += l.side + lh + kGap;
  l.height += l.legend_height + l.caption.size() * (kCaptionSize + 5) + kMargin;
  return l;
}

/// Draws the panels and their labels row by row from `y`; returns the y below them.
double draw_figure_rows(cairo_t* c, const Figure& f, const FigureLayout& l, double y) {
  for (std::size_t r = 0; r < f.rows.size(); ++r) {
    for (std::size_t i = 0; i < f.rows[r].size(); ++i) {
      const double x = kMargin + i * (l.side + kGap);
      const Panel& p = f.rows[r][i];
      if (const auto* pic = std::get_if<RegionPicture>(&p.content)) draw_region_panel(c, *pic, x, y, l.side, l.side);
      else draw_curvature_panel(c, std::get<CurvaturePlot>(p.content), x, y, l.side, l.side);
      set_colour(c, {0, 0, 0});
      double ty = y + l.side + kLabelSize + 4;
      for (const std::string& line : l.labels[r][i]) {
        text_at(c, x, ty, line, kLabelSize);
        ty += kLabelSize + 4;
      }
    }
    y += l.side + l.row_label_height[r] + kGap;
  }
  return y;
}

void draw_legend(cairo_t* c, const Figure& f, const FigureLayout& l, double y) {
  for (std::size_t i = 0; i < f.legend.size(); ++i) {
    const LegendEntry& e = f.legend[i];
    const double x = kMargin + l.legend_at[i].first, ly0 = y + l.legend_at[i].second;
    set_colour(c, e.colour);
    cairo_rectangle(c, x, ly0, 16, 16);
    cairo_fill_preserve(c);
    set_colour(c, {0.4, 0.4, 0.4});
    cairo_set_line_width(c, 1);
    cairo_stroke(c);
    set_colour(c, {0, 0, 0});
    text_at(c, x + 22, ly0 + 13, e.text, 12);
  }
}

}  // namespace

Rgb pixel_colour(const RegionPicture& p, std::size_t index) {
  Absorb sum = kNone;
  for (const RegionResult* layer : p.layers) {
    const uint8_t label = layer->code_at(index);
    const Absorb a = p.depth_shading ? depth_absorb(label, layer->depth[index], p.max_depth)
                                     : (p.split ? split_absorb(label) : plain_absorb(label));
    sum = {sum.r + a.r, sum.g + a.g, sum.b + a.b};
  }
  return colour_of(sum);
}

std::vector<LegendEntry> legend_for(const RegionPicture& p) {
  const auto colour = colour_of;
  if (p.depth_shading)
    return {{colour(depth_absorb(1, 0, p.max_depth)), "increasing, decided at level 0"},
            {colour(depth_absorb(1, 8, p.max_depth)), "increasing, deeper"},
            {colour(depth_absorb(2, 0, p.max_depth)), "decreasing, level 0"},
            {colour(depth_absorb(2, 8, p.max_depth)), "decreasing, deeper"},
            {colour(depth_absorb(0, 0, p.max_depth)), "not monotone, level 0"},
            {colour(depth_absorb(0, 8, p.max_depth)), "not monotone, deeper"}};
  if (p.split)
    return {{colour(kRed), "inc-inc"},
            {colour(kDarkRed), "dec-inc (minimum at the joint)"},
            {colour(kBlue), "dec-dec"},
            {colour(kDarkBlue), "inc-dec (maximum at the joint)"},
            {{1, 1, 1}, "neither part monotone, or undecided"}};
  std::vector<LegendEntry> l = {{colour(kRed), "curvature increasing"},
                                {colour(kBlue), "decreasing"},
                                {{1, 1, 1}, "not monotone or undecided"}};
  if (p.layers.size() > 1)
    l.push_back({colour({kRed.r + kRed.r, kRed.g + kRed.g, kRed.b + kRed.b}), "two increasing regions overlap"});
  return l;
}

std::string region_png(const RegionPicture& picture) {
  check_picture(picture);
  const int W = picture.layers[0]->width, H = picture.layers[0]->height;
  Surface surface = make_surface(W, H);
  Context cr = make_context(surface.get());
  draw_region_panel(cr.get(), picture, 0, 0, W, H);
  return encode_png(surface.get());
}

std::string rgba_png(int width, int height, const std::vector<std::uint8_t>& rgba) {
  if (width < 1 || height < 1 || rgba.size() != std::size_t{4} * width * height)
    throw InputError("rgba_png: " + std::to_string(rgba.size()) + " bytes are not " + std::to_string(width) + "x" +
                     std::to_string(height) + " RGBA pixels");
  Surface surface = make_surface(width, height);
  cairo_surface_flush(surface.get());
  unsigned char* data = cairo_image_surface_get_data(surface.get());
  const int stride = cairo_image_surface_get_stride(surface.get());
  for (int j = 0; j < height; ++j) {
    auto* row = reinterpret_cast<uint32_t*>(data + static_cast<std::ptrdiff_t>(j) * stride);
    for (int i = 0; i < width; ++i) {
      const std::uint8_t* p = &rgba[4 * (static_cast<std::size_t>(j) * width + i)];
      row[i] = 0xff000000u | uint32_t{p[0]} << 16 | uint32_t{p[1]} << 8 | p[2];  // opaque ARGB32
    }
  }
  cairo_surface_mark_dirty(surface.get());
  return encode_png(surface.get());
}

void write_region_png(const std::filesystem::path& path, const RegionPicture& picture) {
  write_file_atomic(path, region_png(picture));
}

std::string figure_png(const Figure& f) {
  const FigureLayout layout = measure_figure(f);
  Surface surface = make_surface(static_cast<int>(std::ceil(layout.width)), static_cast<int>(std::ceil(layout.height)));
  Context cr = make_context(surface.get());
  cairo_t* c = cr.get();
  set_colour(c, {1, 1, 1});
  cairo_paint(c);
  set_colour(c, {0, 0, 0});
  for (std::size_t i = 0; i < layout.title.size(); ++i)
    text_at(c, kMargin, kMargin + kTitleSize + i * (kTitleSize + 6), layout.title[i], kTitleSize, true);
  double y = draw_figure_rows(c, f, layout, kMargin + layout.title_height);
  draw_legend(c, f, layout, y);
  y += layout.legend_height + kCaptionSize;
  for (const std::string& line : layout.caption) {
    text_at(c, kMargin, y, line, kCaptionSize);
    y += kCaptionSize + 5;
  }
  return encode_png(surface.get());
}

void write_figure_png(const std::filesystem::path& path, const Figure& figure) {
  write_file_atomic(path, figure_png(figure));
}

}  // namespace cmr::draw
