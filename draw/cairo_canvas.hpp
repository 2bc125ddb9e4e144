#pragma once
/// The Cairo side of cmr::draw, shared by its picture modules (draw.cpp, plot.cpp,
/// the weight picture): owning handles, a checked image surface and context, the
/// source colour, and the one encoder of a painted picture into PNG or SVG
/// bytes. Private to draw/ (it includes <cairo.h>, which draw links
/// privately); other modules reach SVG through draw/svg_text.hpp.
#include <cairo.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "draw/draw.hpp"

namespace cmr::draw {

using Surface = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
using Context = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;

/// An ARGB32 image surface; std::bad_alloc when Cairo cannot make it.
Surface make_surface(int width, int height);
/// A context on `surface`; std::bad_alloc when Cairo cannot make it.
Context make_context(cairo_surface_t* surface);
void set_colour(cairo_t* cr, Rgb c);
/// The image surface encoded as PNG bytes, in memory (fails only for lack of
/// memory: std::bad_alloc).
std::string encode_png(cairo_surface_t* surface);

/// The picture `paint` draws on a width x height canvas, as PNG bytes or as
/// an SVG document (Cairo's SVG surface, finished so that the document is
/// complete). Every Cairo picture cmr writes passes through here; SVG written
/// by hand is draw/svg_text.hpp.
enum class PictureFormat : std::uint8_t { png, svg };
std::string render_picture(PictureFormat format, double width, double height,
                           const std::function<void(cairo_t*)>& paint);

}  // namespace cmr::draw
