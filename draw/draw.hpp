#pragma once
/// Pictures of regions and curves, drawn with Cairo (antialiased), as PNG
/// bytes in memory or as files (library target cmr::draw; no CLI).
///
/// Region colours (the legend; every layer subtracts its colour from white, so
/// overlapping regions of several points come out darker, as in CAD&A 2024
/// Fig. 3):
///   plain labels   1 increasing: red, 2 decreasing: blue, 0 not monotone and
///                  3 undecided (the paper counts it as not monotone): white;
///   split labels   1 inc-inc: red, 4 dec-dec: blue (monotone across the
///                  joint); 3 dec-inc: dark red, 2 inc-dec: dark blue (an
///                  extremum at the joint: the second part's direction gives the
///                  hue, the darker shade says the first part goes the other
///                  way); 0 none and 5 undecided: white;
///   alternating labels (several joints) 1 group 0 increasing: red,
///                  2 group 0 decreasing: blue; 0 fail and 3 undecided: white;
///   each-piece labels 1 every piece (group) monotone on its own: green;
///                  0 fail and 2 undecided: white;
///   depth shading  (Fig. 7) red / blue from light at level 0 (the sufficient
///                  condition of the paper's reference [16]) to dark at level
///                  D; not monotone and undecided grey, darker with the level.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "bezierize/analyze.hpp"
#include "region/region.hpp"
#include "spline/limits.hpp"

namespace cmr::draw {

/// A colour, each channel in [0, 1].
struct Rgb {
  double r = 1, g = 1, b = 1;
};

/// A knot ruler across the top of a region picture (`cmr sweep`'s frames):
/// the interval [from, to] as a line, a tick per knot (a repeated knot's
/// tick longer by its multiplicity), knot `marked` in red with a triangle
/// over it, and above the line `label` (e.g. "knot 3 = 2.9"). Drawn on a
/// white strip 24 px high in pictures at least kRulerMinWidth x
/// kRulerMinHeight px.
struct KnotRuler {
  std::vector<double> knots;
  int marked = -1;          ///< the moving knot's index, or -1
  double from = 0, to = 1;  ///< the ruler's ends (the same for every frame of a sweep, so the mark moves)
  std::string label;
};
/// The ruler's line: its ends' x and its y in the picture's pixels (the strip
/// is 4 px in from the edges), for `knot_ruler_x` and tests.
struct RulerGeometry {
  double x0 = 0, x1 = 0, y = 0;
  double x(const KnotRuler& r, double u) const { return x0 + (u - r.from) / (r.to - r.from) * (x1 - x0); }
};
RulerGeometry knot_ruler_geometry(double width);
inline constexpr int kRulerMinWidth = 96, kRulerMinHeight = 64;

/// A region image (one layer per moved point) with the curve, the control
/// polygon and the point numbers drawn over it.
struct RegionPicture {
  const BSpline* spline = nullptr;
  std::vector<const RegionResult*> layers;  ///< one per point; overlaps subtract colour from white (Fig. 3)
  bool split = false;                      ///< the layers hold split labels
  bool alternating = false;                ///< the layers hold alternating labels (several joints)
  bool each_piece = false;                 ///< the layers hold each-piece labels (EachPiece)
  /// One line the legend ends with (why a region is empty or full:
  /// region/region_reason.hpp); nothing when empty.
  std::string note;
  bool depth_shading = false;              ///< Fig. 7: darker with the decision level, grey for not monotone
  int max_depth = kDefaultDepth;           ///< D of the render: the depth shading's darkest level
  std::optional<std::pair<Vec2, Vec2>> moved;  ///< a moved point's old and new place
  /// The control point whose region each layer is (same length as layers, or
  /// empty): those points are marked with a ring (`cmr region`'s moved point).
  std::vector<int> points;
  /// Per-point colours (`cmr region --point all`): layer i is drawn in
  /// point_colour(points[i]), filled where the curvature increases (split:
  /// the second part increases) and hatched where it decreases; overlaps
  /// subtract colour from white as above. Needs `points`.
  bool per_point = false;
  /// Draw legend_for(picture) inside the picture (bottom left, on a white
  /// box) when the picture is large enough (at least 240 x 160 px).
  bool legend = false;
  std::optional<KnotRuler> ruler;  ///< a knot ruler across the top (KnotRuler)
};

/// The colour of control point k's regions with per-point colours: eight
/// distinct hues, then further hues by the golden angle.
Rgb point_colour(int k);

/// The picture as PNG bytes, of the layers' size. Throws std::bad_alloc when
/// memory runs out (nothing else can fail in memory).
std::string region_png(const RegionPicture& picture);
/// Writes region_png(picture) to `path` with cmr::write_file_atomic (and its
/// errors: InputError for a missing folder or a directory, EnvironmentError
/// for the rest).
void write_region_png(const std::filesystem::path& path, const RegionPicture& picture);

/// RGBA bytes (row-major, row 0 at the top, width * height * 4; alpha
/// ignored) as PNG bytes: window screenshots. InputError for a size that
/// does not match the bytes.
std::string rgba_png(int width, int height, const std::vector<std::uint8_t>& rgba);

/// The colour of pixel `index` (row-major) of the picture's layers, by the
/// legend above.
Rgb pixel_colour(const RegionPicture& picture, std::size_t index);
/// The legend colour of one label code (a Direction code; with `split` a
/// Split code, with `alternating` an Alternation code, with `each_piece` an
/// EachPiece code) on a single layer: pixel_colour of a one-pixel map.
/// Meshes colour their faces with it and sweep plots their series.
Rgb label_colour(std::uint8_t label, bool split, bool alternating = false, bool each_piece = false);

/// Curvature against the parameter: each segment drawn from its own
/// polynomial (so jumps at joints show), red where kappa increases and blue
/// where it decreases (sampled sign of lambda), knots as ticks and dashed
/// joint lines, and under the axis a band with each segment's certified class
/// from `analysis` (red increasing, blue decreasing, grey otherwise).
struct CurvaturePlot {
  const BSpline* spline = nullptr;
  const SplineAnalysis* analysis = nullptr;  ///< optional: no band without it
};

/// lambda(t) of one Bezier curve in Bernstein form (CAD&A 2024 Eq. 4): the
/// polynomial, and its coefficients xi_i as dots at t = i / (size - 1) joined
/// by their dashed control polygon (red > 0, blue < 0): the signs Algorithm 1
/// reads.
struct LambdaPlot {
  std::vector<double> xi;
};

/// One cell of a figure: a picture or a plot, and its sub-caption.
struct Panel {
  std::variant<RegionPicture, CurvaturePlot, LambdaPlot> content;
  std::string label;
};

/// One coloured square and its text under a figure.
struct LegendEntry {
  Rgb colour;
  std::string text;
  bool hatched = false;  ///< the square is hatched (per-point colours: decreasing)
  bool ring = false;     ///< a ring, not a square (the marked points)
};

/// A composite figure: title, rows of square panels, legend, caption.
struct Figure {
  std::string title;
  std::vector<std::vector<Panel>> rows;
  std::vector<LegendEntry> legend;
  std::string caption;
  int panel_size = 400;  ///< side of every panel in pixels; region pictures are scaled to it
};

/// The legend of a picture: the colours that are drawn in it, each named,
/// so that the legend matches the picture: the label combinations that occur
/// at some pixel (one region's label, or n increasing and m decreasing
/// regions overlapping), then white; with depth shading the shades of Fig. 7;
/// with per-point colours one entry per point plus filled/hatched; a ring for
/// the one marked point.
std::vector<LegendEntry> legend_for(const RegionPicture& picture);

/// A text's box in device pixels (x, y top left), and what it says.
struct TextBox {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  std::string text;
  bool intersects(const TextBox& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
};

/// The composite figure as SVG (Cairo's SVG surface: vector text and lines,
/// region images embedded as PNG), the same drawing as figure_png.
std::string figure_svg(const Figure& figure);

/// The composite figure as PNG bytes; std::bad_alloc as for region_png.
/// With `labels`, also the boxes of the labels drawn inside each panel
/// (point names, axis and knot values, class tags), panel by panel in row
/// order: what label placement keeps apart.
std::string figure_png(const Figure& figure, std::vector<std::vector<TextBox>>* labels = nullptr);

/// One curve of a line plot.
struct Series {
  std::string name;
  Rgb colour{0, 0, 0};
  std::vector<std::pair<double, double>> points;  ///< (x, y), in order of x
};

/// Lines against a common x axis (e.g. region area against a knot value):
/// axes with the data's ranges (y from 0 when all y >= 0), four ticks each,
/// the axis titles and a legend with one entry per series.
struct LinePlot {
  std::string title, x_label, y_label;
  std::vector<Series> series;
  int width = 720, height = 420;
};

/// Where a line plot's data went: the frame's pixels (left..right,
/// top..bottom) and the data ranges mapped onto them (x0 at left, y0 at
/// bottom), so that a page can mark a point of the plot (the sweep page's
/// current step).
struct PlotArea {
  int width = 0, height = 0;  ///< the picture's size
  double left = 0, right = 0, top = 0, bottom = 0;
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  double px(double x) const { return left + (x - x0) / (x1 - x0) * (right - left); }
  double py(double y) const { return bottom - (y - y0) / (y1 - y0) * (bottom - top); }
};

/// The plot as PNG bytes (and with `area` where its data went); std::bad_alloc
/// as for region_png.
std::string line_plot_png(const LinePlot& plot, PlotArea* area = nullptr);

}  // namespace cmr::draw
