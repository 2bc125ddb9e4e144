// The region classifier (RegionProblem::make, classify) at positions from
// the input, on a spline from the input.
#include <cstring>

#include "region/region.hpp"
#include "fuzz/common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 18) return 0;
  auto s = cmr::fuzz::spline_from_bytes(data + 18, size - 18);
  if (!s || !cmr::fuzz::small_enough(*s)) return 0;
  cmr::RegionRequest rq;
  rq.width = rq.height = 4;
  rq.point = data[0] % s->point_count();
  rq.max_depth = data[1] % 8;
  double x, y;
  std::memcpy(&x, data + 2, 8);
  std::memcpy(&y, data + 10, 8);
  try {
    const cmr::RegionProblem p = cmr::RegionProblem::make(*s, rq);
    (void)p.classify(cmr::Vec2(x, y));
    (void)p.classify(s->points()[rq.point]);
  } catch (const cmr::InputError&) {
  }
  return 0;
}
