// kcurve on arbitrary points (doubles from the bytes, any scale).
#include <cstring>
#include <vector>

#include "design/kcurve.hpp"
#include "spline/errors.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  cmr::KCurveOptions o;
  o.closed = data[0] & 1;
  o.max_iterations = 200;
  std::vector<cmr::Vec2> points;
  for (std::size_t at = 1; at + 16 <= size && points.size() < 12; at += 16) {
    double x, y;
    std::memcpy(&x, data + at, 8);
    std::memcpy(&y, data + at + 8, 8);
    points.emplace_back(x, y);
  }
  try {
    const cmr::KCurve k = cmr::kcurve(points, o);
    (void)cmr::kcurve_quadratic_spline(k);
    (void)cmr::kcurve_cubic_chain(k);
  } catch (const cmr::InputError&) {
  }
  return 0;
}
