// analyze (Algorithms 1 and 2, joints, shapes) on a spline from the input.
#include "bezierize/analyze.hpp"
#include "fuzz/common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  auto s = cmr::fuzz::spline_from_bytes(data + 1, size - 1);
  if (!s || !cmr::fuzz::small_enough(*s)) return 0;
  cmr::AnalyzeOptions o;
  o.classify.max_depth = data[0] % 8;
  if (data[0] & 0x80 && s->segment_count() > 1) o.split = 1;
  try {
    (void)cmr::analyze(*s, o);
  } catch (const cmr::InputError&) {
  }
  return 0;
}
