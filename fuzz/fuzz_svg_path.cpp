// SVG path data and transform lists on their own (the linear scanners).
#include <cmath>
#include <string>

#include "io/svg.hpp"
#include "spline/errors.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    for (const auto& s : cmr::import::parse_path_data(text, "p"))
      for (const auto& p : s.points)
        if (!std::isfinite(p.x) || !std::isfinite(p.y)) __builtin_trap();  // every coordinate is checked finite
  } catch (const cmr::InputError&) {
  }
  try {
    (void)cmr::import::parse_transform(text);
  } catch (const cmr::InputError&) {
  }
  return 0;
}
