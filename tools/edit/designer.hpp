#pragma once
// What a designer reads off the editor (issue 21): the legend of what is
// drawn, point names, the auto-fitted curvature comb, joint continuity, the
// curve under the cursor, and views that frame what matters. Pure functions
// of the editor's state, so tests check them without a window.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "draw/draw.hpp"
#include "tools/edit/editor.hpp"

namespace cmr::edit {

/// The file's "point_names" (one per distinct point, as `cmr import` and the
/// report name them), or nothing when the file has none or cannot be read.
std::vector<std::string> read_point_names(const std::filesystem::path& path);

/// One line of the legend.
struct LegendLine {
  enum class Kind { swatch, gradient, outline, dot, square, diamond, line, text };
  Kind kind = Kind::swatch;
  draw::Rgb colour;       ///< swatch, outline or mark colour
  draw::Rgb colour_to;    ///< gradient: the deep end
  std::string text;
  int point = -1;         ///< outline: the point whose region it outlines
  bool same_row = false;  ///< drawn after the previous line, on its row (the marks)
};

/// The legend of the current view: a title in the designer's words, the
/// region colours actually drawn (draw::legend_for of the same layers and
/// flags region_rgba paints with; depth shading as light-to-dark gradients),
/// with every point overlapped the outline hue of each point shown, then the
/// marks on the curve (sharpest and flattest points, inflections, comb,
/// joints by continuity) when they are drawn.
struct Legend {
  std::string title;
  std::vector<LegendLine> lines;
};
Legend region_legend(Editor& e);

/// A colour as the window shows it (the bytes region_rgba writes).
std::array<int, 3> bytes_of(draw::Rgb c);

/// The world rectangle the canvas shows (the part of the view the panels
/// leave free; the whole view without the UI).
View canvas_view(const Editor& e);

/// The curvature comb: `density` teeth per segment, each from a curve point
/// along the normal, away from the centre of curvature, of length
/// unit * |kappa|. `fit_unit` is the largest unit whose tips stay inside
/// `view` (a margin of kCombMargin of its size kept) for every tooth whose
/// foot lies inside it at least that margin from the edge, and at most a
/// fifth of the view's smaller side for the largest |kappa|; unit is
/// scale * fit_unit (scale 1: the comb fits the view).
struct Comb {
  std::vector<Vec2> feet, tips;
  double fit_unit = 0, unit = 0, kmax = 0;
};
inline constexpr double kCombMargin = 0.03;
Comb comb_geometry(const BSpline& spline, const View& view, double scale, int density);

/// The continuity a joint marker shows: 2 (G2), 1 (G1) or 0 (G0 only).
int joint_continuity(const Joint& j);

/// The curve point nearest window pixel (x, y) within `radius` pixels:
/// parameter, point, signed curvature (radius 1/|kappa|).
struct CurvePick {
  double t = 0;
  Vec2 point{0.0};
  double kappa = 0;
};
std::optional<CurvePick> pick_curve(const BSpline& spline, const Viewport& viewport, double x, double y,
                                    double radius);

/// The bounding box of the selected point's region (its current request) on
/// a grid of `pixels` across a view `zoom` times the canvas's, centred on it;
/// nothing when the region is empty there.
std::optional<std::pair<Vec2, Vec2>> region_box(const Editor& e, double zoom, int pixels);

/// Label boxes for the point names that do not overprint: each name tries
/// eight places around its point (right, above-right, ...) and takes the
/// first that overlaps no earlier label and no point marker; a name with no
/// free place is left out (shown when hovered). Screen pixels.
struct PlacedLabel {
  int point = 0;
  float x = 0, y = 0, w = 0, h = 0;
};
std::vector<PlacedLabel> place_labels(const std::vector<Vec2>& points_screen, const std::vector<Vec2>& text_sizes,
                                      float marker_radius);

}  // namespace cmr::edit
