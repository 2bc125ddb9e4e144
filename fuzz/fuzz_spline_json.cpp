// The spline file reader: weights, "closed", conventional knots (the first
// byte chooses the knot convention), and the writer's round trip.
#include "fuzz/common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const bool conventional = data[0] & 1;
  if (auto s = cmr::fuzz::spline_from_bytes(data + 1, size - 1, conventional)) {
    // What cmr writes, cmr reads back as the same spline.
    const auto again = cmr::spline_from_json(cmr::spline_to_json(*s));
    if (again.points().size() != s->points().size()) __builtin_trap();
  }
  return 0;
}
