// The SVG document reader: XML, the element walk, transforms and path data.
#include <string>

#include "io/svg.hpp"
#include "spline/errors.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    for (const auto& s : cmr::import::read_svg_text(text, "f.svg", "f")) {
      (void)cmr::import::path_json(s).dump();
      try {
        (void)cmr::import::to_bspline(s);
      } catch (const cmr::InputError&) {
      }
    }
  } catch (const cmr::InputError&) {
  }
  return 0;
}
