// A variable font's location as --location gives it ("wght=700,opsz=14"):
// parse_location accepts it or refuses it with an InputError, and what it
// accepts is tags of 1-4 characters with finite values.
#include <cmath>
#include <string>

#include "io/font.hpp"
#include "spline/errors.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    for (const auto& [tag, value] : cmr::import::parse_location(text))
      if (tag.empty() || tag.size() > 4 || !std::isfinite(value)) __builtin_trap();
  } catch (const cmr::InputError&) {
  }
  return 0;
}
