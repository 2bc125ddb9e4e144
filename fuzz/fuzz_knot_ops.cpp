// Knot operations on a spline read from the input: the first byte picks the
// operation, the second a knot or parameter.
#include "bezierize/knot_ops.hpp"
#include "fuzz/common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  auto s = cmr::fuzz::spline_from_bytes(data + 2, size - 2);
  if (!s || !cmr::fuzz::small_enough(*s)) return 0;
  const int pick = data[1];
  try {
    switch (data[0] % 6) {
      case 0: (void)cmr::refine(*s); break;
      case 1: (void)cmr::elevate_degree(*s); break;
      case 2: (void)cmr::make_uniform(*s); break;
      case 3: {
        const auto& k = s->knots();
        (void)cmr::insert_knot(*s, k[pick % k.size()] + (pick & 1 ? 0.5 : 0.0), 1 + (pick >> 6));
        break;
      }
      case 4: (void)cmr::set_knot(*s, pick % static_cast<int>(s->knots().size()), pick / 16.0); break;
      default: (void)cmr::clamp(*s); break;
    }
  } catch (const cmr::InputError&) {
  }
  return 0;
}
