#pragma once
// Helpers of the region tests: their request; a label map against the exact
// path. A point on a region boundary, for tests that zoom there: the first label
// change along a row of problem p's default view at size x size (rows from
// the middle out, labels of region_cpu), bisected 60 times on exact labels
// (bench_region finds its zoom centres the same way).
#include <cstdint>
#include <optional>
#include <sstream>

#include "region/region.hpp"
#include "region/region_setup.hpp"

namespace cmr::test {

/// The request of the region tests: point `point` moved, D = depth, a
/// size x size image of `view` (nullopt: the default view), with or without
/// a depth map (without: label maps, where block proofs and their reuse run).
inline RegionRequest region_request(int point, int depth, int size, std::optional<View> view, bool depth_map,
                                    Mode mode = Mode::cmrwi) {
  RegionRequest o;
  o.point = point;
  o.max_depth = depth;
  o.width = o.height = size;
  o.view = view;
  o.depth = depth_map;
  o.mode = mode;
  return o;
}

inline std::optional<Vec2> boundary_point(const RegionProblem& p, int size) {
  const backend::RegionSetup& s = p.setup();
  const backend::RegionImage img = backend::region_cpu(s, 1);
  for (int step = 0; step < size; ++step) {
    const int j = size / 2 + (step % 2 ? -(step + 1) / 2 : step / 2);
    for (int i = 1; i < size; ++i) {
      const std::size_t at = static_cast<std::size_t>(j) * size + i;
      if (img.labels[at] == img.labels[at - 1]) continue;
      Vec2 a = pixel_center(p.view(), size, size, i - 1, j), b = pixel_center(p.view(), size, size, i, j);
      const std::uint8_t left = backend::classify_position_exact(s, a).label;
      for (int k = 0; k < 60; ++k) {
        const Vec2 m = 0.5 * (a + b);
        (backend::classify_position_exact(s, m).label == left ? a : b) = m;
      }
      return 0.5 * (a + b);
    }
  }
  return std::nullopt;
}

/// The pixels of a size x size label map `img` (of setup s, no depth map)
/// whose code is not the exact path's at their centre; the first three are
/// described in `first`.
inline int labels_not_exact(const backend::RegionSetup& s, const backend::RegionImage& img, int size,
                            std::ostringstream& first) {
  int wrong = 0;
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) {
      const std::uint8_t exact = backend::classify_position_exact(s, pixel_center(img.view, size, size, i, j)).label;
      const std::size_t at = static_cast<std::size_t>(j) * size + i;
      if (img.labels[at] != exact && wrong++ < 3)
        first << "\n  pixel (" << i << ", " << j << "): code " << int(img.labels[at]) << ", exact code "
              << int(exact);
    }
  return wrong;
}

}  // namespace cmr::test
