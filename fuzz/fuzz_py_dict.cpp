// The Python module's dict input (issue 42 item 5), on the C++ side of the
// binding: python/cmr_module.cpp turns a dict (or list, NumPy array) into the
// spline file's JSON (to_json) and reads it with spline_from_doc:
// spline_dimension, then space_spline_from_json or spline_from_json. Python
// values can hold what JSON text cannot: the numbers 7777, 8888 and 9999 of
// the input become NaN, +inf and -inf (Python's float('nan'), ...), as a dict
// could carry them. Every spline read is written and read back.
#include <cmath>
#include <limits>

#include "fuzz/common.hpp"
#include "spline/space.hpp"

namespace {

void inject_non_finite(nlohmann::json& j) {
  if (j.is_number()) {
    const double v = j.get<double>();
    if (v == 7777) j = std::numeric_limits<double>::quiet_NaN();
    else if (v == 8888) j = std::numeric_limits<double>::infinity();
    else if (v == 9999) j = -std::numeric_limits<double>::infinity();
  } else if (j.is_structured()) {
    for (auto& item : j) inject_non_finite(item);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  nlohmann::json doc = nlohmann::json::parse(data, data + size, nullptr, false);
  if (doc.is_discarded()) return 0;
  inject_non_finite(doc);
  try {
    if (cmr::spline_dimension(doc) == 3) {  // spline_from_doc's choice
      const cmr::SpaceSpline s = cmr::space_spline_from_json(doc);
      const cmr::SpaceSpline again = cmr::space_spline_from_json(cmr::space_spline_to_json(s));
      if (again.points().size() != s.points().size()) __builtin_trap();
    } else {
      const cmr::BSpline s = cmr::spline_from_json(doc);
      const cmr::BSpline again = cmr::spline_from_json(cmr::spline_to_json(s));
      if (again.points().size() != s.points().size()) __builtin_trap();
    }
  } catch (const cmr::InputError&) {
    return 0;  // the module raises ValueError with the reader's line
  }
  return 0;
}
