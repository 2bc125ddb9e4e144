#pragma once
// Internal to cmr::draw: the cairo text helpers that the region pictures and
// figures (draw.cpp) and the plots (plot.cpp) share, and the plot panels a
// figure draws.
#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "draw/draw.hpp"

namespace cmr::draw::detail {

// ------------------------------------------------------------ cairo helpers --

inline void text_at(cairo_t* cr, double x, double y, const std::string& s, double size, bool bold = false) {
  cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_move_to(cr, x, y);
  cairo_show_text(cr, s.c_str());
}

inline double text_width(cairo_t* cr, const std::string& s) {
  cairo_text_extents_t e;
  cairo_text_extents(cr, s.c_str(), &e);
  return e.x_advance;
}

/// The ink box of `s` drawn with its baseline starting at (x, y), padded by
/// one pixel, in the current font.
inline TextBox text_box(cairo_t* cr, double x, double y, const std::string& s, double size, bool bold = false) {
  cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_text_extents_t e;
  cairo_text_extents(cr, s.c_str(), &e);
  return {x + e.x_bearing - 1, y + e.y_bearing - 1, x + e.x_bearing + e.width + 1, y + e.y_bearing + e.height + 1, s};
}

/// The labels of one panel, kept apart: a label is drawn only where its box
/// meets none drawn before it.
struct Labels {
  std::vector<TextBox> placed;
  bool free(const TextBox& b) const {
    return std::none_of(placed.begin(), placed.end(), [&](const TextBox& o) { return o.intersects(b); });
  }
  /// Draws `s` at (x, y) if it overlaps nothing drawn; returns whether it did.
  bool put(cairo_t* cr, double x, double y, const std::string& s, double size, bool bold = false) {
    const TextBox b = text_box(cr, x, y, s, size, bold);
    if (!free(b)) return false;
    text_at(cr, x, y, s, size, bold);
    placed.push_back(b);
    return true;
  }
};

/// Greedy word wrap at `width` pixels with the current font.
inline std::vector<std::string> wrap(cairo_t* cr, const std::string& text, double width, double size, bool bold = false) {
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

inline void arrow(cairo_t* cr, double x0, double y0, double x1, double y1) {
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
// A figure's curvature and lambda panels (plot.cpp).
void draw_curvature_panel(cairo_t* cr, const CurvaturePlot& plot, double x, double y, double w, double h,
                          Labels& labels);
void draw_lambda_panel(cairo_t* cr, const LambdaPlot& plot, double x, double y, double w, double h, Labels& labels);

}  // namespace cmr::draw::detail
