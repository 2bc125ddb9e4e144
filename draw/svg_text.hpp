#pragma once
/// SVG text written by hand, in one place: the report's curve and curvature
/// plots (report/report_html.cpp), the font page's glyphs (report/font_report.cpp)
/// and region contours (draw/mesh.cpp) open and close their pictures here.
/// Pictures painted with Cairo (figure_svg, the weight picture) become SVG in
/// one other place: render_picture (draw/cairo_canvas.hpp, private to draw).
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "draw/draw.hpp"

namespace cmr::draw {

/// One attribute of an element: name="value" (the value is written as given).
using SvgAttribute = std::pair<std::string_view, std::string>;

/// `<svg xmlns="http://www.w3.org/2000/svg" NAME="VALUE" ...>`, the
/// attributes in the given order.
std::string svg_open(const std::vector<SvgAttribute>& attributes);
/// The closing tag of svg_open.
inline constexpr std::string_view kSvgClose = "</svg>";

/// A colour as SVG writes it: "#rrggbb", each channel rounded to 0..255.
std::string svg_colour(Rgb colour);

}  // namespace cmr::draw
