// Wavefront OBJ curves (io/obj.hpp): parse_obj_curves on the bytes, the
// entry `cmr import FILE.obj` uses after reading the file. Every curve it
// returns is a space spline whose points are finite (the reader's promise)
// and converts to its JSON.
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "io/obj.hpp"
#include "spline/errors.hpp"
#include "spline/space.hpp"
#include "spline/spline_json.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    for (const cmr::import::ObjCurve& c : cmr::import::parse_obj_curves(text, "f.obj")) {
      for (const cmr::Vec3& p : c.spline.points())
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) __builtin_trap();
      (void)cmr::space_spline_to_json(c.spline).dump();
    }
  } catch (const cmr::InputError&) {
  }
  return 0;
}
