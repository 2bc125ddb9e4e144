#include "draw/cairo_canvas.hpp"

#include <cairo-svg.h>

#include <cmath>
#include <new>

namespace cmr::draw {

namespace {

/// Appends each chunk Cairo's PNG or SVG writer hands over to a std::string.
cairo_status_t append_chunk(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

}  // namespace

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

std::string encode_png(cairo_surface_t* surface) {
  cairo_surface_flush(surface);
  std::string bytes;
  if (cairo_surface_write_to_png_stream(surface, append_chunk, &bytes) != CAIRO_STATUS_SUCCESS)
    throw std::bad_alloc();
  return bytes;
}

std::string render_picture(PictureFormat format, double width, double height,
                           const std::function<void(cairo_t*)>& paint) {
  if (format == PictureFormat::png) {
    Surface surface = make_surface(static_cast<int>(std::ceil(width)), static_cast<int>(std::ceil(height)));
    {
      Context cr = make_context(surface.get());
      paint(cr.get());
    }
    return encode_png(surface.get());
  }
  std::string bytes;
  Surface surface(cairo_svg_surface_create_for_stream(append_chunk, &bytes, std::ceil(width), std::ceil(height)),
                  &cairo_surface_destroy);
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS) throw std::bad_alloc();
  {
    Context cr = make_context(surface.get());
    paint(cr.get());
  }
  cairo_surface_finish(surface.get());  // the document is complete only once the surface is finished
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS) throw std::bad_alloc();
  return bytes;
}

}  // namespace cmr::draw
