#include "draw/weight_picture.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "draw/cairo_canvas.hpp"
#include "draw/draw.hpp"
#include "spline/curvature.hpp"
#include "spline/errors.hpp"

namespace cmr {

namespace {

/// "P3", "w3": a letter and an index (appended, which GCC 12's
/// -Wrestrict does not misread as an overlapping copy).
std::string indexed(char letter, int k) {
  std::string s(1, letter);
  s += std::to_string(k);
  return s;
}

/// Axis tick step: 1, 2 or 5 times a power of ten, about six ticks.
double tick_step(double range) {
  const double raw = range / 6, p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double f : {1.0, 2.0, 5.0})
    if (f * p >= raw) return f * p;
  return 10 * p;
}

std::string tick_text(double x, double step) {
  char buf[32];
  const int digits = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
  std::snprintf(buf, sizeof buf, "%.*f", digits, x);
  return buf;
}

/// A curve's colour for a label: the region colour, darkened so that it shows
/// on white (white labels: grey).
draw::Rgb curve_colour(draw::Rgb region) {
  if (region.r > 0.95 && region.g > 0.95 && region.b > 0.95) return {0.6, 0.6, 0.6};
  return {region.r * 0.8, region.g * 0.8, region.b * 0.8};
}

/// Weights whose spline has a pole in a judged span: hatched.
void hatch(cairo_t* cr, double x0, double y0, double x1, double y1) {
  cairo_save(cr);
  cairo_rectangle(cr, x0, y0, x1 - x0, y1 - y0);
  cairo_clip(cr);
  cairo_set_source_rgb(cr, 0.25, 0.25, 0.25);
  cairo_set_line_width(cr, 1);
  for (double x = x0 - (y1 - y0); x < x1; x += 6) {
    cairo_move_to(cr, x, y1);
    cairo_line_to(cr, x + (y1 - y0), y0);
  }
  cairo_stroke(cr);
  cairo_restore(cr);
}

/// A curve as drawable pieces: broken where a pole sends it away
/// (CurveSampler, spline/curvature.hpp).
using Pieces = std::vector<std::vector<Vec2>>;
constexpr int kFamily = 7;

Pieces polyline(const BSpline& s) {
  constexpr int kSteps = 400;
  const CurveSampler sampler(s);
  Pieces pieces;
  std::optional<double> pen;
  for (int i = 0; i <= kSteps; ++i) {
    const double t = i == kSteps ? s.domain_end() : s.domain_begin() + (s.domain_end() - s.domain_begin()) * i / kSteps;
    const std::optional<Vec2> p = sampler.at(t);
    if (!p) {
      pen.reset();
      continue;
    }
    if (!pen || !sampler.joins(*pen, t)) pieces.emplace_back();
    pieces.back().push_back(*p);
    pen = t;
  }
  return pieces;
}

/// The picture's parts, top to bottom: the title, the family of curves
/// (a handful of weights in their labels' colours over the spline as
/// given), the strip of labels along the weight axis with the current
/// weight marked, and the legend.
class WeightPanel {
 public:
  WeightPanel(const BSpline& spline, const WeightRegionRequest& r, const WeightRegion& region, int width, int height)
      : spline_(spline), r_(r), region_(region), width_(width), height_(height), A_(r.from), B_(r.to),
        sx0_(60), columns_(static_cast<int>(width - 40 - sx0_)), strip_top_(height - 150),
        strip_bottom_(strip_top_ + 34) {
    // The strip: one column per pixel, each the label of its weight, as a
    // one-row region image, so that colours and legend are draw's.
    strip_ = region.kind;
    strip_.width = columns_;
    strip_.height = 1;
    strip_.depth.assign(columns_, 0);
    for (int i = 0; i < columns_; ++i) {
      const std::uint8_t l = label_of_weight(A_ + (B_ - A_) * (i + 0.5) / columns_);
      if (strip_.alternating) strip_.alternating_labels.push_back(static_cast<Alternation>(l));
      else if (strip_.split) strip_.split_labels.push_back(static_cast<Split>(l));
      else strip_.labels.push_back(static_cast<Direction>(l));
    }
    pic_.spline = &spline;
    pic_.layers = {&strip_};
    pic_.split = strip_.split;
    pic_.alternating = strip_.alternating;
    legend_ = draw::legend_for(pic_);
  }
  WeightPanel(const WeightPanel&) = delete;  // pic_ points at strip_
  WeightPanel& operator=(const WeightPanel&) = delete;

  void paint(cairo_t* cr) const {
    // The font of every cmr picture (draw.cpp), installed by the setup script
    // (fonts-dejavu-core): "sans-serif" would follow the machine's fontconfig.
    cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    title(cr);
    curves(cr);
    const bool any_pole = strip(cr);
    axis(cr);
    current_marker(cr);
    legend(cr, any_pole);
  }

 private:
  std::uint8_t label_of_weight(double x) const {
    for (const WeightInterval& iv : region_.intervals)
      if (x <= iv.to) return iv.label;
    return region_.intervals.back().label;
  }
  draw::Rgb colour_of_label(std::uint8_t l) const {
    for (int i = 0; i < columns_; ++i)
      if (strip_.code_at(i) == l) return draw::pixel_colour(pic_, i);
    return draw::Rgb{1, 1, 1};
  }
  double x_of(double x) const { return sx0_ + (x - A_) / (B_ - A_) * columns_; }

  void title(cairo_t* cr) const {
    const int K = r_.point;
    cairo_set_font_size(cr, 14);
    draw::set_colour(cr, {0, 0, 0});
    cairo_move_to(cr, 12, 20);
    std::string mode = r_.labels.mode == Mode::cmr ? "CMR" : "CMRWI";
    if (r_.labels.split) mode += " split at joint " + std::to_string(*r_.labels.split);
    for (std::size_t i = 0; i < r_.labels.splits.size(); ++i)
      mode += (i == 0 ? " joints " : ",") + std::to_string(r_.labels.splits[i]);
    if (r_.labels.segments)
      mode += " segments " + std::to_string(r_.labels.segments->first) + ".." + std::to_string(r_.labels.segments->last);
    const std::string text = "weight w" + std::to_string(K) + " of P" + std::to_string(K) + " in [" +
                             tick_text(A_, 1e-3) + ", " + tick_text(B_, 1e-3) + "]: " + mode + " labels, the rest fixed";
    cairo_show_text(cr, text.c_str());
  }

  /// The family of curves: a handful of weights, thin, in their label's
  /// colour, over the control polygon and the spline's own curve.
  void curves(cairo_t* cr) const {
    const int K = r_.point;
    const double top = 32;
    const double cx0 = 12, cx1 = width_ - 12, cy0 = top, cy1 = strip_top_ - 24;
    // The curves first (polylines), then the view: their bounding box with
    // P_K, so that the part the weight bends fills the panel.
    // Equally spaced weights, and the middle of each interval (the first
    // kFamily), so that every label shows in a curve.
    std::vector<double> family_weights;
    for (int i = 0; i < kFamily; ++i)
      family_weights.push_back(i == kFamily - 1 ? B_ : A_ + (B_ - A_) * i / (kFamily - 1));
    for (std::size_t i = 0; i < region_.intervals.size() && i < static_cast<std::size_t>(kFamily); ++i)
      family_weights.push_back((region_.intervals[i].from + region_.intervals[i].to) / 2);
    std::vector<Pieces> family;
    std::vector<bool> through_infinity;
    for (double x : family_weights) {
      const BSpline member = with_weight(spline_, K, x);
      family.push_back(polyline(member));
      through_infinity.push_back(has_pole(member));
    }
    const Pieces own = polyline(spline_);
    // The view: the curves that stay finite (a pole's curve is drawn clipped),
    // the spline's own curve and P_K.
    double bx0 = spline_.points()[K].x, bx1 = bx0, by0 = spline_.points()[K].y, by1 = by0;
    const auto extend = [&](const Pieces& curve) {
      for (const auto& line : curve)
        for (const Vec2& p : line) {
          bx0 = std::min(bx0, p.x), bx1 = std::max(bx1, p.x);
          by0 = std::min(by0, p.y), by1 = std::max(by1, p.y);
        }
    };
    extend(own);
    for (std::size_t i = 0; i < family.size(); ++i)
      if (!through_infinity[i]) extend(family[i]);
    if (has_pole(spline_)) {  // the own curve is clipped too: frame its control points
      for (const Vec2& p : spline_.points()) extend({{p}});
    }
    const double ext = std::max({bx1 - bx0, by1 - by0, 1e-300});
    bx0 -= 0.05 * ext, bx1 += 0.05 * ext, by0 -= 0.05 * ext, by1 += 0.05 * ext;
    const double scale = std::min((cx1 - cx0) / (bx1 - bx0), (cy1 - cy0) / (by1 - by0));
    const double ox = (cx0 + cx1) / 2 - scale * (bx0 + bx1) / 2, oy = (cy0 + cy1) / 2 + scale * (by0 + by1) / 2;
    const auto screen = [&](Vec2 p) { return std::pair{ox + scale * p.x, oy - scale * p.y}; };
    const auto stroke_line = [&](const Pieces& pieces) {
      for (const std::vector<Vec2>& pts : pieces)
        for (std::size_t i = 0; i < pts.size(); ++i) {
          const auto [x, y] = screen(pts[i]);
          if (i == 0) cairo_move_to(cr, x, y);
          else cairo_line_to(cr, x, y);
        }
      cairo_stroke(cr);
    };
    cairo_save(cr);
    cairo_rectangle(cr, cx0, cy0 - 8, cx1 - cx0, cy1 - cy0 + 16);
    cairo_clip(cr);
    // The control polygon (dashed), the spline's own curve, the family over
    // it, the points, P_K ringed.
    const double dash[] = {4, 3};
    cairo_set_line_width(cr, 1);
    cairo_set_dash(cr, dash, 2, 0);
    draw::set_colour(cr, {0.5, 0.5, 0.5});
    for (int i = 0; i < spline_.point_count(); ++i) {
      const auto [x, y] = screen(spline_.points()[i]);
      if (i == 0) cairo_move_to(cr, x, y);
      else cairo_line_to(cr, x, y);
    }
    cairo_stroke(cr);
    cairo_set_dash(cr, nullptr, 0, 0);
    draw::set_colour(cr, {0, 0, 0});
    cairo_set_line_width(cr, 2.5);
    stroke_line(own);
    // Curves of white labels (grey) first and thin, the coloured ones over them.
    for (const bool coloured : {false, true})
      for (std::size_t i = 0; i < family.size(); ++i) {
        const draw::Rgb c = curve_colour(colour_of_label(label_of_weight(family_weights[i])));
        if ((c.r == c.g && c.g == c.b) == coloured) continue;
        cairo_set_line_width(cr, coloured ? 1.8 : 1);
        draw::set_colour(cr, c);
        stroke_line(family[i]);
      }
    draw::set_colour(cr, {0, 0, 0});
    for (int i = 0; i < spline_.unique_point_count(); ++i) {
      const auto [x, y] = screen(spline_.points()[i]);
      cairo_arc(cr, x, y, 2.5, 0, 2 * M_PI);
      cairo_fill(cr);
    }
    {
      const auto [x, y] = screen(spline_.points()[K]);
      cairo_set_source_rgb(cr, 0.95, 0.55, 0.0);
      cairo_set_line_width(cr, 2);
      cairo_arc(cr, x, y, 7, 0, 2 * M_PI);
      cairo_stroke(cr);
      cairo_set_font_size(cr, 12);
      cairo_move_to(cr, x + 9, y - 9);
      const std::string name = indexed('P', K);
      cairo_show_text(cr, name.c_str());
    }
    cairo_restore(cr);
  }

  /// The strip, one column per weight, its frame and the boundaries between
  /// labels; whether some interval has a pole (hatched).
  bool strip(cairo_t* cr) const {
    for (int i = 0; i < columns_; ++i) {
      draw::set_colour(cr, draw::pixel_colour(pic_, i));
      cairo_rectangle(cr, sx0_ + i, strip_top_, 1, strip_bottom_ - strip_top_);
      cairo_fill(cr);
    }
    bool any_pole = false;
    for (const WeightInterval& iv : region_.intervals)
      if (iv.pole) {
        any_pole = true;
        hatch(cr, std::max(x_of(iv.from), sx0_) - 0.5, strip_top_, std::min(x_of(iv.to), sx0_ + columns_) + 0.5,
              strip_bottom_);
      }
    draw::set_colour(cr, {0, 0, 0});
    cairo_set_line_width(cr, 1);
    cairo_rectangle(cr, sx0_, strip_top_, columns_, strip_bottom_ - strip_top_);
    cairo_stroke(cr);
    // Boundaries as thin lines.
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    for (std::size_t i = 0; i + 1 < region_.intervals.size(); ++i) {
      const double x = x_of((region_.intervals[i].to + region_.intervals[i + 1].from) / 2);
      cairo_move_to(cr, x, strip_top_);
      cairo_line_to(cr, x, strip_bottom_);
      cairo_stroke(cr);
    }
    return any_pole;
  }

  /// The weight axis under the strip.
  void axis(cairo_t* cr) const {
    const double step = tick_step(B_ - A_);
    cairo_set_font_size(cr, 11);
    draw::set_colour(cr, {0, 0, 0});
    for (double t = std::ceil(A_ / step) * step; t <= B_ + 1e-9 * step; t += step) {
      const double x = x_of(t);
      cairo_move_to(cr, x, strip_bottom_);
      cairo_line_to(cr, x, strip_bottom_ + 5);
      cairo_stroke(cr);
      const std::string text = tick_text(std::fabs(t) < 1e-12 * step ? 0.0 : t, step);
      cairo_text_extents_t e;
      cairo_text_extents(cr, text.c_str(), &e);
      cairo_move_to(cr, x - e.width / 2, strip_bottom_ + 17);
      cairo_show_text(cr, text.c_str());
    }
    const std::string name = indexed('w', r_.point);
    cairo_move_to(cr, 12, strip_bottom_ + 17);
    cairo_show_text(cr, name.c_str());
  }

  /// The current weight: a marker over the strip (or a note when outside).
  void current_marker(cairo_t* cr) const {
    const int K = r_.point;
    const double current = spline_.weight(K);
    cairo_set_source_rgb(cr, 0.95, 0.55, 0.0);
    const std::string now = "current w" + std::to_string(K) + " = " + tick_text(current, 1e-4);
    if (current >= A_ && current <= B_) {
      const double x = x_of(current);
      cairo_set_line_width(cr, 2);
      cairo_move_to(cr, x, strip_top_ - 2);
      cairo_line_to(cr, x, strip_bottom_ + 2);
      cairo_stroke(cr);
      cairo_move_to(cr, x - 6, strip_top_ - 12);
      cairo_line_to(cr, x + 6, strip_top_ - 12);
      cairo_line_to(cr, x, strip_top_ - 3);
      cairo_close_path(cr);
      cairo_fill(cr);
      cairo_text_extents_t e;
      cairo_text_extents(cr, now.c_str(), &e);
      const double tx = std::clamp(x - e.width / 2, 4.0, width_ - e.width - 4);
      cairo_set_source_rgb(cr, 1, 1, 1);  // on white: the curves' panel may reach down here
      cairo_rectangle(cr, tx - 2, strip_top_ - 15 - e.height - 1, e.width + 4, e.height + 4);
      cairo_fill(cr);
      cairo_set_source_rgb(cr, 0.95, 0.55, 0.0);
      cairo_move_to(cr, tx, strip_top_ - 15);
    } else {
      cairo_move_to(cr, sx0_, strip_top_ - 6);
    }
    cairo_show_text(cr, (current >= A_ && current <= B_ ? now : now + " (outside the interval)").c_str());
  }

  /// The legend: the colours drawn, named as in region pictures, the pole's
  /// hatching where there is one, and what the thin curves are.
  void legend(cairo_t* cr, bool any_pole) const {
    double lx = 12, ly = strip_bottom_ + 40;
    cairo_set_font_size(cr, 12);
    for (const draw::LegendEntry& e : legend_) {
      if (e.ring) continue;
      cairo_text_extents_t ex;
      cairo_text_extents(cr, e.text.c_str(), &ex);
      if (lx + 22 + ex.x_advance > width_ - 12) lx = 12, ly += 22;
      draw::set_colour(cr, e.colour);
      cairo_rectangle(cr, lx, ly - 11, 14, 14);
      cairo_fill_preserve(cr);
      draw::set_colour(cr, {0, 0, 0});
      cairo_set_line_width(cr, 1);
      cairo_stroke(cr);
      cairo_move_to(cr, lx + 20, ly);
      cairo_show_text(cr, e.text.c_str());
      lx += 20 + ex.x_advance + 24;
    }
    if (any_pole) {
      const char* text = "pole: W vanishes in a judged span (the curve passes through infinity)";
      cairo_text_extents_t ex;
      cairo_text_extents(cr, text, &ex);
      if (lx + 22 + ex.x_advance > width_ - 12) lx = 12, ly += 22;
      hatch(cr, lx, ly - 11, lx + 14, ly + 3);
      draw::set_colour(cr, {0, 0, 0});
      cairo_rectangle(cr, lx, ly - 11, 14, 14);
      cairo_stroke(cr);
      cairo_move_to(cr, lx + 20, ly);
      cairo_show_text(cr, text);
    }
    ly += 22;
    cairo_set_font_size(cr, 11);
    cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
    cairo_move_to(cr, 12, ly);
    cairo_show_text(cr, ("thin curves: w" + std::to_string(r_.point) + " at " + std::to_string(kFamily) +
                         " equally spaced weights and in each interval's middle, in their label's colour; black: the "
                         "spline as given")
                            .c_str());
  }

  const BSpline& spline_;
  const WeightRegionRequest& r_;
  const WeightRegion& region_;
  const int width_, height_;
  const double A_, B_;
  const double sx0_;
  const int columns_;
  const double strip_top_, strip_bottom_;
  RegionResult strip_;
  draw::RegionPicture pic_;
  std::vector<draw::LegendEntry> legend_;
};

}  // namespace

std::string weight_region_picture(const BSpline& spline, const WeightRegionRequest& r, const WeightRegion& region,
                                  bool svg, int width, int height) {
  CMR_CHECK(!region.intervals.empty() && width >= 400 && height >= 300);
  const WeightPanel panel(spline, r, region, width, height);
  return draw::render_picture(svg ? draw::PictureFormat::svg : draw::PictureFormat::png, width, height,
                              [&](cairo_t* cr) { panel.paint(cr); });
}

}  // namespace cmr
